//! A save is saved or marked: the book is written on the writer's thread, and each write's
//! outcome comes back as [`Input::PositionsSaved`](super::Input::PositionsSaved). A position
//! whose write failed (a full disk, a read-only folder) is marked "not saved" in the panel until
//! a later write holds it; every change writes the whole book, so the next save retries it;
//! quitting with positions not saved asks first, and tries once more as it quits.
//!
//! The writer counts the books handed to it as the app counts the saves it asks for (every
//! [`Effect::SavePositions`] that leaves [`super::App::handle`]), so an outcome's count says
//! which changes it covers.

use std::collections::{BTreeMap, BTreeSet};
use std::time::Instant;

use super::message::Until;
use super::{App, Effect, Severity};
use crate::console::book_io::SaveOutcome;
use crate::console::form::Confirm;
use crate::console::positions::PositionBook;

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

    /// `asked` saves left `handle` (as the writer counts them). With none asked and the book
    /// unreadable (never saved over), the names changed are handed back: unsaved at once.
    pub(super) fn count(&mut self, asked: u64, unreadable: bool) -> BTreeSet<String> {
        if asked > 0 {
            self.asked += asked;
            let upto = self.asked;
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

    /// The names the writes up to `upto` held, no longer pending.
    pub(super) fn covered(&mut self, upto: u64) -> Vec<String> {
        let covered: Vec<String> = self
            .pending
            .iter()
            .filter(|(_, at)| **at <= upto)
            .map(|(name, _)| name.clone())
            .collect();
        for name in &covered {
            self.pending.remove(name);
        }
        covered
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
        if let Some(entry) = positions.get_mut(&name)
            && !entry.unsaved
        {
            entry.unsaved = true;
        }
        saving.mark_failed(name);
    }
}

impl App {
    /// Changes to `changed` are to be written: asks for the whole book to be saved.
    pub(super) fn save_book<S: AsRef<str>>(&mut self, changed: &[S], effects: &mut Vec<Effect>) {
        let book = self
            .book
            .on_changed(changed.iter().map(|n| n.as_ref().to_string()));
        effects.push(Effect::SavePositions(book));
    }

    /// After every input: the saves that leave `handle` are counted, as the writer counts them.
    /// A book that could not be read is never saved over: its changes are unsaved at once.
    pub(super) fn count_saves(&mut self, effects: &[Effect]) {
        let asked = effects
            .iter()
            .filter(|e| matches!(e, Effect::SavePositions(_)))
            .count() as u64;
        self.book.on_saves_asked(asked);
    }

    /// The writer's outcome for the saves up to `outcome.upto`.
    pub(super) fn on_positions_saved(&mut self, mut outcome: SaveOutcome, now: Instant) {
        if let Some(found) = outcome.found.take() {
            self.book.on_found(&found);
            self.tell_found(&found.written, now);
        }
        match self.book.on_saved(outcome) {
            Saved::Quietly => {}
            Saved::Recovered(n) => {
                let text = format!("positions saved ({n} that had failed)");
                self.say(text, Severity::Info, now);
            }
            Saved::Failed { error, unsaved } => {
                tracing::error!("positions not saved: {error}");
                let text = format!(
                    "positions not saved: {error}; {unsaved} marked not saved, retried with the \
                     next change"
                );
                self.say_until(text, Severity::Error, Until::BookSaved, now);
            }
        }
    }

    /// How many changed positions no write has held (their write failed).
    pub fn unsaved_positions(&self) -> usize {
        self.book.unsaved()
    }

    /// The quit key: with positions not saved, asks first (and stops the arm meanwhile).
    pub(super) fn ask_quit(&mut self, now: Instant, effects: &mut Vec<Effect>) {
        let count = self.unsaved_positions();
        if count == 0 {
            self.quit(now, effects);
            return;
        }
        self.stop_everything(now, effects);
        self.screen
            .show(super::Overlay::Confirm(Confirm::QuitUnsaved { count }));
    }

    /// Quitting with positions not saved: the book is handed over once more, and written (or
    /// its failure logged) before the process ends.
    pub(super) fn retry_save_at_quit(&mut self, effects: &mut Vec<Effect>) {
        if let Some(names) = self.book.unsaved_to_retry() {
            tracing::warn!(
                "quitting with {} positions not saved: writing the book once more",
                names.len()
            );
            self.save_book(&names, effects);
        }
    }
}
