//! Two writers on one book: a three-way merge by name, pure. `known` is the file as this console
//! last knew it, `ours` its book, `theirs` the file now. A name one side changed takes that change;
//! a name both changed keeps theirs under the name and ours beside it (`pick~2`), and the conflict
//! is reported. A position saved here since the last write (`touched`) counts as changed even at
//! the file's value: an explicit save never silently loses.

use std::collections::BTreeSet;

use super::names::{is_copy_of, unique};
use super::tours::Tour;
use super::{BookEntry, Named, PositionBook};

/// What a merge made: the book to write, and what it took from the other side.
#[derive(Debug, Clone, PartialEq)]
pub struct Merged {
    pub book: PositionBook,
    /// Positions and tours the other side changed, added or deleted that ours had not.
    pub taken: usize,
    /// Names both sides changed.
    pub conflicts: Vec<Conflict>,
    /// Positions of ours another writer moved beside their name (a swap after a conflict).
    pub moved: Vec<Moved>,
}

/// Ours, unchanged here, now under a copy's name elsewhere while the name holds another entry.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Moved {
    pub name: String,
    pub to: String,
}

impl Moved {
    /// One line for the technician.
    pub fn describe(&self) -> String {
        let Moved { name, to } = self;
        format!(
            "position '{name}' was kept as '{to}' by another program, which gave '{name}' to \
             another position"
        )
    }
}

/// A name both sides changed, and how nothing of it was lost.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Conflict {
    /// "position" or "tour".
    pub kind: &'static str,
    pub name: String,
    pub outcome: Kept,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Kept {
    /// Both changed it: theirs keeps the name, ours is kept as `copy`.
    Both { copy: String },
    /// We deleted it, they changed it: theirs is kept.
    TheirsNotDeleted,
    /// They deleted it, we changed it: ours is kept.
    OursNotDeleted,
}

impl Conflict {
    /// One line for the technician.
    pub fn describe(&self) -> String {
        let Conflict {
            kind,
            name,
            outcome,
        } = self;
        match outcome {
            Kept::Both { copy } => format!(
                "{kind} '{name}' was changed here and by another program: theirs is kept as \
                 '{name}', this console's as '{copy}'"
            ),
            Kept::TheirsNotDeleted => format!(
                "{kind} '{name}' was deleted here but changed by another program: kept, not deleted"
            ),
            Kept::OursNotDeleted => {
                format!("{kind} '{name}' was deleted by another program but changed here: kept")
            }
        }
    }
}

/// Whether two entries are the same in the file (what is not saved does not count).
pub fn same_on_disk(a: &BookEntry, b: &BookEntry) -> bool {
    // Destructured so that a new field must be placed here.
    let BookEntry {
        anchor,
        parent,
        cartesian,
        orientation,
        joints,
        frame,
        unknown_to_operator: _,
        unsaved: _,
    } = a;
    *anchor == b.anchor
        && *parent == b.parent
        && *cartesian == b.cartesian
        && *orientation == b.orientation
        && *joints == b.joints
        && *frame == b.frame
}

/// Both there and the same on disk, or both gone.
fn same_entry(a: Option<&BookEntry>, b: Option<&BookEntry>) -> bool {
    a.zip(b)
        .map_or(a.is_none() && b.is_none(), |(a, b)| same_on_disk(a, b))
}

/// How one name merges.
enum Side<T> {
    /// The value to keep (none: the name is gone), and whether it came from the other side.
    Take(Option<T>, bool),
    /// Both changed it: theirs and ours.
    Conflict(Option<T>, Option<T>),
}

/// `touched`: the name was saved or edited here since `known`, whatever its value now.
fn three_way<T: Clone>(
    known: Option<&T>,
    ours: Option<&T>,
    theirs: Option<&T>,
    touched: bool,
    same: impl Fn(Option<&T>, Option<&T>) -> bool,
) -> Side<T> {
    if same(ours, theirs) {
        // Ours, which keeps what is not saved (marks the panel shows).
        Side::Take(ours.cloned(), false)
    } else if !touched && same(ours, known) {
        Side::Take(theirs.cloned(), true)
    } else if same(theirs, known) {
        Side::Take(ours.cloned(), false)
    } else {
        Side::Conflict(theirs.cloned(), ours.cloned())
    }
}

/// A name both sides changed, recorded in `conflicts`: what keeps the name, and ours to keep
/// beside it (named once every name is known) when both still have it.
fn resolve<T>(
    kind: &'static str,
    name: &str,
    theirs: Option<T>,
    ours: Option<T>,
    conflicts: &mut Vec<Conflict>,
) -> (Option<T>, Option<T>) {
    let both = Kept::Both {
        copy: String::new(),
    };
    let (outcome, keep, copy) = match (theirs, ours) {
        (Some(theirs), Some(ours)) => (both, Some(theirs), Some(ours)),
        (Some(theirs), None) => (Kept::TheirsNotDeleted, Some(theirs), None),
        (None, ours) => (Kept::OursNotDeleted, ours, None),
    };
    let name = name.to_string();
    conflicts.push(Conflict {
        kind,
        name,
        outcome,
    });
    (keep, copy)
}

/// The three-way merge of a write; `touched`: saved or edited here since `known`.
pub fn merge(
    known: &PositionBook,
    ours: &PositionBook,
    theirs: &PositionBook,
    touched: &BTreeSet<String>,
) -> Merged {
    merge_with(known, ours, theirs, touched, true)
}

/// The written book back in a console whose book may have changed since it was `handed`: what the
/// write took from the other side comes in; names changed here since keep their change.
pub fn incorporate(
    handed: &PositionBook,
    ours: &PositionBook,
    written: &PositionBook,
) -> PositionBook {
    merge_with(handed, ours, written, &BTreeSet::new(), false).book
}

fn merge_with(
    known: &PositionBook,
    ours: &PositionBook,
    theirs: &PositionBook,
    touched: &BTreeSet<String>,
    keep_both: bool,
) -> Merged {
    let mut taken = 0;
    let mut conflicts = Vec::new();
    let mut moved = Vec::new();
    let names: BTreeSet<&str> = known
        .names()
        .chain(ours.names())
        .chain(theirs.names())
        .collect();
    let mut list: Vec<Named> = Vec::with_capacity(names.len());
    let mut copies: Vec<Named> = Vec::new();
    for name in &names {
        let side = three_way(
            known.get(name),
            ours.get(name),
            theirs.get(name),
            touched.contains(*name),
            same_entry,
        );
        let keep = match side {
            Side::Take(entry, from_theirs) => {
                taken += usize::from(from_theirs);
                if from_theirs && keep_both {
                    moved.extend(moved_to(name, known, ours, theirs));
                }
                entry
            }
            Side::Conflict(theirs, ours) if !keep_both => ours.or(theirs),
            Side::Conflict(theirs, ours) => {
                let (keep, copy) = resolve("position", name, theirs, ours, &mut conflicts);
                copies.extend(copy.map(|ours| (name.to_string(), ours)));
                keep
            }
        };
        if let Some(entry) = keep {
            list.push((name.to_string(), entry));
        }
    }
    if !copies.is_empty() {
        let mut taken_names: BTreeSet<String> = names.iter().map(|n| n.to_string()).collect();
        for (name, entry) in copies {
            let copy = unique(&name, &taken_names);
            taken_names.insert(copy.clone());
            for conflict in conflicts.iter_mut().filter(|c| c.name == name) {
                conflict.outcome = Kept::Both { copy: copy.clone() };
            }
            list.push((copy, entry));
        }
        list.sort_by(|a, b| a.0.cmp(&b.0));
    }
    let tours = merge_tours(known, ours, theirs, keep_both, &mut taken, &mut conflicts);
    let mut book = PositionBook::new();
    book.positions = std::sync::Arc::new(list);
    book.tours = tours;
    Merged {
        book,
        taken,
        conflicts,
        moved,
    }
}

/// Where another writer moved our unchanged `name` to: a copy's name new to us.
fn moved_to(
    name: &str,
    known: &PositionBook,
    ours: &PositionBook,
    theirs: &PositionBook,
) -> Option<Moved> {
    let ours_entry = ours.get(name)?;
    theirs
        .entries()
        .find(|(copy, entry)| {
            is_copy_of(copy, name)
                && known.get(copy).is_none()
                && ours.get(copy).is_none()
                && same_on_disk(entry, ours_entry)
        })
        .map(|(copy, _)| Moved {
            name: name.to_string(),
            to: copy.to_string(),
        })
}

/// Tours merge as positions do, by name; the result has theirs in their order, then ours new.
fn merge_tours(
    known: &PositionBook,
    ours: &PositionBook,
    theirs: &PositionBook,
    keep_both: bool,
    taken: &mut usize,
    conflicts: &mut Vec<Conflict>,
) -> Vec<Tour> {
    let mut order: Vec<&str> = Vec::new();
    for tour in theirs
        .tours()
        .iter()
        .chain(ours.tours())
        .chain(known.tours())
    {
        if !order.contains(&tour.name.as_str()) {
            order.push(&tour.name);
        }
    }
    let mut kept: Vec<Tour> = Vec::new();
    let mut copies: Vec<Tour> = Vec::new();
    for name in order {
        let side = three_way(
            known.tour(name),
            ours.tour(name),
            theirs.tour(name),
            false,
            |a, b| a == b,
        );
        match side {
            Side::Take(tour, from_theirs) => {
                *taken += usize::from(from_theirs);
                kept.extend(tour);
            }
            Side::Conflict(theirs, ours) if !keep_both => kept.extend(ours.or(theirs)),
            Side::Conflict(theirs, ours) => {
                let (keep, copy) = resolve("tour", name, theirs, ours, conflicts);
                kept.extend(keep);
                copies.extend(copy);
            }
        }
    }
    for mut tour in copies {
        let taken_names: BTreeSet<String> = kept.iter().map(|t| t.name.clone()).collect();
        let copy = unique(&tour.name, &taken_names);
        for conflict in conflicts
            .iter_mut()
            .filter(|c| c.kind == "tour" && c.name == tour.name)
        {
            conflict.outcome = Kept::Both { copy: copy.clone() };
        }
        tour.name = copy;
        kept.push(tour);
    }
    kept
}

#[cfg(test)]
mod tests;
