//! The position book: its entries, the selection, edits, undo, re-saves and saves.

use super::super::{BookState, edits, resave, saving};
use crate::console::positions::PositionBook;

/// The position book: its entries, the selection, edits, undo, re-saves and saves.
#[derive(Debug, Clone)]
pub(in crate::console::app) struct Book {
    pub(in crate::console::app) positions: PositionBook,
    /// Whether the book is loaded, still loading, or could not be read.
    pub(in crate::console::app) book_state: BookState,
    pub(in crate::console::app) selected: usize,
    /// A rename on the operator between its steps, and a restore waiting for its answer.
    pub(in crate::console::app) renaming: Option<edits::Renaming>,
    pub(in crate::console::app) restoring: Option<edits::Deleted>,
    /// The last deleted position, for undo (one level).
    pub(in crate::console::app) last_deleted: Option<edits::Deleted>,
    /// Re-saving names the operator lost (see `resave`).
    pub(in crate::console::app) resave: resave::Resave,
    /// The book's writes and the positions they failed to write.
    pub(in crate::console::app) saving: saving::Saving,
}

impl Book {
    pub(in crate::console::app) fn new(positions: PositionBook) -> Book {
        Book {
            positions,
            book_state: BookState::Ready,
            selected: 0,
            renaming: None,
            restoring: None,
            last_deleted: None,
            resave: resave::Resave::default(),
            saving: saving::Saving::default(),
        }
    }
}

