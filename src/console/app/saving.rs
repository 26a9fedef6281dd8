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
use super::{App, BookState, Effect, Severity};
use crate::console::book_io::SaveOutcome;
use crate::console::form::Confirm;

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

impl App {
    /// Changes to `changed` are to be written: asks for the whole book to be saved.
    pub(super) fn save_book<S: AsRef<str>>(&mut self, changed: &[S], effects: &mut Vec<Effect>) {
        self.book
            .saving_mut()
            .touched
            .extend(changed.iter().map(|n| n.as_ref().to_string()));
        effects.push(Effect::SavePositions(self.book.positions().clone()));
    }

    /// After every input: the saves that leave `handle` are counted, as the writer counts them.
    /// A book that could not be read is never saved over: its changes are unsaved at once.
    pub(super) fn count_saves(&mut self, effects: &[Effect]) {
        let asked = effects
            .iter()
            .filter(|e| matches!(e, Effect::SavePositions(_)))
            .count() as u64;
        if asked > 0 {
            self.book.saving_mut().asked += asked;
            let upto = self.book.saving_mut().asked;
            for name in std::mem::take(&mut self.book.saving_mut().touched) {
                self.book.saving_mut().pending.insert(name, upto);
            }
        } else if matches!(self.book.state(), BookState::Failed { .. })
            && !self.book.saving_mut().touched.is_empty()
        {
            let names = std::mem::take(&mut self.book.saving_mut().touched);
            self.mark_unsaved(names);
        }
    }

    /// The writer's outcome for the saves up to `outcome.upto`.
    pub(super) fn on_positions_saved(&mut self, outcome: SaveOutcome, now: Instant) {
        let covered: Vec<String> = self
            .book
            .saving_mut()
            .pending
            .iter()
            .filter(|(_, upto)| **upto <= outcome.upto)
            .map(|(name, _)| name.clone())
            .collect();
        for name in &covered {
            self.book.saving_mut().pending.remove(name);
        }
        match outcome.error {
            None => {
                // The whole book was written: whatever had failed before is on disk now.
                let failed = std::mem::take(&mut self.book.saving_mut().failed);
                if failed.is_empty() {
                    return;
                }
                for name in &failed {
                    if let Some(entry) = self.book.positions_mut().get_mut(name) {
                        entry.unsaved = false;
                    }
                }
                let text = format!("positions saved ({} that had failed)", failed.len());
                self.say(text, Severity::Info, now);
            }
            Some(error) => {
                tracing::error!("positions not saved: {error}");
                self.mark_unsaved(covered);
                let n = self.book.saving().failed.len();
                let text = format!(
                    "positions not saved: {error}; {n} marked not saved, retried with the next \
                     change"
                );
                self.say_until(text, Severity::Error, Until::BookSaved, now);
            }
        }
    }

    fn mark_unsaved(&mut self, names: impl IntoIterator<Item = String>) {
        for name in names {
            if let Some(entry) = self.book.positions_mut().get_mut(&name)
                && !entry.unsaved
            {
                entry.unsaved = true;
            }
            self.book.saving_mut().failed.insert(name);
        }
    }

    /// How many changed positions no write has held (their write failed).
    pub fn unsaved_positions(&self) -> usize {
        self.book.saving().failed.len()
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
        if self.unsaved_positions() > 0 && *self.book.state() == BookState::Ready {
            let names: Vec<String> = self.book.saving_mut().failed.iter().cloned().collect();
            tracing::warn!(
                "quitting with {} positions not saved: writing the book once more",
                names.len()
            );
            self.save_book(&names, effects);
        }
    }
}
