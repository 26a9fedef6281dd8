//! Bounded reads of user-supplied files: a `/dev/zero`, a FIFO or a huge file stops at the limit
//! instead of eating all memory.

use std::io::Read;
use std::path::Path;

/// The largest keymap file read (`--keymap PATH`).
pub const KEYMAP_LIMIT: u64 = 1024 * 1024;
/// The largest positions book read (`--positions PATH`).
pub const POSITIONS_LIMIT: u64 = 16 * 1024 * 1024;

/// Reads a UTF-8 file of at most `limit` bytes. A longer file is refused with
/// `ErrorKind::FileTooLarge` and a message naming the limit; the file's metadata is not trusted
/// (devices and FIFOs report 0), so the read itself stops at `limit + 1` bytes.
pub fn read_to_string_bounded(path: &Path, limit: u64) -> std::io::Result<String> {
    let file = std::fs::File::open(path)?;
    let mut bytes = Vec::new();
    file.take(limit.saturating_add(1)).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(std::io::Error::new(
            std::io::ErrorKind::FileTooLarge,
            format!("larger than the limit of {}", describe_size(limit)),
        ));
    }
    String::from_utf8(bytes).map_err(|e| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!(
                "not UTF-8 text (invalid byte at offset {})",
                e.utf8_error().valid_up_to()
            ),
        )
    })
}

/// "1 MB (1048576 bytes)": the limit as people and `ls -l` read it.
fn describe_size(bytes: u64) -> String {
    const MB: u64 = 1024 * 1024;
    if bytes.is_multiple_of(MB) {
        format!("{} MB ({bytes} bytes)", bytes / MB)
    } else {
        format!("{bytes} bytes")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_file(contents: &[u8]) -> tempfile::NamedTempFile {
        let mut file = tempfile::NamedTempFile::new().unwrap();
        std::io::Write::write_all(&mut file, contents).unwrap();
        file
    }

    #[test]
    fn a_file_at_the_limit_is_read_and_one_byte_more_is_refused() {
        let file = temp_file(&[b'x'; 10]);
        let path = file.path();
        assert_eq!(read_to_string_bounded(path, 10).unwrap().len(), 10);
        let err = read_to_string_bounded(path, 9).unwrap_err();
        assert_eq!(err.kind(), std::io::ErrorKind::FileTooLarge);
        assert!(err.to_string().contains("9 bytes"), "{err}");
    }

    #[cfg(unix)]
    #[test]
    fn dev_zero_stops_at_the_limit() {
        let err = read_to_string_bounded(Path::new("/dev/zero"), KEYMAP_LIMIT).unwrap_err();
        assert!(err.to_string().contains("1 MB"), "{err}");
    }

    #[test]
    fn invalid_utf8_is_refused() {
        let file = temp_file(&[b'a', 0xff]);
        let path = file.path();
        let err = read_to_string_bounded(path, 10).unwrap_err();
        assert_eq!(err.kind(), std::io::ErrorKind::InvalidData);
    }
}
