//! The position book while it loads: the runtime parses the file off the event loop (a book of
//! up to 16 MB takes a second or more) and hands it over as [`super::Input::PositionsLoaded`];
//! meanwhile the console draws, jogs and stops as usual.
//!
//! Nothing is lost and nothing is overwritten: a change made while the book loads is kept in
//! memory and merged into the loaded book, which is then saved; a book that could not be read is
//! never saved over (the file may only need a fix). The state machine's side is in `book.rs`.

/// How many remembered names are checked with the operator when the link comes up: each costs
/// a request, and a big book would flood the operator (and the console) for minutes. The others
/// are checked when shown or gone to.
pub const CHECKED_ON_CONNECT: usize = 100;

/// Where the position book stands.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum BookState {
    /// Loaded (or there is no file): changes are saved.
    Ready,
    /// The file is being read and parsed. `file` names it.
    Loading { file: String },
    /// The file could not be read: it is never saved over. `error` names the file and the cause.
    Failed { error: String },
}
