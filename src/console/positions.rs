//! The console's book of named positions, kept in a JSON file.
//!
//! The Talos ICD has no "list positions" command, so the console remembers the names it saved or
//! saw, per arm. Over Modbus the arm has no named positions at all and the book is where they
//! live, with their full pose. Writes are atomic (temporary file, fsync, rename), so a crash
//! never leaves a half-written book.

use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use serde::{Deserialize, Serialize};

/// Version of the file format.
const FORMAT: u32 = 1;

/// One named position.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BookEntry {
    #[serde(default)]
    pub anchor: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub parent: Option<String>,
    /// Tool position in tenths of millimetres, when known.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cartesian: Option<[i32; 3]>,
    /// Tool orientation in degrees (extrinsic XYZ), when known (stored-pose go-to over Modbus).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub orientation: Option<[f32; 3]>,
    /// The operator answered "unknown position" for this name. Not saved: re-checked each run.
    #[serde(skip)]
    pub unknown_to_operator: bool,
}

/// The named positions of one arm.
///
/// Cloning is cheap (the map is shared, copied on the first change to a shared book): the
/// runtime hands the book to the saver and the app to the drawing thread without copying a big
/// book each time.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PositionBook {
    format: u32,
    #[serde(with = "shared_map")]
    positions: Arc<BTreeMap<String, BookEntry>>,
}

/// Serde for the shared map: the file holds the plain map.
mod shared_map {
    use super::*;

    pub fn serialize<S: serde::Serializer>(
        map: &Arc<BTreeMap<String, BookEntry>>,
        serializer: S,
    ) -> Result<S::Ok, S::Error> {
        map.as_ref().serialize(serializer)
    }

    pub fn deserialize<'de, D: serde::Deserializer<'de>>(
        deserializer: D,
    ) -> Result<Arc<BTreeMap<String, BookEntry>>, D::Error> {
        BTreeMap::deserialize(deserializer).map(Arc::new)
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
}

impl PositionBook {
    pub fn new() -> Self {
        PositionBook {
            format: FORMAT,
            positions: Arc::new(BTreeMap::new()),
        }
    }

    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.positions.keys().map(String::as_str)
    }

    pub fn len(&self) -> usize {
        self.positions.len()
    }

    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    pub fn get(&self, name: &str) -> Option<&BookEntry> {
        self.positions.get(name)
    }

    pub fn entries(&self) -> impl Iterator<Item = (&str, &BookEntry)> {
        self.positions.iter().map(|(n, e)| (n.as_str(), e))
    }

    /// The entry for `name`, created empty if new.
    pub fn entry(&mut self, name: &str) -> &mut BookEntry {
        Arc::make_mut(&mut self.positions)
            .entry(name.to_string())
            .or_default()
    }

    pub fn remove(&mut self, name: &str) -> Option<BookEntry> {
        if !self.positions.contains_key(name) {
            return None;
        }
        Arc::make_mut(&mut self.positions).remove(name)
    }

    /// Up to `count` entries from the `start`-th, in name order: a window of a big book, built
    /// without copying the rest of it.
    pub fn window(&self, start: usize, count: usize) -> PositionBook {
        PositionBook {
            format: self.format,
            positions: Arc::new(
                self.positions
                    .iter()
                    .skip(start)
                    .take(count)
                    .map(|(n, e)| (n.clone(), e.clone()))
                    .collect(),
            ),
        }
    }

    /// Adds every entry of `other` to this book, replacing those of the same name.
    pub fn merge(&mut self, other: &PositionBook) {
        if other.is_empty() {
            return;
        }
        let map = Arc::make_mut(&mut self.positions);
        for (name, entry) in other.positions.iter() {
            map.insert(name.clone(), entry.clone());
        }
    }

    /// Reads a book; a missing file is an empty book.
    pub fn load(path: &Path) -> Result<PositionBook, BookError> {
        let shown = path.display().to_string();
        let text = match crate::files::read_to_string_bounded(path, crate::files::POSITIONS_LIMIT) {
            Ok(text) => text,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(PositionBook::new()),
            Err(source) => {
                return Err(BookError::Io {
                    path: shown,
                    source,
                });
            }
        };
        let book: PositionBook = serde_json::from_str(&text).map_err(|e| BookError::Parse {
            path: shown.clone(),
            line: e.line(),
            column: e.column(),
            message: e.to_string(),
        })?;
        if book.format > FORMAT {
            return Err(BookError::Format {
                path: shown,
                found: book.format,
            });
        }
        Ok(book)
    }

    /// Writes the book atomically: a temporary file beside it, flushed to disk, then renamed.
    pub fn save(&self, path: &Path) -> Result<(), BookError> {
        let shown = path.display().to_string();
        let io = |source| BookError::Io {
            path: shown.clone(),
            source,
        };
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(io)?;
        }
        let text = self.to_text(&shown, crate::files::POSITIONS_LIMIT)?;
        let tmp = temporary_path(path);
        let mut file = std::fs::File::create(&tmp).map_err(io)?;
        file.write_all(text.as_bytes()).map_err(io)?;
        file.write_all(b"\n").map_err(io)?;
        file.sync_all().map_err(io)?;
        drop(file);
        std::fs::rename(&tmp, path).map_err(io)?;
        Ok(())
    }
}

impl PositionBook {
    /// The file's text (without the final newline): indented for people to read, compact when
    /// that would not fit in `limit` bytes (a book written must load again), refused when even
    /// compact does not.
    fn to_text(&self, path: &str, limit: u64) -> Result<String, BookError> {
        // The text and its final newline.
        let fits = |text: &String| (text.len() as u64) < limit;
        let failed = |e: serde_json::Error| BookError::Io {
            path: path.to_string(),
            source: std::io::Error::other(e),
        };
        let text = serde_json::to_string_pretty(self).map_err(failed)?;
        if fits(&text) {
            return Ok(text);
        }
        let text = serde_json::to_string(self).map_err(failed)?;
        if fits(&text) {
            return Ok(text);
        }
        Err(BookError::TooLarge {
            path: path.to_string(),
            bytes: text.len() as u64 + 1,
            limit,
        })
    }
}

fn temporary_path(path: &Path) -> PathBuf {
    let mut name = path
        .file_name()
        .map(|n| n.to_os_string())
        .unwrap_or_else(|| "positions.json".into());
    name.push(format!(".tmp{}", std::process::id()));
    path.with_file_name(name)
}

/// Where the book of the arm at `target` lives: `$ARMJOG_DATA_DIR` or the user's data
/// directory, then `armjog/positions/<target>.json`.
pub fn default_path(target: &str) -> Option<PathBuf> {
    let base = std::env::var_os("ARMJOG_DATA_DIR")
        .map(PathBuf::from)
        .or_else(|| dirs::data_dir().map(|d| d.join("armjog")))?;
    let safe: String = target
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '.' || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    Some(base.join("positions").join(format!("{safe}.json")))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir() -> PathBuf {
        let d = std::env::temp_dir().join(format!(
            "armjog-book-{}-{}",
            std::process::id(),
            std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map(|d| d.as_nanos())
                .unwrap_or(0)
        ));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn saves_and_loads_and_leaves_no_temporary_file() {
        let d = dir();
        let path = d.join("book.json");
        let mut book = PositionBook::new();
        let e = book.entry("pick");
        e.cartesian = Some([4566, 10, 4338]);
        e.anchor = true;
        e.parent = Some("table".into());
        book.entry("table");
        book.save(&path).unwrap();
        assert_eq!(PositionBook::load(&path).unwrap(), book);
        let files: Vec<_> = std::fs::read_dir(&d).unwrap().collect();
        assert_eq!(files.len(), 1, "only the book itself");
    }

    #[test]
    fn a_book_too_big_to_indent_is_written_compact_and_one_too_big_for_that_is_refused() {
        let mut book = PositionBook::new();
        for i in 0..100 {
            book.entry(&format!("p{i:03}")).cartesian = Some([i, 0, 0]);
        }
        let pretty = book.to_text("b.json", u64::MAX).unwrap();
        let compact = serde_json::to_string(&book).unwrap();
        assert!(
            pretty.len() > compact.len() + 100,
            "the test needs a difference"
        );
        let limit = compact.len() as u64 + 1;
        assert_eq!(book.to_text("b.json", limit).unwrap(), compact);
        let parsed: PositionBook = serde_json::from_str(&compact).unwrap();
        assert_eq!(parsed, book);
        let err = book.to_text("b.json", limit - 1).unwrap_err().to_string();
        assert!(err.starts_with("b.json: not written"), "{err}");
        assert!(err.contains(&format!("{limit} bytes")), "{err}");
    }

    #[test]
    fn a_missing_file_is_an_empty_book() {
        let book = PositionBook::load(&dir().join("none.json")).unwrap();
        assert!(book.is_empty());
    }

    #[test]
    fn a_corrupt_file_is_refused_with_its_name_line_and_column() {
        let path = dir().join("bad.json");
        std::fs::write(
            &path,
            "{\n  \"format\": 1,\n  \"positions\": {\n    \"a\": { \"anchr\": true }\n  }\n}\n",
        )
        .unwrap();
        let err = PositionBook::load(&path).unwrap_err().to_string();
        assert!(err.starts_with(&format!("{}:4:", path.display())), "{err}");
        assert!(err.contains("anchr"), "{err}");
    }

    #[test]
    fn target_names_become_safe_file_names() {
        let p = default_path("talos 10.0.0.2:61616").unwrap();
        assert!(
            p.ends_with("positions/talos_10.0.0.2_61616.json"),
            "{}",
            p.display()
        );
    }
}
