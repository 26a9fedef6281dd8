//! The position book: its entries, the selection, edits, undo, re-saves and saves.

use super::super::edits::{Deleted, Renaming};
use super::super::saving::{self, Saved};
use super::super::{BookState, resave};
use crate::console::book_io::{BookSave, Found, SaveOutcome};
use crate::console::positions::{PositionBook, merge};

#[derive(Debug, Clone)]
pub(in crate::console::app) struct Book {
    positions: PositionBook,
    /// The file as last known: a write merges the file's changes since (see `BookSave`).
    known: PositionBook,
    state: BookState,
    /// Whether the book has a file (saves are written, and their outcomes reported).
    file: bool,
    selected: usize,
    /// A rename on the operator between its steps, and a restore waiting for its answer.
    renaming: Option<Renaming>,
    restoring: Option<Deleted>,
    /// The last deleted position, for undo (one level).
    last_deleted: Option<Deleted>,
    /// Re-saving names the operator lost (see `resave`).
    resave: resave::Resave,
    /// The book's writes and the positions they failed to write (see `saving`).
    saving: saving::Saving,
}

/// What the book shows: the part of it a screen can show.
#[derive(Debug, Clone, PartialEq)]
pub struct BookView {
    pub state: BookState,
    /// What a screen can show: the selection and a screen's height of names either side.
    pub positions: PositionBook,
    /// The selection's row in `positions`.
    pub selected: usize,
}

impl Book {
    pub(in crate::console::app) fn new(positions: PositionBook) -> Book {
        Book {
            known: positions.clone(),
            positions,
            state: BookState::Ready,
            file: false,
            selected: 0,
            renaming: None,
            restoring: None,
            last_deleted: None,
            resave: resave::Resave::default(),
            saving: saving::Saving::default(),
        }
    }

    pub(in crate::console::app) fn positions(&self) -> &PositionBook {
        &self.positions
    }

    /// The entries, to edit (the caller asks for the save: see `saving`).
    pub(in crate::console::app) fn positions_mut(&mut self) -> &mut PositionBook {
        &mut self.positions
    }

    pub(in crate::console::app) fn state(&self) -> &BookState {
        &self.state
    }

    pub(in crate::console::app) fn on_loading(&mut self, file: String) {
        self.state = BookState::Loading { file };
        self.file = true;
    }

    /// `name` is "saving…" until the writer reports it; false without a file.
    pub(in crate::console::app) fn announce(&mut self, name: &str) -> bool {
        if self.file {
            self.saving.announce(name);
        }
        self.file
    }

    /// Whether a save said as being saved is not reported yet.
    pub(in crate::console::app) fn writing(&self) -> bool {
        self.saving.writing()
    }

    /// The name said as being saved, when the writes up to `upto` hold it.
    pub(in crate::console::app) fn reported(&mut self, upto: u64) -> Option<String> {
        self.saving.reported(upto)
    }

    /// The file's book arrived, merged with changes made meanwhile; returns whether any were.
    pub(in crate::console::app) fn on_loaded(&mut self, mut book: PositionBook) -> bool {
        let changed_meanwhile = !self.positions.is_empty();
        let selected = self.selected_name().map(str::to_string);
        self.known = book.clone();
        book.merge(&self.positions);
        self.positions = book;
        self.state = BookState::Ready;
        match selected {
            Some(name) => self.select(&name),
            None => self.selected = 0,
        }
        self.keep_selection();
        changed_meanwhile
    }

    pub(in crate::console::app) fn on_load_failed(&mut self, error: String) {
        self.state = BookState::Failed { error };
    }

    pub(in crate::console::app) fn selected(&self) -> usize {
        self.selected
    }

    pub(in crate::console::app) fn selected_name(&self) -> Option<&str> {
        self.positions.name_at(self.selected)
    }

    /// The selection one down or up, round the ends.
    pub(in crate::console::app) fn on_select_next(&mut self, forward: bool) {
        let n = self.positions.len();
        if n > 0 {
            self.selected = (self.selected + if forward { 1 } else { n - 1 }) % n;
        }
    }

    pub(in crate::console::app) fn select(&mut self, name: &str) {
        if let Some(i) = self.positions.index_of(name) {
            self.selected = i;
        }
    }

    /// The selection kept within the book after it shrank.
    pub(in crate::console::app) fn keep_selection(&mut self) {
        self.selected = self.selected.min(self.positions.len().saturating_sub(1));
    }

    /// The operator answered about `name`: it knows it (and where it is, when it says).
    pub(in crate::console::app) fn on_operator_knows(
        &mut self,
        name: &str,
        cartesian: Option<[i32; 3]>,
    ) {
        // A reply about a deleted name adds nothing: it would shift rows under the technician.
        if let Some(entry) = self.positions.get_mut(name) {
            entry.unknown_to_operator = false;
            if let Some(c) = cartesian {
                entry.set_cartesian(c);
            }
        }
    }

    pub(in crate::console::app) fn on_unknown_to_operator(&mut self, name: &str) {
        if let Some(entry) = self.positions.get_mut(name) {
            entry.unknown_to_operator = true;
        }
    }

    /// `name` out of the book, kept for undo (one level).
    pub(in crate::console::app) fn on_delete(&mut self, name: &str) {
        if let Some(entry) = self.positions.remove(name) {
            self.last_deleted = Some((name.to_string(), entry));
        }
        self.keep_selection();
    }

    pub(in crate::console::app) fn last_deleted(&self) -> Option<&Deleted> {
        self.last_deleted.as_ref()
    }

    /// The undo was used (or its position is back another way).
    pub(in crate::console::app) fn forget_deleted(&mut self) {
        self.last_deleted = None;
    }

    pub(in crate::console::app) fn renaming(&self) -> Option<&Renaming> {
        self.renaming.as_ref()
    }

    pub(in crate::console::app) fn renaming_mut(&mut self) -> Option<&mut Renaming> {
        self.renaming.as_mut()
    }

    /// A rename on the operator starts its steps, or (`None`) has ended.
    pub(in crate::console::app) fn set_renaming(&mut self, renaming: Option<Renaming>) {
        self.renaming = renaming;
    }

    pub(in crate::console::app) fn restoring(&self) -> Option<&Deleted> {
        self.restoring.as_ref()
    }

    /// A restore waits for the operator's answer, or (`None`) has had it.
    pub(in crate::console::app) fn set_restoring(&mut self, restoring: Option<Deleted>) {
        self.restoring = restoring;
    }

    pub(in crate::console::app) fn resave_mut(&mut self) -> &mut resave::Resave {
        &mut self.resave
    }

    /// Names changed: the whole book for the writer, the file as last known, and the names changed
    /// since (a save at the file's value counts).
    pub(in crate::console::app) fn on_changed(
        &mut self,
        changed: impl IntoIterator<Item = String>,
    ) -> BookSave {
        self.saving.touch(changed);
        let known = std::mem::replace(&mut self.known, self.positions.clone());
        BookSave {
            book: self.positions.clone(),
            known,
            touched: self.saving.touched().clone(),
        }
    }

    /// Another writer's changes merged by a write come into the book (a name changed here since
    /// keeps ours, for the next write) and the file as known. The selection stays on its name.
    pub(in crate::console::app) fn on_found(&mut self, found: &Found) {
        let selected = self.selected_name().map(str::to_string);
        let written = &found.written.book;
        self.positions = merge::incorporate(&found.handed, &self.positions, written);
        self.known = merge::incorporate(&found.handed, &self.known, written);
        if let Some(name) = selected {
            self.select(&name);
        }
        self.keep_selection();
    }

    /// `asked` saves left `handle`; an unreadable book's changes are unsaved at once.
    pub(in crate::console::app) fn on_saves_asked(&mut self, asked: u64) {
        let unreadable = matches!(self.state, BookState::Failed { .. });
        let unsaved = self.saving.count(asked, unreadable);
        saving::mark_unsaved(&mut self.positions, &mut self.saving, unsaved);
    }

    pub(in crate::console::app) fn on_saved(&mut self, outcome: SaveOutcome) -> Saved {
        let covered = self.saving.covered(outcome.upto);
        match outcome.error {
            None => {
                let failed = self.saving.take_failed();
                if failed.is_empty() {
                    return Saved::Quietly;
                }
                for name in &failed {
                    if let Some(entry) = self.positions.get_mut(name) {
                        entry.unsaved = false;
                    }
                }
                Saved::Recovered(failed.len())
            }
            Some(error) => {
                saving::mark_unsaved(&mut self.positions, &mut self.saving, covered);
                Saved::Failed {
                    error,
                    unsaved: self.saving.failed().len(),
                }
            }
        }
    }

    pub(in crate::console::app) fn unsaved(&self) -> usize {
        self.saving.failed().len()
    }

    /// At quit: the names no write has held, when the book may be written (it was read).
    pub(in crate::console::app) fn unsaved_to_retry(&self) -> Option<Vec<String>> {
        (self.unsaved() > 0 && self.state == BookState::Ready)
            .then(|| self.saving.failed().iter().cloned().collect())
    }

    /// The selection and up to `rows` names either side (enough for any panel).
    pub(in crate::console::app) fn view(&self, rows: usize) -> BookView {
        let start = self.selected.saturating_sub(rows);
        BookView {
            state: self.state.clone(),
            positions: self.positions.window(start, 2 * rows + 1),
            selected: self.selected - start,
        }
    }
}
