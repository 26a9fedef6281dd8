//! The part of an MCAP file whose chunks are sound, checked before the `mcap` crate reads it:
//! that reader loops for ever on a chunk that says it holds more than it does, and does
//! arithmetic on sizes that a damaged chunk can make overflow. Each chunk is decompressed here
//! and held to its stated size and CRC; the file is read up to the first that is not.

use crc::{CRC_32_ISO_HDLC, Crc};

const MAGIC_LEN: usize = 8;
const CHUNK: u8 = 0x06;
const FOOTER: u8 = 0x02;
const DATA_END: u8 = 0x0F;
/// A chunk this armjog would never write (it closes one a second): a damaged size.
const LARGEST_CHUNK: u64 = 1 << 30;

/// How many of `bytes` to read, and why not all (the first damaged chunk, in words).
pub fn sound_prefix(bytes: &[u8]) -> (usize, Option<String>) {
    let mut at = MAGIC_LEN.min(bytes.len());
    while at < bytes.len() {
        let Some((opcode, body)) = record(bytes, at) else {
            // A record cut short: the reader says so itself.
            return (bytes.len(), None);
        };
        if opcode == CHUNK
            && let Err(why) = chunk_sound(body)
        {
            return (at, Some(format!("damaged chunk at byte {at}: {why}")));
        }
        if opcode == DATA_END || opcode == FOOTER {
            break;
        }
        at += 9 + body.len();
    }
    (bytes.len(), None)
}

/// The opcode and body of the record at `at`, if it is whole.
fn record(bytes: &[u8], at: usize) -> Option<(u8, &[u8])> {
    let opcode = *bytes.get(at)?;
    let len = usize::try_from(u64_at(bytes, at + 1)?).ok()?;
    let start = at.checked_add(9)?;
    let body = bytes.get(start..start.checked_add(len)?)?;
    Some((opcode, body))
}

fn u64_at(bytes: &[u8], at: usize) -> Option<u64> {
    let b = bytes.get(at..at.checked_add(8)?)?;
    Some(u64::from_le_bytes(b.try_into().ok()?))
}

fn u32_at(bytes: &[u8], at: usize) -> Option<u32> {
    let b = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes(b.try_into().ok()?))
}

/// A chunk's body: start and end time, uncompressed size and CRC, compression, records.
fn chunk_sound(body: &[u8]) -> Result<(), String> {
    let short = || "cut short".to_string();
    let size = u64_at(body, 16).ok_or_else(short)?;
    let crc = u32_at(body, 24).ok_or_else(short)?;
    let name_len = usize::try_from(u32_at(body, 28).ok_or_else(short)?).map_err(|_| short())?;
    let name = body.get(32..32 + name_len).ok_or_else(short)?;
    let records_at = 32 + name_len;
    let records_len =
        usize::try_from(u64_at(body, records_at).ok_or_else(short)?).map_err(|_| short())?;
    let records = body
        .get(records_at + 8..)
        .filter(|r| r.len() == records_len)
        .ok_or_else(|| "its records' length is not its own".to_string())?;
    if size > LARGEST_CHUNK {
        return Err(format!("it says it holds {size} bytes"));
    }
    let data = match name {
        b"" => records.to_vec(),
        b"zstd" => zstd::bulk::decompress(records, size as usize + 1)
            .map_err(|e| format!("not zstd: {e}"))?,
        other => {
            return Err(format!(
                "compression {:?} not known",
                String::from_utf8_lossy(other)
            ));
        }
    };
    if data.len() as u64 != size {
        return Err(format!(
            "it holds {} bytes, not the {size} it says",
            data.len()
        ));
    }
    if crc != 0 && Crc::<u32>::new(&CRC_32_ISO_HDLC).checksum(&data) != crc {
        return Err("its CRC does not match".into());
    }
    Ok(())
}
