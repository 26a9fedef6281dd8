//! The console's book of named positions, kept in a JSON file.
//!
//! The Talos ICD has no "list positions" command, so the console remembers the names it saved or
//! saw, per arm. Over Modbus the arm has no named positions at all and the book is where they
//! live, with their full pose. Writes are atomic (temporary file, fsync, rename), so a crash
//! never leaves a half-written book.

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
    /// Tool orientation θx, θy, θz in degrees (extrinsic XYZ, as the telemetry gives them),
    /// when known.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub orientation: Option<[f32; 3]>,
    /// Joint angles J1-J7 in degrees as the telemetry reported them (0-360) when the pose was
    /// saved from the arm; dropped once the coordinates change, as they no longer describe it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub joints: Option<[f32; 7]>,
    /// The frame `cartesian` and `orientation` are in. Books written before it was recorded
    /// held base-frame coordinates too (the telemetry's and the operator's frame).
    #[serde(default)]
    pub frame: PoseFrame,
    /// The operator answered "unknown position" for this name. Not saved: re-checked each run.
    #[serde(skip)]
    pub unknown_to_operator: bool,
}

impl BookEntry {
    /// Sets the coordinates (tenths of millimetres). Joint angles taken elsewhere no longer
    /// describe the position and are dropped; a difference of one tenth is rounding.
    pub fn set_cartesian(&mut self, cartesian: [i32; 3]) {
        let moved = self.cartesian.is_none_or(|old| {
            old.iter()
                .zip(cartesian)
                .any(|(before, now)| before.abs_diff(now) > 1)
        });
        if moved {
            self.joints = None;
        }
        self.cartesian = Some(cartesian);
    }
}

/// The frame a position's coordinates are given in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PoseFrame {
    /// The arm's base frame: the frame of the tool pose in telemetry and of the Talos
    /// operator's cartesian and polar coordinates.
    #[default]
    Base,
}

impl PoseFrame {
    /// Words for the screen: "base frame".
    pub fn label(self) -> &'static str {
        match self {
            PoseFrame::Base => "base frame",
        }
    }
}

/// One named position and its name; the book keeps them sorted by name.
type Named = (String, BookEntry);

/// The named positions of one arm, in name order.
///
/// Kept as a sorted list, so the `i`-th name (the selection, the rows on the screen) is found
/// at once and a name in a few steps however big the book: no frame walks the whole book.
/// Cloning is cheap (the list is shared, copied on the first change to a shared book): the
/// runtime hands the book to the writer without copying a big book each time.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PositionBook {
    format: u32,
    #[serde(with = "sorted_map")]
    positions: Arc<Vec<Named>>,
}

/// Serde for the shared sorted list: the file holds a map from name to entry.
mod sorted_map {
    use super::*;
    use serde::ser::SerializeMap;

    pub fn serialize<S: serde::Serializer>(
        list: &Arc<Vec<Named>>,
        serializer: S,
    ) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(list.len()))?;
        for (name, entry) in list.iter() {
            map.serialize_entry(name, entry)?;
        }
        map.end()
    }

    pub fn deserialize<'de, D: serde::Deserializer<'de>>(
        deserializer: D,
    ) -> Result<Arc<Vec<Named>>, D::Error> {
        deserializer.deserialize_map(ListVisitor).map(Arc::new)
    }

    /// Reads the map straight into the list (no map built on the side), then sorts it and keeps
    /// the last of a name given twice, as a map would.
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
            positions: Arc::new(Vec::new()),
        }
    }

    /// Where `name` is in the list, or where it would go.
    fn find(&self, name: &str) -> Result<usize, usize> {
        self.positions
            .binary_search_by(|(n, _)| n.as_str().cmp(name))
    }

    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.positions.iter().map(|(n, _)| n.as_str())
    }

    /// The `index`-th name in name order.
    pub fn name_at(&self, index: usize) -> Option<&str> {
        self.positions.get(index).map(|(n, _)| n.as_str())
    }

    /// Where `name` is in name order.
    pub fn index_of(&self, name: &str) -> Option<usize> {
        self.find(name).ok()
    }

    pub fn len(&self) -> usize {
        self.positions.len()
    }

    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    pub fn get(&self, name: &str) -> Option<&BookEntry> {
        let index = self.find(name).ok()?;
        self.positions.get(index).map(|(_, e)| e)
    }

    pub fn entries(&self) -> impl Iterator<Item = (&str, &BookEntry)> {
        self.entries_from(0)
    }

    /// The entries from the `start`-th on, in name order (none past the end).
    pub fn entries_from(&self, start: usize) -> impl Iterator<Item = (&str, &BookEntry)> {
        self.positions
            .get(start..)
            .unwrap_or_default()
            .iter()
            .map(|(n, e)| (n.as_str(), e))
    }

    /// The entry for `name`, to change it; `None` (and nothing added) if the book has no such
    /// name. Looking a name up never adds it, so it never moves the rows after it.
    pub fn get_mut(&mut self, name: &str) -> Option<&mut BookEntry> {
        let index = self.find(name).ok()?;
        Arc::make_mut(&mut self.positions)
            .get_mut(index)
            .map(|(_, e)| e)
    }

    /// The entry for `name`, added empty if new: for a name the technician saved (or a book
    /// being built). Adding a name moves the names after it down a row.
    pub fn get_or_insert(&mut self, name: &str) -> &mut BookEntry {
        let index = match self.find(name) {
            Ok(index) => index,
            Err(index) => {
                Arc::make_mut(&mut self.positions)
                    .insert(index, (name.to_string(), BookEntry::default()));
                index
            }
        };
        &mut Arc::make_mut(&mut self.positions)[index].1
    }

    pub fn remove(&mut self, name: &str) -> Option<BookEntry> {
        let index = self.find(name).ok()?;
        Some(Arc::make_mut(&mut self.positions).remove(index).1)
    }

    /// Up to `count` entries from the `start`-th, in name order: a window of a big book, built
    /// without copying the rest of it.
    pub fn window(&self, start: usize, count: usize) -> PositionBook {
        PositionBook {
            format: self.format,
            positions: Arc::new(
                self.positions
                    .get(start..)
                    .unwrap_or_default()
                    .iter()
                    .take(count)
                    .cloned()
                    .collect(),
            ),
        }
    }

    /// Adds every entry of `other` to this book, replacing those of the same name.
    pub fn merge(&mut self, other: &PositionBook) {
        if other.is_empty() {
            return;
        }
        for (name, entry) in other.positions.iter() {
            *self.get_or_insert(name) = entry.clone();
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

    /// Writes the book atomically: a temporary file beside it, flushed to disk, renamed over
    /// the book, then the directory flushed so the rename itself survives a power cut. On any
    /// failure the book on disk is untouched and the temporary file is removed (when dropped).
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
        let tmp = new_book_file(dir, path).map_err(io)?;
        let mut out = std::io::BufWriter::new(tmp);
        self.write_to(&mut out, &shown, crate::files::POSITIONS_LIMIT)?;
        let tmp = out.into_inner().map_err(|e| io(e.into_error()))?;
        tmp.as_file().sync_all().map_err(io)?;
        tmp.persist(path).map_err(|e| io(e.error))?;
        sync_directory(dir).map_err(io)
    }
}

/// The temporary file a save writes, with the permissions the book will keep: those of the
/// book it replaces, or for a new book the usual 0644 less the umask (tempfile's own default,
/// 0600, would quietly hide a shared lab book from its other users).
fn new_book_file(dir: &Path, book: &Path) -> std::io::Result<tempfile::NamedTempFile> {
    let mut builder = tempfile::Builder::new();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o644));
    }
    let tmp = builder.tempfile_in(dir)?;
    if let Ok(existing) = std::fs::metadata(book) {
        tmp.as_file().set_permissions(existing.permissions())?;
    }
    Ok(tmp)
}

/// Flushes a directory's entries (a rename into it) to disk. Only Unix can open a directory
/// as a file; elsewhere the rename is as durable as the platform makes it.
fn sync_directory(dir: &Path) -> std::io::Result<()> {
    #[cfg(unix)]
    std::fs::File::open(dir)?.sync_all()?;
    #[cfg(not(unix))]
    let _ = dir;
    Ok(())
}

impl PositionBook {
    /// Writes the file's text to `out`: indented for people to read, compact when that would
    /// not fit in `limit` bytes (a book written must load again), refused when even compact does
    /// not. The sizes are counted first, so a big book is never held as text in memory.
    fn write_to(&self, out: &mut impl Write, path: &str, limit: u64) -> Result<(), BookError> {
        let failed = |e: serde_json::Error| BookError::Io {
            path: path.to_string(),
            source: std::io::Error::other(e),
        };
        let size = |pretty: bool| {
            let mut counter = ByteCounter(0);
            let result = if pretty {
                serde_json::to_writer_pretty(&mut counter, self)
            } else {
                serde_json::to_writer(&mut counter, self)
            };
            // With its final newline.
            result.map(|()| counter.0 + 1).map_err(failed)
        };
        let pretty = if size(true)? <= limit {
            true
        } else {
            let bytes = size(false)?;
            if bytes > limit {
                return Err(BookError::TooLarge {
                    path: path.to_string(),
                    bytes,
                    limit,
                });
            }
            false
        };
        if pretty {
            serde_json::to_writer_pretty(&mut *out, self).map_err(failed)?;
        } else {
            serde_json::to_writer(&mut *out, self).map_err(failed)?;
        }
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

    fn dir() -> tempfile::TempDir {
        tempfile::tempdir().unwrap()
    }

    #[test]
    #[cfg(unix)]
    fn a_save_keeps_the_books_permissions_and_a_new_book_is_not_private() {
        use std::os::unix::fs::{OpenOptionsExt, PermissionsExt};
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("book.json");
        let mut book = PositionBook::default();
        book.get_or_insert("pick");
        book.save(&path).expect("saved");
        let mode = |p: &Path| std::fs::metadata(p).expect("metadata").permissions().mode() & 0o777;
        // What any new 0644 file gets under this process's umask.
        let probe = dir.path().join("probe");
        std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .mode(0o644)
            .open(&probe)
            .expect("probe file");
        assert_eq!(mode(&path), mode(&probe), "a new book follows the umask");
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o640)).expect("chmod");
        book.save(&path).expect("saved again");
        assert_eq!(mode(&path), 0o640, "the book keeps its permissions");
    }

    #[test]
    fn saves_and_loads_and_leaves_no_temporary_file() {
        let d = dir();
        let path = d.path().join("book.json");
        let mut book = PositionBook::new();
        let e = book.get_or_insert("pick");
        e.cartesian = Some([4566, 10, 4338]);
        e.anchor = true;
        e.parent = Some("table".into());
        book.get_or_insert("table");
        book.save(&path).unwrap();
        assert_eq!(PositionBook::load(&path).unwrap(), book);
        let files: Vec<_> = std::fs::read_dir(d.path()).unwrap().collect();
        assert_eq!(files.len(), 1, "only the book itself");
    }

    #[test]
    fn a_save_that_cannot_rename_leaves_no_temporary_file_and_names_the_book() {
        let d = dir();
        // A non-empty directory where the book should go: the final rename fails.
        let path = d.path().join("book.json");
        std::fs::create_dir_all(path.join("in-the-way")).unwrap();
        let mut book = PositionBook::new();
        book.get_or_insert("pick");
        let err = book.save(&path).unwrap_err().to_string();
        assert!(err.starts_with(&path.display().to_string()), "{err}");
        let names: Vec<_> = std::fs::read_dir(d.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, ["book.json"], "the temporary file is removed");
        assert!(
            path.join("in-the-way").is_dir(),
            "what was there is untouched"
        );
    }

    #[test]
    fn saving_over_an_old_book_replaces_it_whole() {
        let d = dir();
        let path = d.path().join("nested").join("book.json");
        let mut old = PositionBook::new();
        for i in 0..50 {
            old.get_or_insert(&format!("p{i:02}"));
        }
        old.save(&path).unwrap();
        let mut new = PositionBook::new();
        new.get_or_insert("only");
        new.save(&path).unwrap();
        assert_eq!(PositionBook::load(&path).unwrap(), new);
    }

    #[test]
    fn a_book_too_big_to_indent_is_written_compact_and_one_too_big_for_that_is_refused() {
        let mut book = PositionBook::new();
        for i in 0..100 {
            book.get_or_insert(&format!("p{i:03}")).cartesian = Some([i, 0, 0]);
        }
        let text = |limit: u64| {
            let mut out = Vec::new();
            book.write_to(&mut out, "b.json", limit).map(|()| out)
        };
        let pretty = text(u64::MAX).unwrap();
        assert_eq!(
            pretty,
            format!("{}\n", serde_json::to_string_pretty(&book).unwrap()).into_bytes()
        );
        let compact = format!("{}\n", serde_json::to_string(&book).unwrap()).into_bytes();
        assert!(
            pretty.len() > compact.len() + 100,
            "the test needs a difference"
        );
        let limit = compact.len() as u64;
        assert_eq!(text(limit).unwrap(), compact);
        let parsed: PositionBook = serde_json::from_slice(&compact).unwrap();
        assert_eq!(parsed, book);
        let err = text(limit - 1).unwrap_err().to_string();
        assert!(err.starts_with("b.json: not written"), "{err}");
        assert!(err.contains(&format!("takes {limit} bytes")), "{err}");
    }

    #[test]
    fn names_stay_in_order_through_changes_and_are_found_by_index_and_by_name() {
        let mut book = PositionBook::new();
        for name in ["pick", "bench", "table", "home"] {
            book.get_or_insert(name);
        }
        book.get_or_insert("pick").anchor = true;
        assert_eq!(book.remove("table").map(|e| e.anchor), Some(false));
        assert_eq!(book.remove("table"), None);
        let names: Vec<&str> = book.names().collect();
        assert_eq!(names, ["bench", "home", "pick"]);
        assert_eq!(book.name_at(2), Some("pick"));
        assert_eq!(book.name_at(3), None);
        assert_eq!(book.index_of("home"), Some(1));
        assert_eq!(book.index_of("nope"), None);
        assert!(book.get("pick").is_some_and(|e| e.anchor));
        let tail: Vec<&str> = book.entries_from(1).map(|(n, _)| n).collect();
        assert_eq!(tail, ["home", "pick"]);
        assert_eq!(book.entries_from(9).count(), 0);
        let window: Vec<String> = book.window(1, 1).names().map(String::from).collect();
        assert_eq!(window, ["home"]);
        // A file in any order, a name given twice: sorted, the last one kept.
        let parsed: PositionBook = serde_json::from_str(
            r#"{"format":1,"positions":{"b":{},"a":{"anchor":true},"b":{"anchor":true}}}"#,
        )
        .unwrap();
        let names: Vec<&str> = parsed.names().collect();
        assert_eq!(names, ["a", "b"]);
        assert!(parsed.get("b").is_some_and(|e| e.anchor));
    }

    #[test]
    fn looking_a_name_up_adds_nothing() {
        let mut book = PositionBook::new();
        book.get_or_insert("bench");
        book.get_or_insert("table");
        assert!(book.get_mut("apple").is_none());
        assert!(book.get_mut("zebra").is_none());
        let names: Vec<&str> = book.names().collect();
        assert_eq!(names, ["bench", "table"]);
        if let Some(bench) = book.get_mut("bench") {
            bench.anchor = true;
        }
        assert!(book.get("bench").is_some_and(|e| e.anchor));
        assert_eq!(book.len(), 2);
    }

    #[test]
    fn a_missing_file_is_an_empty_book() {
        let book = PositionBook::load(&dir().path().join("none.json")).unwrap();
        assert!(book.is_empty());
    }

    #[test]
    fn a_corrupt_file_is_refused_with_its_name_line_and_column() {
        let d = dir();
        let path = d.path().join("bad.json");
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
