//! An MCAP reader written for the tests from the specification alone (mcap.dev/spec): it shares
//! no code with the `mcap` crate that writes the recordings, so a mistake of the writer's is not
//! read back the same way. It reads the whole file and checks what the spec lets a reader check:
//! the magic at both ends, the Header first and the Footer last, every record's length, each
//! Chunk's sizes and CRC, the Data End's CRC of the data section, the Footer's CRC of the
//! summary, each Message Index against the messages of its chunk, and (`summary.rs`) the
//! summary's Schema and Channel copies, Chunk Indexes, Statistics and Summary Offsets against
//! what the data section holds.

mod records;
mod summary;
#[cfg(test)]
mod tests;

use std::collections::BTreeMap;

pub use records::{Channel, Message, Schema, Statistics};
use records::{Cursor, MAGIC, Read, Record};

/// The CRC32 the spec names (zlib's: reflected polynomial 0xEDB88320), from armjog's own `crc`
/// crate, not the `crc32fast` the writer uses.
const CRC32: crc::Crc<u32> = crc::Crc::<u32>::new(&crc::CRC_32_ISO_HDLC);

/// A Footer record is always 9 + 20 bytes: opcode, length, two offsets and a CRC.
const FOOTER_RECORD: usize = 29;

/// A whole file, read and checked.
pub struct Recording {
    pub profile: String,
    pub library: String,
    /// The data section's Schemas and Channels by id.
    pub schemas: BTreeMap<u16, Schema>,
    pub channels: BTreeMap<u16, Channel>,
    /// Every message, in file order.
    pub messages: Vec<Message>,
    pub chunks: Vec<ChunkSeen>,
    /// Messages outside any chunk.
    pub loose_messages: usize,
    /// Records read past, by opcode: attachments, metadata, private records.
    pub skipped: BTreeMap<u8, u64>,
    /// The Data End's CRC of the data section (zero: the writer gave none); `None` without a
    /// Data End (the spec's simplest diagrams have none).
    pub data_section_crc: Option<u32>,
    pub summary_crc: u32,
    pub summary: Option<summary::Summary>,
}

/// A Chunk as found in the data section, with the Message Indexes that follow it.
pub struct ChunkSeen {
    /// Where its record starts in the file, and its whole length.
    pub offset: u64,
    pub length: u64,
    pub message_start_time: u64,
    pub message_end_time: u64,
    pub compression: String,
    pub compressed_size: u64,
    pub uncompressed_size: u64,
    /// Its messages: channel, log time, offset in the uncompressed records.
    pub messages: Vec<(u16, u64, u64)>,
    /// The Message Index records after it: channel → (offset in the file, entries).
    pub indexes: BTreeMap<u16, (u64, Vec<(u64, u64)>)>,
    /// Their total length.
    pub indexes_length: u64,
}

impl Recording {
    /// The schema of the channel a message is on.
    pub fn schema_of(&self, message: &Message) -> Option<(&Channel, &Schema)> {
        let channel = self.channels.get(&message.channel_id)?;
        Some((channel, self.schemas.get(&channel.schema_id)?))
    }
}

/// Reads and checks a whole MCAP file.
pub fn read(bytes: &[u8]) -> Read<Recording> {
    if bytes.len() < 2 * MAGIC.len() + FOOTER_RECORD {
        return Err(format!("{} bytes: too short for an MCAP file", bytes.len()));
    }
    if !bytes.starts_with(&MAGIC) || !bytes.ends_with(&MAGIC) {
        return Err("no MCAP magic at the start or the end".into());
    }
    let footer_at = bytes.len() - MAGIC.len() - FOOTER_RECORD;
    let footer = records::records(bytes, footer_at, bytes.len() - MAGIC.len())?;
    let content = match footer.as_slice() {
        [record] if record.opcode == records::FOOTER => record.content,
        _ => return Err("the last record is not a Footer".into()),
    };
    let mut c = Cursor::new(content, "Footer");
    let (summary_start, summary_offset_start, summary_crc) = (c.u64()?, c.u64()?, c.u32()?);
    c.done()?;
    let at = |offset: u64, what: &str| {
        usize::try_from(offset)
            .ok()
            .filter(|o| (MAGIC.len()..=footer_at).contains(o))
            .ok_or_else(|| format!("{what} {offset} is outside the file"))
    };
    let data_limit = match summary_start {
        0 => footer_at,
        start => at(start, "summary_start")?,
    };
    let mut recording = data_section(bytes, data_limit)?;
    recording.summary_crc = summary_crc;
    if summary_start != 0 {
        let offsets_at = match summary_offset_start {
            0 => footer_at,
            start => at(start, "summary_offset_start")?,
        };
        if offsets_at < data_limit {
            return Err("the summary offsets start before the summary".into());
        }
        if summary_crc != 0 {
            // From the summary's start through the Footer's summary_offset_start.
            let crc = CRC32.checksum(&bytes[data_limit..footer_at + 9 + 16]);
            if crc != summary_crc {
                return Err(format!(
                    "summary CRC {crc:08x}, the Footer says {summary_crc:08x}"
                ));
            }
        }
        let summary = summary::read(bytes, data_limit, offsets_at, footer_at)?;
        summary::check(&recording, &summary)?;
        recording.summary = Some(summary);
    }
    Ok(recording)
}

/// From the Header to the Data End, which when there must be the last record before `limit`.
fn data_section(bytes: &[u8], limit: usize) -> Read<Recording> {
    let all = records::records(bytes, MAGIC.len(), limit)?;
    let Some((first, rest)) = all.split_first() else {
        return Err("no Header".into());
    };
    if first.opcode != records::HEADER {
        return Err(format!(
            "the first record is 0x{:02x}, not a Header",
            first.opcode
        ));
    }
    let mut c = Cursor::new(first.content, "Header");
    let mut recording = Recording {
        profile: c.string()?,
        library: c.string()?,
        schemas: BTreeMap::new(),
        channels: BTreeMap::new(),
        messages: Vec::new(),
        chunks: Vec::new(),
        loose_messages: 0,
        skipped: BTreeMap::new(),
        data_section_crc: None,
        summary_crc: 0,
        summary: None,
    };
    let (data_end, between) = match rest.split_last() {
        Some((last, between)) if last.opcode == records::DATA_END => (Some(last), between),
        _ => (None, rest),
    };
    // Message Indexes may follow only a Chunk or another Message Index.
    let mut indexable = false;
    for record in between {
        let follows_chunk = indexable;
        indexable = false;
        match record.opcode {
            records::SCHEMA | records::CHANNEL => definition(&mut recording, record)?,
            records::MESSAGE => {
                let message = records::message(record.content)?;
                known_channel(&recording, &message)?;
                recording.messages.push(message);
                recording.loose_messages += 1;
            }
            records::CHUNK => {
                chunk(&mut recording, record)?;
                indexable = true;
            }
            records::MESSAGE_INDEX if follows_chunk => {
                let (channel, entries) = records::message_index(record.content)?;
                let chunk = recording.chunks.last_mut().expect("after a chunk");
                let offset = record.offset as u64;
                if chunk.indexes.insert(channel, (offset, entries)).is_some() {
                    return Err(format!(
                        "two Message Indexes for channel {channel} at {offset}"
                    ));
                }
                chunk.indexes_length += record.length as u64;
                indexable = true;
            }
            // Attachments, metadata and private records: nothing the tests look at.
            op @ (0x09 | 0x0C | 0x80..=0xFF) => *recording.skipped.entry(op).or_default() += 1,
            op => {
                return Err(format!(
                    "record 0x{op:02x} at {} in the data section",
                    record.offset
                ));
            }
        }
    }
    if let Some(data_end) = data_end {
        let mut c = Cursor::new(data_end.content, "Data End");
        let said = c.u32()?;
        c.done()?;
        // Every byte from the file's start up to the Data End record.
        let crc = CRC32.checksum(&bytes[..data_end.offset]);
        if said != 0 && crc != said {
            return Err(format!(
                "data section CRC {crc:08x}, the Data End says {said:08x}"
            ));
        }
        recording.data_section_crc = Some(said);
    }
    for chunk in &recording.chunks {
        indexes_match(chunk)?;
    }
    Ok(recording)
}

/// A Schema or Channel, in the data section or a chunk: ids known before use, repeats identical.
fn definition(recording: &mut Recording, record: &Record<'_>) -> Read<()> {
    if record.opcode == records::SCHEMA {
        let schema = records::schema(record.content)?;
        if schema.id == 0 {
            return Err("a Schema with id 0".into());
        }
        match recording.schemas.get(&schema.id) {
            Some(known) if *known != schema => Err(format!("schema {} redefined", schema.id)),
            _ => {
                recording.schemas.insert(schema.id, schema);
                Ok(())
            }
        }
    } else {
        let channel = records::channel(record.content)?;
        if channel.schema_id != 0 && !recording.schemas.contains_key(&channel.schema_id) {
            let (id, schema) = (channel.id, channel.schema_id);
            return Err(format!("channel {id} before its schema {schema}"));
        }
        match recording.channels.get(&channel.id) {
            Some(known) if *known != channel => Err(format!("channel {} redefined", channel.id)),
            _ => {
                recording.channels.insert(channel.id, channel);
                Ok(())
            }
        }
    }
}

fn known_channel(recording: &Recording, message: &Message) -> Read<()> {
    if recording.channels.contains_key(&message.channel_id) {
        Ok(())
    } else {
        Err(format!(
            "a message on channel {} before it",
            message.channel_id
        ))
    }
}

/// A Chunk: decompressed, its size and CRC checked, its records read.
fn chunk(recording: &mut Recording, record: &Record<'_>) -> Read<()> {
    let chunk = records::chunk(record.content)?;
    let data = match chunk.compression.as_str() {
        "" => chunk.records.to_vec(),
        "zstd" => zstd::stream::decode_all(chunk.records)
            .map_err(|e| format!("chunk at {}: zstd: {e}", record.offset))?,
        other => {
            return Err(format!(
                "chunk compression {other:?}: not one this reader knows"
            ));
        }
    };
    if data.len() as u64 != chunk.uncompressed_size {
        let (size, said) = (data.len(), chunk.uncompressed_size);
        return Err(format!(
            "chunk at {}: {size} bytes, it says {said}",
            record.offset
        ));
    }
    if chunk.uncompressed_crc != 0 && CRC32.checksum(&data) != chunk.uncompressed_crc {
        return Err(format!("chunk at {}: CRC mismatch", record.offset));
    }
    let mut seen = ChunkSeen {
        offset: record.offset as u64,
        length: record.length as u64,
        message_start_time: chunk.message_start_time,
        message_end_time: chunk.message_end_time,
        compression: chunk.compression.clone(),
        compressed_size: chunk.records.len() as u64,
        uncompressed_size: chunk.uncompressed_size,
        messages: Vec::new(),
        indexes: BTreeMap::new(),
        indexes_length: 0,
    };
    for inner in records::records(&data, 0, data.len())? {
        match inner.opcode {
            records::SCHEMA | records::CHANNEL => definition(recording, &inner)?,
            records::MESSAGE => {
                let message = records::message(inner.content)?;
                known_channel(recording, &message)?;
                let at = inner.offset as u64;
                seen.messages
                    .push((message.channel_id, message.log_time, at));
                recording.messages.push(message);
            }
            op => {
                return Err(format!(
                    "record 0x{op:02x} inside the chunk at {}",
                    seen.offset
                ));
            }
        }
    }
    // Its earliest and latest log times; zero without messages.
    let times = seen.messages.iter().map(|m| m.1);
    let span = (times.clone().min().unwrap_or(0), times.max().unwrap_or(0));
    if span != (chunk.message_start_time, chunk.message_end_time) {
        let (offset, start, end) = (
            seen.offset,
            chunk.message_start_time,
            chunk.message_end_time,
        );
        return Err(format!(
            "chunk at {offset}: says {start}..{end}, its messages {span:?}"
        ));
    }
    recording.chunks.push(seen);
    Ok(())
}

/// A chunk's Message Indexes list exactly its messages: one index per channel in it, each
/// message's log time and offset.
fn indexes_match(chunk: &ChunkSeen) -> Read<()> {
    let mut wanted: BTreeMap<u16, Vec<(u64, u64)>> = BTreeMap::new();
    for &(channel, time, offset) in &chunk.messages {
        wanted.entry(channel).or_default().push((time, offset));
    }
    let mut indexed: BTreeMap<u16, Vec<(u64, u64)>> = BTreeMap::new();
    for (channel, (_, entries)) in &chunk.indexes {
        let mut entries = entries.clone();
        entries.sort_unstable();
        indexed.insert(*channel, entries);
    }
    for entries in wanted.values_mut() {
        entries.sort_unstable();
    }
    if wanted != indexed {
        return Err(format!(
            "chunk at {}: its Message Indexes are not its messages",
            chunk.offset
        ));
    }
    Ok(())
}
