//! One book, several writers: a write never drops what another wrote since this console read the
//! file. Each write takes the lock (`book.json.lock`, held only while writing), re-reads the file,
//! merges by name (`merge`) and writes atomically (`save`). A file that no longer reads as a book
//! is not written over; one with entries set aside only once its `.bad` copy is kept.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use super::file::{Read, read_file};
use super::lenient::{self, SetAside};
use super::merge::{Conflict, Moved, merge};
use super::{BookError, PositionBook};

/// How long a write waits for another writer's lock: a write takes well under a second.
pub const LOCK_WAIT: Duration = Duration::from_secs(10);

/// What a write found in the file and made of it.
#[derive(Debug, Clone, PartialEq)]
pub struct Written {
    /// The book as written: this console's, merged with the file's.
    pub book: PositionBook,
    /// Positions and tours another writer changed, added or deleted, now in the book.
    pub taken: usize,
    /// Names changed both here and by another writer: both kept.
    pub conflicts: Vec<Conflict>,
    /// Positions of this console's that another writer moved beside their name.
    pub moved: Vec<Moved>,
    /// Entries of the file that did not load, not written again; `notes` says where they are.
    pub set_aside: Vec<SetAside>,
    /// What to tell about `set_aside` (where the file's bytes are kept).
    pub notes: Vec<String>,
}

impl Written {
    /// Whether another writer's work is in it (or set aside): the console is to be told.
    pub fn found_others(&self) -> bool {
        self.taken > 0
            || !self.conflicts.is_empty()
            || !self.moved.is_empty()
            || !self.set_aside.is_empty()
    }
}

impl PositionBook {
    /// Writes this book to `path` under its lock, merged with the file as it is now; `known` is the
    /// file as last known, `touched` the positions saved or edited here since.
    pub fn save_shared(
        &self,
        known: &PositionBook,
        touched: &BTreeSet<String>,
        path: &Path,
    ) -> Result<Written, BookError> {
        let shown = path.display().to_string();
        let _lock = BookLock::take(path)?;
        let (theirs, set_aside, notes) = match read_file(path) {
            Ok(None) => (PositionBook::new(), Vec::new(), Vec::new()),
            Ok(Some(Read { book, aside, text })) => {
                let notes = if aside.is_empty() {
                    Vec::new()
                } else {
                    let copy = lenient::keep_bad_copy(path, text.as_bytes()).map_err(|e| {
                        BookError::Unreadable {
                            path: shown.clone(),
                            reason: format!(
                                "{} bad entries in it could not be kept in a copy: {e}",
                                aside.len()
                            ),
                        }
                    })?;
                    lenient::notes(&aside, &Ok(copy))
                };
                (book, aside, notes)
            }
            Err(e) => {
                return Err(BookError::Unreadable {
                    path: shown,
                    reason: e.to_string(),
                });
            }
        };
        let merged = merge(known, self, &theirs, touched);
        merged.book.save(path)?;
        Ok(Written {
            book: merged.book,
            taken: merged.taken,
            conflicts: merged.conflicts,
            moved: merged.moved,
            set_aside,
            notes,
        })
    }
}

/// The book's lock, held while it is read and written; released when dropped.
struct BookLock {
    _file: Option<std::fs::File>,
}

impl BookLock {
    fn take(book: &Path) -> Result<BookLock, BookError> {
        let path = lock_path(book);
        let io = |source| BookError::Io {
            path: path.display().to_string(),
            source,
        };
        if let Some(dir) = book.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(io)?;
        }
        let file = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(&path)
            // A lock file another user made, readable only: a read-only lock locks as well.
            .or_else(|_| std::fs::File::open(&path))
            .map_err(io)?;
        let until = Instant::now() + LOCK_WAIT;
        loop {
            match file.try_lock() {
                Ok(()) => return Ok(BookLock { _file: Some(file) }),
                Err(std::fs::TryLockError::WouldBlock) if Instant::now() < until => {
                    std::thread::sleep(Duration::from_millis(20));
                }
                Err(std::fs::TryLockError::WouldBlock) => {
                    return Err(BookError::Locked {
                        path: book.display().to_string(),
                        lock: path.display().to_string(),
                        waited: LOCK_WAIT,
                    });
                }
                Err(std::fs::TryLockError::Error(e))
                    if e.kind() == std::io::ErrorKind::Unsupported =>
                {
                    // Without locks (network shares), re-read and merge leave a short race.
                    tracing::warn!(
                        "{}: no file locks here ({e}); the book is merged unlocked",
                        path.display()
                    );
                    return Ok(BookLock { _file: None });
                }
                Err(std::fs::TryLockError::Error(e)) => return Err(io(e)),
            }
        }
    }
}

/// `book.json.lock` beside `book.json`.
pub fn lock_path(book: &Path) -> PathBuf {
    let mut name = book.as_os_str().to_owned();
    name.push(".lock");
    PathBuf::from(name)
}

#[cfg(test)]
mod tests;
