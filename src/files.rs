//! Bounded reads of user-supplied files (config, keymap, book): only a regular file is read, so a
//! FIFO or device is refused at once instead of blocking the start or eating memory, and a huge
//! file stops at the limit. Also what a write that replaces a file by a rename needs (`temp_beside`,
//! `sync_directory`), shared by the book and the profile's fence.

use std::fs::{File, FileType, OpenOptions};
use std::io::Read;
use std::path::Path;

/// The largest keymap file read (`--keymap PATH`).
pub const KEYMAP_LIMIT: u64 = 1024 * 1024;
/// The largest positions book read (`--positions PATH`).
pub const POSITIONS_LIMIT: u64 = 16 * 1024 * 1024;

/// Reads a UTF-8 regular file of at most `limit` bytes. Anything else is refused without blocking
/// (`ErrorKind::InvalidInput`, naming what it is; [`open_regular`]); a longer file with
/// `ErrorKind::FileTooLarge`. The size is not trusted (a file may grow): the read stops at `limit +
/// 1` bytes.
pub fn read_to_string_bounded(path: &Path, limit: u64) -> std::io::Result<String> {
    let bytes = read_bytes_bounded(path, limit)?;
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

/// Opens `path` for reading if it is a regular file, without blocking: its kind is checked before
/// the open (opening a device may do something) and on the file opened non-blocking, so a path
/// swapped for a FIFO in between cannot hold the open up either.
pub fn open_regular(path: &Path) -> std::io::Result<File> {
    not_regular(std::fs::metadata(path)?.file_type())?;
    let mut options = OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        // The flag's bits fit an i32 (open(2)'s flags argument is one).
        options.custom_flags(rustix::fs::OFlags::NONBLOCK.bits() as i32);
    }
    let file = options.open(path)?;
    not_regular(file.metadata()?.file_type())?;
    // O_NONBLOCK changes nothing for a regular file's reads.
    Ok(file)
}

/// Refuses every kind of file but a regular one, naming what it is.
fn not_regular(kind: FileType) -> std::io::Result<()> {
    if kind.is_file() {
        return Ok(());
    }
    let what = if kind.is_dir() {
        "a directory"
    } else {
        special_kind(kind)
    };
    Err(std::io::Error::new(
        std::io::ErrorKind::InvalidInput,
        format!("not a regular file ({what}); only a regular file is read"),
    ))
}

#[cfg(unix)]
fn special_kind(kind: FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if kind.is_fifo() {
        "a FIFO"
    } else if kind.is_char_device() {
        "a character device"
    } else if kind.is_block_device() {
        "a block device"
    } else if kind.is_socket() {
        "a socket"
    } else {
        "a special file"
    }
}

#[cfg(not(unix))]
fn special_kind(_: FileType) -> &'static str {
    "a special file"
}

/// Reads a file of at most `limit` bytes, as [`read_to_string_bounded`] does, as bytes.
pub fn read_bytes_bounded(path: &Path, limit: u64) -> std::io::Result<Vec<u8>> {
    let file = open_regular(path)?;
    let mut bytes = Vec::new();
    file.take(limit.saturating_add(1)).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(std::io::Error::new(
            std::io::ErrorKind::FileTooLarge,
            format!("larger than the limit of {}", describe_size(limit)),
        ));
    }
    Ok(bytes)
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

/// A temporary file beside `target` in `dir` (`.NAME.XXXXXX`), for a write that replaces `target`
/// by a rename: with `target`'s permissions, or 0644 less the umask for a new file (tempfile's 0600
/// would hide a shared lab file from its other users).
pub fn temp_beside(dir: &Path, target: &Path) -> std::io::Result<tempfile::NamedTempFile> {
    let name = target
        .file_name()
        .map_or_else(|| "file".into(), |n| n.to_string_lossy());
    let prefix = format!(".{name}.");
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix);
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o644));
    }
    let tmp = builder.tempfile_in(dir)?;
    if let Ok(existing) = std::fs::metadata(target) {
        tmp.as_file().set_permissions(existing.permissions())?;
    }
    Ok(tmp)
}

/// Flushes a folder's entries to disk, so a rename in it survives a power cut (Unix only can
/// open a folder).
pub fn sync_directory(dir: &Path) -> std::io::Result<()> {
    #[cfg(unix)]
    std::fs::File::open(dir)?.sync_all()?;
    #[cfg(not(unix))]
    let _ = dir;
    Ok(())
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
    fn make_fifo(path: &Path) {
        let mode = rustix::fs::Mode::RUSR | rustix::fs::Mode::WUSR;
        rustix::fs::mkfifoat(rustix::fs::CWD, path, mode).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn a_device_a_fifo_and_a_directory_are_refused_at_once() {
        let err = read_to_string_bounded(Path::new("/dev/zero"), KEYMAP_LIMIT).unwrap_err();
        assert_eq!(err.kind(), std::io::ErrorKind::InvalidInput);
        assert_eq!(
            err.to_string(),
            "not a regular file (a character device); only a regular file is read"
        );
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("fifo");
        make_fifo(&fifo);
        // No writer: an ordinary open would wait for one for ever.
        let err = read_to_string_bounded(&fifo, KEYMAP_LIMIT).unwrap_err();
        assert!(err.to_string().contains("(a FIFO)"), "{err}");
        let err = read_to_string_bounded(dir.path(), KEYMAP_LIMIT).unwrap_err();
        assert!(err.to_string().contains("(a directory)"), "{err}");
    }

    #[cfg(unix)]
    #[test]
    fn a_fifo_in_place_of_the_file_checked_does_not_block_the_open() {
        // The check after the open, as a path swapped between the two would meet it.
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("fifo");
        make_fifo(&fifo);
        let mut options = OpenOptions::new();
        options.read(true);
        std::os::unix::fs::OpenOptionsExt::custom_flags(
            &mut options,
            rustix::fs::OFlags::NONBLOCK.bits() as i32,
        );
        let file = options.open(&fifo).unwrap();
        assert!(not_regular(file.metadata().unwrap().file_type()).is_err());
    }

    #[test]
    fn invalid_utf8_is_refused() {
        let file = temp_file(&[b'a', 0xff]);
        let path = file.path();
        let err = read_to_string_bounded(path, 10).unwrap_err();
        assert_eq!(err.kind(), std::io::ErrorKind::InvalidData);
    }
}
