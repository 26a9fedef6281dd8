//! The summary section (mcap.dev/spec, "Summary Section", "Summary Offset Section"): its
//! records grouped by opcode, each group found by its Summary Offset, and what they say checked
//! against the data section: the Schema and Channel copies, one Chunk Index per Chunk pointing at
//! it and its Message Indexes, and the Statistics' counts and times.

use std::collections::BTreeMap;

use super::records::{self, ChunkIndex, Read, Record};
use super::{Channel, Schema, Statistics};
use super::{ChunkSeen, Recording};

/// The summary section, read.
pub struct Summary {
    pub schemas: BTreeMap<u16, Schema>,
    pub channels: BTreeMap<u16, Channel>,
    pub chunk_indexes: Vec<ChunkIndex>,
    pub statistics: Option<Statistics>,
    /// Each group of same-opcode records: opcode, start, length.
    pub groups: Vec<(u8, u64, u64)>,
}

/// The summary in `bytes[start..offsets_at]`, its Summary Offsets in `bytes[offsets_at..end]`.
pub fn read(bytes: &[u8], start: usize, offsets_at: usize, end: usize) -> Read<Summary> {
    let mut summary = Summary {
        schemas: BTreeMap::new(),
        channels: BTreeMap::new(),
        chunk_indexes: Vec::new(),
        statistics: None,
        groups: Vec::new(),
    };
    for record in records::records(bytes, start, offsets_at)? {
        group(&mut summary.groups, &record)?;
        match record.opcode {
            records::SCHEMA => {
                let schema = records::schema(record.content)?;
                summary.schemas.insert(schema.id, schema);
            }
            records::CHANNEL => {
                let channel = records::channel(record.content)?;
                summary.channels.insert(channel.id, channel);
            }
            records::CHUNK_INDEX => summary
                .chunk_indexes
                .push(records::chunk_index(record.content)?),
            records::STATISTICS if summary.statistics.is_none() => {
                summary.statistics = Some(records::statistics(record.content)?);
            }
            records::STATISTICS => return Err("two Statistics records".into()),
            // Attachment and Metadata Indexes: this recorder writes none.
            0x0A | 0x0D => {}
            op => return Err(format!("record 0x{op:02x} in the summary section")),
        }
    }
    let mut offsets = Vec::new();
    for record in records::records(bytes, offsets_at, end)? {
        if record.opcode != records::SUMMARY_OFFSET {
            let op = record.opcode;
            return Err(format!("record 0x{op:02x} in the summary offset section"));
        }
        offsets.push(records::summary_offset(record.content)?);
    }
    // Optional; when there, one for each group, at it.
    if !offsets.is_empty() {
        offsets.sort_unstable();
        let mut groups = summary.groups.clone();
        groups.sort_unstable();
        if offsets != groups {
            return Err(format!("Summary Offsets {offsets:?}, groups {groups:?}"));
        }
    }
    Ok(summary)
}

/// Summary records must be grouped by opcode: a record extends the last group or starts a new
/// one of an opcode not seen before.
fn group(groups: &mut Vec<(u8, u64, u64)>, record: &Record<'_>) -> Read<()> {
    let (offset, length) = (record.offset as u64, record.length as u64);
    if let Some((op, start, len)) = groups.last_mut()
        && *op == record.opcode
        && *start + *len == offset
    {
        *len += length;
    } else if groups.iter().any(|g| g.0 == record.opcode) {
        return Err(format!(
            "summary record 0x{:02x} out of its group",
            record.opcode
        ));
    } else {
        groups.push((record.opcode, offset, length));
    }
    Ok(())
}

/// What the summary says against what the data section holds.
pub fn check(recording: &Recording, summary: &Summary) -> Read<()> {
    for (id, schema) in &summary.schemas {
        if recording.schemas.get(id) != Some(schema) {
            return Err(format!(
                "the summary's schema {id} is not the data section's"
            ));
        }
    }
    for (id, channel) in &summary.channels {
        if recording.channels.get(id) != Some(channel) {
            return Err(format!(
                "the summary's channel {id} is not the data section's"
            ));
        }
    }
    if !summary.chunk_indexes.is_empty() {
        chunk_indexes(recording, summary)?;
    }
    if let Some(statistics) = &summary.statistics {
        counts(recording, summary, statistics)?;
    }
    Ok(())
}

/// One Chunk Index per Chunk, at it, saying what it is; every channel and schema in the summary.
fn chunk_indexes(recording: &Recording, summary: &Summary) -> Read<()> {
    if recording.loose_messages > 0 {
        return Err("an indexed file with messages outside chunks".into());
    }
    if summary.chunk_indexes.len() != recording.chunks.len() {
        let (indexes, chunks) = (summary.chunk_indexes.len(), recording.chunks.len());
        return Err(format!("{indexes} Chunk Indexes for {chunks} Chunks"));
    }
    for index in &summary.chunk_indexes {
        let offset = index.chunk_start_offset;
        let chunk = recording
            .chunks
            .iter()
            .find(|c| c.offset == offset)
            .ok_or_else(|| format!("a Chunk Index points at {offset}, where no Chunk starts"))?;
        if !same_chunk(index, chunk) {
            return Err(format!(
                "the Chunk Index of the chunk at {offset} differs from it"
            ));
        }
    }
    for message in &recording.messages {
        let channel = summary.channels.get(&message.channel_id);
        let schema = channel.and_then(|c| summary.schemas.get(&c.schema_id));
        if schema.is_none() {
            let id = message.channel_id;
            return Err(format!("channel {id} or its schema is not in the summary"));
        }
    }
    Ok(())
}

fn same_chunk(index: &ChunkIndex, chunk: &ChunkSeen) -> bool {
    let index_offsets: BTreeMap<u16, u64> = chunk
        .indexes
        .iter()
        .map(|(channel, (offset, _))| (*channel, *offset))
        .collect();
    index.chunk_length == chunk.length
        && index.message_start_time == chunk.message_start_time
        && index.message_end_time == chunk.message_end_time
        && index.compression == chunk.compression
        && index.compressed_size == chunk.compressed_size
        && index.uncompressed_size == chunk.uncompressed_size
        && index.message_index_offsets == index_offsets
        && index.message_index_length == chunk.indexes_length
}

/// The Statistics' counts and times are the file's.
fn counts(recording: &Recording, summary: &Summary, statistics: &Statistics) -> Read<()> {
    let messages = &recording.messages;
    let mut per_channel: BTreeMap<u16, u64> = BTreeMap::new();
    for message in messages {
        *per_channel.entry(message.channel_id).or_default() += 1;
    }
    let times = messages.iter().map(|m| m.log_time);
    let span = (times.clone().min().unwrap_or(0), times.max().unwrap_or(0));
    let skipped = |op| recording.skipped.get(&op).copied().unwrap_or(0);
    let found = [
        (
            "message_count",
            statistics.message_count,
            messages.len() as u64,
        ),
        (
            "schema_count",
            u64::from(statistics.schema_count),
            recording.schemas.len() as u64,
        ),
        (
            "channel_count",
            u64::from(statistics.channel_count),
            recording.channels.len() as u64,
        ),
        (
            "chunk_count",
            u64::from(statistics.chunk_count),
            recording.chunks.len() as u64,
        ),
        (
            "attachment_count",
            u64::from(statistics.attachment_count),
            skipped(0x09),
        ),
        (
            "metadata_count",
            u64::from(statistics.metadata_count),
            skipped(0x0C),
        ),
        ("message_start_time", statistics.message_start_time, span.0),
        ("message_end_time", statistics.message_end_time, span.1),
    ];
    for (what, said, counted) in found {
        if said != counted {
            return Err(format!("Statistics {what} {said}, the file has {counted}"));
        }
    }
    // Channels without messages may be listed with 0, or left out.
    let listed: BTreeMap<u16, u64> = (statistics.channel_message_counts.iter())
        .filter(|(_, n)| **n > 0)
        .map(|(id, n)| (*id, *n))
        .collect();
    if !statistics.channel_message_counts.is_empty() {
        if listed != per_channel {
            return Err(format!(
                "Statistics per channel {listed:?}, the file {per_channel:?}"
            ));
        }
        // Per-channel counts need every Channel in the summary.
        if let Some(id) = listed.keys().find(|id| !summary.channels.contains_key(id)) {
            return Err(format!("channel {id} counted but not in the summary"));
        }
    }
    Ok(())
}
