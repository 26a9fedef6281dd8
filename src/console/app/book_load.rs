//! The position book while it loads: parsed off the event loop (a 16 MB book takes a second or
//! more) and handed over as [`super::Input::PositionsLoaded`], so the console keeps jogging and
//! stopping meanwhile. A change made meanwhile is merged into the loaded book and saved; a book
//! that could not be read is never saved over.

/// Remembered names checked when the link comes up (a request each); others when shown.
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
