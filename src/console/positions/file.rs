//! The book's file: versioned JSON, read within a size limit, written atomically.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::lenient::{self, SetAside};
use super::{BookEntry, Named, PositionBook};

/// Version of the file format.
pub(super) const FORMAT: u32 = 1;

/// Serde for the shared sorted list: the file holds a map from name to entry.
pub(super) mod sorted_map {
    use super::*;

    pub fn serialize<S: serde::Serializer>(
        list: &Arc<Vec<Named>>,
        serializer: S,
    ) -> Result<S::Ok, S::Error> {
        serializer.collect_map(list.iter().map(|(name, entry)| (name, entry)))
    }

    pub fn deserialize<'de, D: serde::Deserializer<'de>>(
        deserializer: D,
    ) -> Result<Arc<Vec<Named>>, D::Error> {
        deserializer.deserialize_map(ListVisitor).map(Arc::new)
    }

    /// Reads the map straight into a sorted list, the last of a repeated name kept.
    struct ListVisitor;

    impl<'de> serde::de::Visitor<'de> for ListVisitor {
        type Value = Vec<Named>;

        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("a map from position names to positions")
        }

        fn visit_map<A: serde::de::MapAccess<'de>>(
            self,
            mut map: A,
        ) -> Result<Vec<Named>, A::Error> {
            let mut list: Vec<Named> = Vec::new();
            while let Some(named) = map.next_entry::<String, BookEntry>()? {
                list.push(named);
            }
            // Stable: of equal names, the one given last stays last.
            list.sort_by(|a, b| a.0.cmp(&b.0));
            list.dedup_by(|later, kept| {
                if later.0 == kept.0 {
                    std::mem::swap(later, kept);
                    true
                } else {
                    false
                }
            });
            list.shrink_to_fit();
            Ok(list)
        }
    }
}

/// Why the book could not be read or written. Names the file.
#[derive(Debug, thiserror::Error)]
pub enum BookError {
    #[error("{path}: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    #[error("{path}:{line}:{column}: {message}")]
    Parse {
        path: String,
        line: usize,
        column: usize,
        message: String,
    },
    #[error("{path}: format {found} is newer than this armjog understands ({FORMAT})")]
    Format { path: String, found: u32 },
    /// The file now (changed since read) is not a book: a write would lose it.
    #[error("{path}: not written over: the file as it is now cannot be kept ({reason})")]
    Unreadable { path: String, reason: String },
    /// Another writer held the book's lock for longer than a write takes.
    #[error("{path}: not written: its lock {lock} was held by another program for {waited:?}")]
    Locked {
        path: String,
        lock: String,
        waited: std::time::Duration,
    },
    /// Writing it would make a file too large to be read back.
    #[error(
        "{path}: not written: the book takes {bytes} bytes, over the limit of {limit} bytes \
         that armjog reads back"
    )]
    TooLarge {
        path: String,
        bytes: u64,
        limit: u64,
    },
    /// The thread that reads it ended without an answer.
    #[error("the positions loader ended without a book")]
    LoaderEnded,
}

/// A book as its file holds it: what loaded, what was set aside, and the file's text.
pub(super) struct Read {
    pub book: PositionBook,
    pub aside: Vec<SetAside>,
    pub text: String,
}

/// Reads the book at `path` (`None`: no file), strictly or per entry (`lenient`); names repaired.
pub(super) fn read_file(path: &Path) -> Result<Option<Read>, BookError> {
    let shown = path.display().to_string();
    let text = match crate::files::read_to_string_bounded(path, crate::files::POSITIONS_LIMIT) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(source) => {
            return Err(BookError::Io {
                path: shown,
                source,
            });
        }
    };
    let (mut book, aside) = match serde_json::from_str::<PositionBook>(&text) {
        Ok(book) => (book, Vec::new()),
        Err(e) => lenient::parse(&text).ok_or_else(|| BookError::Parse {
            path: shown.clone(),
            line: e.line(),
            column: e.column(),
            message: e.to_string(),
        })?,
    };
    if book.format > FORMAT {
        return Err(BookError::Format {
            path: shown,
            found: book.format,
        });
    }
    book.repair_names();
    book.repair_tours();
    Ok(Some(Read { book, aside, text }))
}

impl PositionBook {
    /// Reads a book (missing: empty); bad entries set aside, the bytes kept (`lenient`).
    pub fn load(path: &Path) -> Result<PositionBook, BookError> {
        let Some(Read {
            mut book,
            aside,
            text,
        }) = read_file(path)?
        else {
            return Ok(PositionBook::new());
        };
        if !aside.is_empty() {
            let copy = lenient::keep_bad_copy(path, text.as_bytes());
            let mut notes = lenient::notes(&aside, &copy);
            notes.append(&mut book.load_notes);
            book.load_notes = notes;
        }
        Ok(book)
    }

    /// Writes the book atomically: a temporary file beside it, flushed, renamed over the book, then
    /// the directory flushed so the rename survives a power cut. On failure the book is untouched.
    pub fn save(&self, path: &Path) -> Result<(), BookError> {
        let shown = path.display().to_string();
        let io = |source| BookError::Io {
            path: shown.clone(),
            source,
        };
        let dir = match path.parent().filter(|d| !d.as_os_str().is_empty()) {
            Some(dir) => {
                std::fs::create_dir_all(dir).map_err(io)?;
                dir
            }
            None => Path::new("."),
        };
        let tmp = crate::files::temp_beside(dir, path).map_err(io)?;
        let mut out = std::io::BufWriter::new(tmp);
        self.write_to(&mut out, &shown, crate::files::POSITIONS_LIMIT)?;
        let tmp = out.into_inner().map_err(|e| io(e.into_error()))?;
        tmp.as_file().sync_all().map_err(io)?;
        tmp.persist(path).map_err(|e| io(e.error))?;
        crate::files::sync_directory(dir).map_err(io)
    }
}

impl PositionBook {
    /// Writes the file's text to `out`: indented, compact when that would not fit `limit` (a
    /// written book must load again), refused when even compact does not. Sizes are counted first.
    pub(super) fn write_to(
        &self,
        out: &mut impl Write,
        path: &str,
        limit: u64,
    ) -> Result<(), BookError> {
        let failed = |e: serde_json::Error| BookError::Io {
            path: path.to_string(),
            source: std::io::Error::other(e),
        };
        let write = |out: &mut dyn Write, pretty: bool| {
            if pretty {
                serde_json::to_writer_pretty(out, self)
            } else {
                serde_json::to_writer(out, self)
            }
        };
        let size = |pretty: bool| {
            let mut counter = ByteCounter(0);
            // With its final newline.
            write(&mut counter, pretty)
                .map(|()| counter.0 + 1)
                .map_err(failed)
        };
        let pretty = size(true)? <= limit;
        if !pretty {
            let bytes = size(false)?;
            if bytes > limit {
                return Err(BookError::TooLarge {
                    path: path.to_string(),
                    bytes,
                    limit,
                });
            }
        }
        write(&mut *out, pretty).map_err(failed)?;
        out.write_all(b"\n").map_err(|source| BookError::Io {
            path: path.to_string(),
            source,
        })
    }
}

/// Counts the bytes written to it.
struct ByteCounter(u64);

impl Write for ByteCounter {
    fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
        self.0 += bytes.len() as u64;
        Ok(bytes.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// An arm's book key: its profile's name if opened by one (one book per arm), else its target.
pub fn book_key(profile: Option<&str>, target: &str) -> String {
    match profile {
        Some(name) => format!("arm-{name}"),
        None => target.to_string(),
    }
}

/// `$ARMJOG_DATA_DIR` or the user's data directory, then `armjog/positions/<target>.json`.
pub fn default_path(target: &str) -> Option<PathBuf> {
    let base = std::env::var_os("ARMJOG_DATA_DIR")
        .map(PathBuf::from)
        .or_else(|| dirs::data_dir().map(|d| d.join("armjog")))?;
    let unsafe_in_a_file_name = |c: char| !(c.is_ascii_alphanumeric() || c == '.' || c == '-');
    let safe = target.replace(unsafe_in_a_file_name, "_");
    Some(base.join("positions").join(format!("{safe}.json")))
}
