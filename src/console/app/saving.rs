//! A save is saved or marked: each write's outcome comes back as
//! [`Input::PositionsSaved`](super::Input::PositionsSaved); a failed position shows "not saved"
//! until a later write (of the whole book) holds it, and quitting with such positions asks first.
//! The writer counts the books it is handed as the app counts [`super::Effect::SavePositions`], so
//! an outcome's count says which changes it covers.

use crate::console::positions::PositionBook;
use std::collections::{BTreeMap, BTreeSet};

/// What the app knows of its book's writes.
#[derive(Debug, Clone, Default)]
pub(super) struct Saving {
    /// Saves asked for so far.
    asked: u64,
    /// Names changed since the last save was asked for.
    touched: BTreeSet<String>,
    /// Names in a save not confirmed yet, with the count of the latest save holding them.
    pending: BTreeMap<String, u64>,
    /// Names whose write failed and that no write has held since (a deleted one included).
    failed: BTreeSet<String>,
    /// The name said as being saved, until the save holding it is counted.
    announced: Option<String>,
    /// The name said as being saved, with the count of the save holding it.
    writing: Option<(String, u64)>,
}

/// What a write's outcome comes to, for the message line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) enum Saved {
    /// Written, and nothing had failed before.
    Quietly,
    /// Written, with this many positions whose earlier write had failed.
    Recovered(usize),
    /// Not written: the error, and how many positions are now marked not saved.
    Failed { error: String, unsaved: usize },
}

impl Saving {
    /// Names changed, to be held by the next save asked for.
    pub(super) fn touch(&mut self, changed: impl IntoIterator<Item = String>) {
        self.touched.extend(changed);
    }

    /// The names changed since the last save was asked for (held back while the book loads).
    pub(super) fn touched(&self) -> &BTreeSet<String> {
        &self.touched
    }

    /// `asked` saves left `handle`; with none and the book unreadable, the changes are unsaved now.
    pub(super) fn count(&mut self, asked: u64, unreadable: bool) -> BTreeSet<String> {
        let announced = self.announced.take();
        if asked > 0 {
            self.asked += asked;
            let upto = self.asked;
            if let Some(name) = announced {
                self.writing = Some((name, upto));
            }
            for name in std::mem::take(&mut self.touched) {
                self.pending.insert(name, upto);
            }
            BTreeSet::new()
        } else if unreadable {
            std::mem::take(&mut self.touched)
        } else {
            BTreeSet::new()
        }
    }

    /// `name` is said as being saved, by the save asked for now.
    pub(super) fn announce(&mut self, name: &str) {
        self.announced = Some(name.to_string());
    }

    pub(super) fn writing(&self) -> bool {
        self.writing.is_some()
    }

    pub(super) fn reported(&mut self, upto: u64) -> Option<String> {
        let held = self.writing.take_if(|(_, at)| *at <= upto);
        held.map(|(name, _)| name)
    }

    /// The names the writes up to `upto` held, no longer pending.
    pub(super) fn covered(&mut self, upto: u64) -> Vec<String> {
        let (covered, pending): (BTreeMap<_, _>, _) = std::mem::take(&mut self.pending)
            .into_iter()
            .partition(|(_, at)| *at <= upto);
        self.pending = pending;
        covered.into_keys().collect()
    }

    /// The whole book was written: whatever had failed is on disk now.
    pub(super) fn take_failed(&mut self) -> BTreeSet<String> {
        std::mem::take(&mut self.failed)
    }

    pub(super) fn mark_failed(&mut self, name: String) {
        self.failed.insert(name);
    }

    pub(super) fn failed(&self) -> &BTreeSet<String> {
        &self.failed
    }
}

/// Marks `names` not saved in the panel and in the saves' record.
pub(super) fn mark_unsaved(
    positions: &mut PositionBook,
    saving: &mut Saving,
    names: impl IntoIterator<Item = String>,
) {
    for name in names {
        if let Some(entry) = positions.get_mut(&name) {
            entry.unsaved = true;
        }
        saving.mark_failed(name);
    }
}
