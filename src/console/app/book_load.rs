//! The position book while it loads: the runtime parses the file off the event loop (a book of
//! up to 16 MB takes a second or more) and hands it over as [`super::Input::PositionsLoaded`];
//! meanwhile the console draws, jogs and stops as usual.
//!
//! Nothing is lost and nothing is overwritten: a change made while the book loads is kept in
//! memory and merged into the loaded book, which is then saved; a book that could not be read is
//! never saved over (the file may only need a fix).

use std::time::Instant;

use super::{App, Effect, Severity};
use crate::console::positions::PositionBook;
use crate::link::interface::ArmCommand;

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

impl App {
    /// The runtime started loading the book from `file`.
    pub fn begin_loading_positions(&mut self, file: impl Into<String>) {
        self.book.on_loading(file.into());
    }

    /// The book arrived (or could not be read: the error names the file and what was wrong).
    pub(super) fn on_positions_loaded(
        &mut self,
        result: Result<PositionBook, String>,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) {
        match result {
            Ok(mut book) => {
                self.tell_repaired_names(book.take_load_notes(), now);
                let changed_meanwhile = self.book.on_loaded(book);
                if changed_meanwhile {
                    // The names changed meanwhile were noted as they changed.
                    self.save_book::<&str>(&[], effects);
                }
                if self.config.positions_on_operator && self.link_is_up() {
                    self.check_names_on_operator(effects);
                }
            }
            Err(error) => {
                tracing::error!("positions not loaded: {error}");
                self.say(
                    format!("positions not loaded: {error}"),
                    Severity::Error,
                    now,
                );
                self.book.on_load_failed(error);
            }
        }
    }

    /// Names in the file that broke the name rule were repaired as it loaded: each is logged,
    /// and the bottom line says so and shows the first.
    fn tell_repaired_names(&mut self, notes: Vec<String>, now: Instant) {
        let Some(first) = notes.first() else {
            return;
        };
        for note in &notes {
            tracing::warn!("positions: {note}");
        }
        let more = match notes.len() {
            1 => String::new(),
            n => format!(" (and {} more: see the log)", n - 1),
        };
        self.say(
            format!("positions file: {first}{more}"),
            Severity::Warning,
            now,
        );
    }

    /// Asks the operator about the first [`CHECKED_ON_CONNECT`] remembered names, so the panel
    /// marks the ones it does not know.
    pub(super) fn check_names_on_operator(&self, effects: &mut Vec<Effect>) {
        for name in self.book.positions().names().take(CHECKED_ON_CONNECT) {
            effects.push(Effect::Arm(ArmCommand::GetPosition {
                name: name.to_string(),
            }));
        }
        if self.book.positions().len() > CHECKED_ON_CONNECT {
            tracing::info!(
                "checked the first {CHECKED_ON_CONNECT} of {} positions with the operator",
                self.book.positions().len()
            );
        }
    }

    /// Holds back saving while the book is not loaded: saving then would write a partial book
    /// over the file.
    pub(super) fn hold_saves_until_loaded(&mut self, now: Instant, effects: &mut Vec<Effect>) {
        let text = match self.book.state() {
            BookState::Ready => return,
            BookState::Loading { file } => {
                format!("positions still loading from {file}: the change is saved once loaded")
            }
            BookState::Failed { error } => {
                format!("positions not saved: the file could not be read ({error})")
            }
        };
        let before = effects.len();
        effects.retain(|e| !matches!(e, Effect::SavePositions(_)));
        if effects.len() != before {
            let severity = match self.book.state() {
                BookState::Loading { .. } => Severity::Warning,
                _ => Severity::Error,
            };
            self.say(text, severity, now);
        }
    }
}
