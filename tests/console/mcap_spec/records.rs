//! MCAP's serialization and records, written from the specification (mcap.dev/spec, "Records"
//! and "Serialization"): little-endian integers, `uint32`-prefixed strings, byte arrays and maps,
//! every record `<opcode u8><content length u64><content>`.

use std::collections::BTreeMap;

/// What went wrong, and where.
pub type Read<T> = Result<T, String>;

pub const MAGIC: [u8; 8] = [0x89, b'M', b'C', b'A', b'P', b'0', b'\r', b'\n'];

pub const HEADER: u8 = 0x01;
pub const FOOTER: u8 = 0x02;
pub const SCHEMA: u8 = 0x03;
pub const CHANNEL: u8 = 0x04;
pub const MESSAGE: u8 = 0x05;
pub const CHUNK: u8 = 0x06;
pub const MESSAGE_INDEX: u8 = 0x07;
pub const CHUNK_INDEX: u8 = 0x08;
pub const STATISTICS: u8 = 0x0B;
pub const SUMMARY_OFFSET: u8 = 0x0E;
pub const DATA_END: u8 = 0x0F;

/// Reads fields off the front of a record's content; every read is bounds-checked.
pub struct Cursor<'a> {
    bytes: &'a [u8],
    what: &'static str,
}

impl<'a> Cursor<'a> {
    pub fn new(bytes: &'a [u8], what: &'static str) -> Cursor<'a> {
        Cursor { bytes, what }
    }

    pub fn take(&mut self, n: usize) -> Read<&'a [u8]> {
        if n > self.bytes.len() {
            return Err(format!(
                "{}: {n} bytes wanted, {} left",
                self.what,
                self.bytes.len()
            ));
        }
        let (taken, rest) = self.bytes.split_at(n);
        self.bytes = rest;
        Ok(taken)
    }

    fn array<const N: usize>(&mut self) -> Read<[u8; N]> {
        let bytes = self.take(N)?;
        Ok(bytes.try_into().expect("N bytes taken"))
    }

    pub fn u8(&mut self) -> Read<u8> {
        Ok(self.array::<1>()?[0])
    }
    pub fn u16(&mut self) -> Read<u16> {
        Ok(u16::from_le_bytes(self.array()?))
    }
    pub fn u32(&mut self) -> Read<u32> {
        Ok(u32::from_le_bytes(self.array()?))
    }
    pub fn u64(&mut self) -> Read<u64> {
        Ok(u64::from_le_bytes(self.array()?))
    }

    /// A byte count that must fit this machine's `usize`.
    fn len(&mut self, prefix: u64) -> Read<usize> {
        usize::try_from(prefix).map_err(|_| format!("{}: length {prefix} too large", self.what))
    }

    /// `uint32` length-prefixed bytes.
    pub fn bytes_u32(&mut self) -> Read<&'a [u8]> {
        let n = self.u32()?;
        let n = self.len(u64::from(n))?;
        self.take(n)
    }

    /// `uint64` length-prefixed bytes.
    pub fn bytes_u64(&mut self) -> Read<&'a [u8]> {
        let n = self.u64()?;
        let n = self.len(n)?;
        self.take(n)
    }

    /// A String: `uint32` byte length, then UTF-8.
    pub fn string(&mut self) -> Read<String> {
        let what = self.what;
        let bytes = self.bytes_u32()?;
        String::from_utf8(bytes.to_vec()).map_err(|e| format!("{what}: a string not UTF-8: {e}"))
    }

    /// `Map<string, string>`: a `uint32` byte length, then keys and values.
    pub fn string_map(&mut self) -> Read<BTreeMap<String, String>> {
        let mut entries = Cursor::new(self.bytes_u32()?, self.what);
        let mut map = BTreeMap::new();
        while !entries.is_empty() {
            let key = entries.string()?;
            let value = entries.string()?;
            if map.insert(key.clone(), value).is_some() {
                return Err(format!("{}: key {key:?} twice in a map", self.what));
            }
        }
        Ok(map)
    }

    /// `Map<uint16, uint64>`.
    pub fn id_map(&mut self) -> Read<BTreeMap<u16, u64>> {
        let mut entries = Cursor::new(self.bytes_u32()?, self.what);
        let mut map = BTreeMap::new();
        while !entries.is_empty() {
            let key = entries.u16()?;
            let value = entries.u64()?;
            if map.insert(key, value).is_some() {
                return Err(format!("{}: key {key} twice in a map", self.what));
            }
        }
        Ok(map)
    }

    /// `Array<Tuple<Timestamp, uint64>>`.
    pub fn time_offsets(&mut self) -> Read<Vec<(u64, u64)>> {
        let mut entries = Cursor::new(self.bytes_u32()?, self.what);
        let mut pairs = Vec::new();
        while !entries.is_empty() {
            pairs.push((entries.u64()?, entries.u64()?));
        }
        Ok(pairs)
    }

    pub fn is_empty(&self) -> bool {
        self.bytes.is_empty()
    }

    /// What is left: a Message's data.
    pub fn rest(&mut self) -> &'a [u8] {
        std::mem::take(&mut self.bytes)
    }

    /// For the records the spec says will never be extended (Message, Data End, Footer).
    pub fn done(&self) -> Read<()> {
        if self.bytes.is_empty() {
            Ok(())
        } else {
            Err(format!(
                "{}: {} bytes past its end",
                self.what,
                self.bytes.len()
            ))
        }
    }
}

/// One record: where it starts in its buffer, its opcode, its content, and its whole length
/// (opcode and length prefix included).
pub struct Record<'a> {
    pub offset: usize,
    pub opcode: u8,
    pub content: &'a [u8],
    pub length: usize,
}

/// The records of `bytes[start..end]`, in order; it must end on a record's end.
pub fn records(bytes: &[u8], start: usize, end: usize) -> Read<Vec<Record<'_>>> {
    let mut out = Vec::new();
    let mut at = start;
    while at < end {
        let mut head = Cursor::new(&bytes[at..end], "a record's opcode and length");
        let opcode = head.u8()?;
        let length = head.u64()?;
        if opcode == 0 {
            return Err(format!("opcode 0 at {at}: not a valid opcode"));
        }
        let length = usize::try_from(length)
            .ok()
            .filter(|n| *n <= end - at - 9)
            .ok_or_else(|| format!("record 0x{opcode:02x} at {at}: length {length} overruns"))?;
        out.push(Record {
            offset: at,
            opcode,
            content: &bytes[at + 9..at + 9 + length],
            length: 9 + length,
        });
        at += 9 + length;
    }
    Ok(out)
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Schema {
    pub id: u16,
    pub name: String,
    pub encoding: String,
    pub data: Vec<u8>,
}

pub fn schema(content: &[u8]) -> Read<Schema> {
    let mut c = Cursor::new(content, "Schema");
    Ok(Schema {
        id: c.u16()?,
        name: c.string()?,
        encoding: c.string()?,
        data: c.bytes_u32()?.to_vec(),
    })
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Channel {
    pub id: u16,
    pub schema_id: u16,
    pub topic: String,
    pub message_encoding: String,
    pub metadata: BTreeMap<String, String>,
}

pub fn channel(content: &[u8]) -> Read<Channel> {
    let mut c = Cursor::new(content, "Channel");
    Ok(Channel {
        id: c.u16()?,
        schema_id: c.u16()?,
        topic: c.string()?,
        message_encoding: c.string()?,
        metadata: c.string_map()?,
    })
}

#[derive(Debug, Clone)]
pub struct Message {
    pub channel_id: u16,
    pub sequence: u32,
    pub log_time: u64,
    pub publish_time: u64,
    pub data: Vec<u8>,
}

pub fn message(content: &[u8]) -> Read<Message> {
    let mut c = Cursor::new(content, "Message");
    Ok(Message {
        channel_id: c.u16()?,
        sequence: c.u32()?,
        log_time: c.u64()?,
        publish_time: c.u64()?,
        data: c.rest().to_vec(),
    })
}

/// A Chunk's fields; `records` still compressed.
pub struct Chunk<'a> {
    pub message_start_time: u64,
    pub message_end_time: u64,
    pub uncompressed_size: u64,
    pub uncompressed_crc: u32,
    pub compression: String,
    pub records: &'a [u8],
}

pub fn chunk(content: &[u8]) -> Read<Chunk<'_>> {
    let mut c = Cursor::new(content, "Chunk");
    Ok(Chunk {
        message_start_time: c.u64()?,
        message_end_time: c.u64()?,
        uncompressed_size: c.u64()?,
        uncompressed_crc: c.u32()?,
        compression: c.string()?,
        records: c.bytes_u64()?,
    })
}

/// A Message Index: a channel, and each message's log time and offset in the chunk's records.
pub fn message_index(content: &[u8]) -> Read<(u16, Vec<(u64, u64)>)> {
    let mut c = Cursor::new(content, "Message Index");
    Ok((c.u16()?, c.time_offsets()?))
}

#[derive(Debug, Clone)]
pub struct ChunkIndex {
    pub message_start_time: u64,
    pub message_end_time: u64,
    pub chunk_start_offset: u64,
    pub chunk_length: u64,
    pub message_index_offsets: BTreeMap<u16, u64>,
    pub message_index_length: u64,
    pub compression: String,
    pub compressed_size: u64,
    pub uncompressed_size: u64,
}

pub fn chunk_index(content: &[u8]) -> Read<ChunkIndex> {
    let mut c = Cursor::new(content, "Chunk Index");
    Ok(ChunkIndex {
        message_start_time: c.u64()?,
        message_end_time: c.u64()?,
        chunk_start_offset: c.u64()?,
        chunk_length: c.u64()?,
        message_index_offsets: c.id_map()?,
        message_index_length: c.u64()?,
        compression: c.string()?,
        compressed_size: c.u64()?,
        uncompressed_size: c.u64()?,
    })
}

#[derive(Debug, Clone)]
pub struct Statistics {
    pub message_count: u64,
    pub schema_count: u16,
    pub channel_count: u32,
    pub attachment_count: u32,
    pub metadata_count: u32,
    pub chunk_count: u32,
    pub message_start_time: u64,
    pub message_end_time: u64,
    pub channel_message_counts: BTreeMap<u16, u64>,
}

pub fn statistics(content: &[u8]) -> Read<Statistics> {
    let mut c = Cursor::new(content, "Statistics");
    Ok(Statistics {
        message_count: c.u64()?,
        schema_count: c.u16()?,
        channel_count: c.u32()?,
        attachment_count: c.u32()?,
        metadata_count: c.u32()?,
        chunk_count: c.u32()?,
        message_start_time: c.u64()?,
        message_end_time: c.u64()?,
        channel_message_counts: c.id_map()?,
    })
}

/// A Summary Offset: the opcode of a group of summary records, its start and its length.
pub fn summary_offset(content: &[u8]) -> Read<(u8, u64, u64)> {
    let mut c = Cursor::new(content, "Summary Offset");
    Ok((c.u8()?, c.u64()?, c.u64()?))
}
