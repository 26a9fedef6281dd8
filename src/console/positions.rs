//! The console's book of named positions, in a JSON file. The Talos ICD cannot list positions, so
//! the console remembers the names it saved or saw; over Modbus the book is where positions live.
//! `file`: format, load, atomic save; `lenient`: a file with bad entries; `shared`: a write that
//! keeps another writer's changes.

mod file;
mod lenient;
pub mod merge;
mod names;
pub mod shared;
#[cfg(test)]
mod tests;
mod tours;

pub use file::{BookError, book_key, default_path};
pub use lenient::{SetAside, keep_bad_copy};
pub use tours::{LEG_SEPARATOR, Tour};

use std::sync::Arc;

use serde::{Deserialize, Serialize};

use file::{FORMAT, sorted_map};

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
    /// Its last change could not be written to the file (see `app::saving`). Not saved.
    #[serde(skip)]
    pub unsaved: bool,
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
    /// What loading the file repaired (names breaking the rule), for the console to tell.
    #[serde(skip)]
    load_notes: Vec<String>,
    /// Ordered lists of positions to visit (see `tours`); absent from older books.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    tours: Vec<Tour>,
}
impl PositionBook {
    pub fn new() -> Self {
        PositionBook {
            format: FORMAT,
            positions: Arc::new(Vec::new()),
            load_notes: Vec::new(),
            tours: Vec::new(),
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
            load_notes: Vec::new(),
            tours: Vec::new(),
        }
    }

    /// Adds every entry and tour of `other` to this book, replacing those of the same name.
    pub fn merge(&mut self, other: &PositionBook) {
        self.merge_tours(other);
        if other.is_empty() {
            return;
        }
        for (name, entry) in other.positions.iter() {
            *self.get_or_insert(name) = entry.clone();
        }
    }
}
