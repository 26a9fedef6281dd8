//! The position book in the state machine, from its file to the operator:
//! - loading: the runtime parses the file off the event loop and hands it over as
//!   [`Input::PositionsLoaded`]; meanwhile the console draws, jogs and stops as usual. A change
//!   made while it loads is kept and merged into the loaded book, then saved; a book that could
//!   not be read is never saved over (`book_load`: [`BookState`]).
//! - saving: every change writes the whole book on the writer's thread, each outcome comes back
//!   as [`Input::PositionsSaved`]; a position whose write failed is marked "not saved" until a
//!   later write holds it, and quitting with such positions asks first (`saving`: the counts).
//! - merges: what a write found another writer had put in the file is told here; a position
//!   both changed is kept twice (`pick~2`) and the technician is asked which keeps the name.
//! - re-saves: a name a Talos operator has lost is offered for re-saving from the coordinates
//!   the console remembers, then gone to, as the one confirmation (`resave`).
//!
//! Edits (save, rename, delete, undo) are in `edits`, the named-position keys in `named`.

use std::time::Instant;

use super::book_load::{BookState, CHECKED_ON_CONNECT};
use super::message::Until;
use super::resave::RESAVE_GO_WITHIN;
use super::saving::Saved;
use super::{App, Effect, Input, Overlay, Severity};
use crate::console::book_io::{Loaded, SaveOutcome};
use crate::console::form::Confirm;
use crate::console::positions::merge::Kept;
use crate::console::positions::shared::Written;
use crate::link::interface::{ArmCommand, ArmError, ArmEvent, CommandKind, LinkStatus};
use crate::talos::ReturnCode;

impl App {
    /// The runtime started loading the book from `file`.
    pub fn begin_loading_positions(&mut self, file: impl Into<String>) {
        self.book.on_loading(file.into());
    }

    /// The book arrived (or could not be read: the error names the file and what was wrong).
    pub(super) fn on_positions_loaded(
        &mut self,
        result: Loaded,
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
                self.book.on_load_failed(error.to_string());
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

impl App {
    /// A write found another writer's changes: a name changed on both sides is a warning naming
    /// it (and a question, when nothing else is going on), as are entries of the file set
    /// aside; what was merged in is said, after `saved`, the name said as being saved.
    pub(super) fn tell_found(&mut self, written: &Written, saved: Option<&str>, now: Instant) {
        for conflict in &written.conflicts {
            tracing::warn!("positions: {}", conflict.describe());
        }
        for note in &written.notes {
            tracing::warn!("positions file: {note}");
        }
        for moved in &written.moved {
            tracing::warn!("positions: {}", moved.describe());
        }
        let more = |n: usize| match n {
            0 | 1 => String::new(),
            n => format!(" (and {} more: see the log)", n - 1),
        };
        if let Some(first) = written.conflicts.first() {
            let text = format!("{}{}", first.describe(), more(written.conflicts.len()));
            self.say(text, Severity::Warning, now);
            self.ask_which(written);
        } else if let Some(first) = written.notes.first() {
            self.say(format!("positions file: {first}"), Severity::Warning, now);
        } else if let Some(first) = written.moved.first() {
            let text = format!("{}{}", first.describe(), more(written.moved.len()));
            self.say(text, Severity::Warning, now);
        } else if written.taken > 0 {
            let saved = saved.map(|n| format!("saved '{n}'; ")).unwrap_or_default();
            let text = format!(
                "{saved}positions file changed by another program: {} change(s) merged in, \
                 nothing lost",
                written.taken
            );
            self.say(text, Severity::Info, now);
        }
    }

    /// Asks about the first position kept twice, unless a question or motion is under way (the
    /// warning stays; a question never interrupts the technician).
    fn ask_which(&mut self, written: &Written) {
        let busy = !self.screen.overlay_is_none()
            || self.keys.jog().is_jogging()
            || self.tours.phase().is_some()
            || self.truth.action().is_some();
        if busy {
            return;
        }
        let first = written.conflicts.iter().find_map(|c| match &c.outcome {
            Kept::Both { copy } if c.kind == "position" => Some((c.name.clone(), copy.clone())),
            _ => None,
        });
        if let Some((name, copy)) = first {
            self.screen
                .show(Overlay::Confirm(Confirm::BothChanged { name, copy }));
        }
    }

    /// Yes: this console's position takes the name, the other program's goes beside it.
    pub(super) fn take_the_name(
        &mut self,
        name: String,
        copy: String,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) {
        let book = self.book.positions_mut();
        let (Some(theirs), Some(ours)) = (book.get(&name).cloned(), book.get(&copy).cloned())
        else {
            let text = format!("'{name}' or '{copy}' is gone meanwhile: nothing swapped");
            self.say(text, Severity::Warning, now);
            return;
        };
        if let Some(entry) = book.get_mut(&name) {
            *entry = ours;
        }
        if let Some(entry) = book.get_mut(&copy) {
            *entry = theirs;
        }
        self.book.select(&name);
        let text = format!("'{name}' is this console's now; the other program's is '{copy}'");
        self.say(text, Severity::Info, now);
        self.save_book(&[&name, &copy], effects);
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

    /// `name` was saved in the book: "saved" once written (at once when there is no file),
    /// "saving…" until then.
    pub(super) fn say_saved(&mut self, name: &str, now: Instant) {
        if self.book.announce(name) {
            let text = format!("saving '{name}'…");
            self.say_until(text, Severity::Info, Until::BookWritten, now);
        } else {
            self.say(format!("saved '{name}'"), Severity::Info, now);
        }
    }

    /// The writer's outcome for the saves up to `outcome.upto`.
    pub(super) fn on_positions_saved(&mut self, mut outcome: SaveOutcome, now: Instant) {
        let reported = self.book.reported(outcome.upto);
        let written = outcome.error.is_none();
        if let Some(found) = outcome.found.take() {
            self.book.on_found(&found);
            self.tell_found(&found.written, reported.as_deref(), now);
        } else if let Some(name) = reported.filter(|_| written) {
            self.say(format!("saved '{name}'"), Severity::Info, now);
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

impl App {
    /// The go-to key on `name`: the usual question, or the re-save offer for a name the operator
    /// is known to have lost.
    pub(super) fn ask_go_to(&mut self, name: String, now: Instant) {
        // Not asked when the answer could only be that it cannot work.
        if let Some(why) = self.go_to_refusal(&name) {
            self.say(why, Severity::Warning, now);
            return;
        }
        if self.refuse_motion(now) {
            return;
        }
        let lost = self.config.positions_on_operator
            && self
                .book
                .positions()
                .get(&name)
                .is_some_and(|e| e.unknown_to_operator);
        if !lost {
            self.screen.show(Overlay::Confirm(Confirm::GoTo(name)));
        } else if self.remembered_cartesian(&name).is_some() {
            self.screen.show(Overlay::Confirm(Confirm::Resave(name)));
        } else {
            self.say(
                format!("'{name}' is unknown to the operator and no coordinates are remembered"),
                Severity::Warning,
                now,
            );
        }
    }

    fn remembered_cartesian(&self, name: &str) -> Option<[i32; 3]> {
        self.book.positions().get(name).and_then(|e| e.cartesian)
    }

    /// The technician said yes to re-saving `name`.
    pub(super) fn resave_confirmed(
        &mut self,
        name: String,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) {
        let Some([x, y, z]) = self.remembered_cartesian(&name) else {
            self.say(
                format!("'{name}' has no coordinates remembered"),
                Severity::Warning,
                now,
            );
            return;
        };
        effects.push(Effect::Arm(ArmCommand::SetCartesianPosition {
            name: name.clone(),
            x,
            y,
            z,
        }));
        self.say(
            format!("re-saving '{name}' on the operator"),
            Severity::Info,
            now,
        );
        self.book.resave_mut().then_go = Some((name, now));
    }

    /// A Go To is being sent for `name`.
    pub(super) fn going_to(&mut self, name: &str) {
        self.book.resave_mut().goto_sent = Some(name.to_string());
    }

    /// The operator accepted Set Cartesian Position for `name`: the go-to a re-save was for.
    pub(super) fn after_resave(&mut self, name: &str, now: Instant, effects: &mut Vec<Effect>) {
        let Some((pending, asked)) = self
            .book
            .resave_mut()
            .then_go
            .take_if(|(n, _)| n.as_str() == name)
        else {
            return;
        };
        if now.saturating_duration_since(asked) > RESAVE_GO_WITHIN {
            self.say(
                format!("re-saved '{pending}' (too late to move there unasked: go to it again)"),
                Severity::Info,
                now,
            );
            return;
        }
        self.going_to(&pending);
        self.say(
            format!("re-saved '{pending}': moving there"),
            Severity::Info,
            now,
        );
        effects.push(Effect::Arm(ArmCommand::GoToPosition { name: pending }));
    }

    /// Anything but the operator's answer drops a pending go-to: only the technician's "yes",
    /// with nothing in between, moves the arm.
    pub(super) fn resave_watch(&mut self, input: &Input) {
        let interrupts = match input {
            Input::Key(key) => key.kind != crate::console::jog::KeyKind::Release,
            Input::FocusLost | Input::Signal(_) => true,
            Input::Arm(ArmEvent::Status(status)) => !matches!(status, LinkStatus::Up { .. }),
            _ => false,
        };
        if interrupts {
            self.book.resave_mut().then_go = None;
        }
    }

    /// A failed position command. Go To failing with UNKNOWN_POSITION offers the re-save;
    /// returns whether the failure was told here.
    pub(super) fn position_failed(
        &mut self,
        command: CommandKind,
        error: &ArmError,
        now: Instant,
    ) -> bool {
        match command {
            CommandKind::SetCartesianPosition => {
                self.book.resave_mut().then_go = None;
                false
            }
            CommandKind::GoToPosition
                if *error == ArmError::ReturnCode(ReturnCode::UNKNOWN_POSITION) =>
            {
                let Some(name) = self.book.resave_mut().goto_sent.take() else {
                    return false;
                };
                if let Some(entry) = self.book.positions_mut().get_mut(&name) {
                    entry.unknown_to_operator = true;
                }
                let can_offer = self.remembered_cartesian(&name).is_some();
                if can_offer && self.screen.overlay_is_none() && !self.keys.jog().is_jogging() {
                    self.screen
                        .show(Overlay::Confirm(Confirm::Resave(name.clone())));
                    self.say(
                        format!("the operator does not know '{name}'"),
                        Severity::Warning,
                        now,
                    );
                } else if can_offer {
                    self.say(
                        format!(
                            "the operator does not know '{name}': go to it again to re-save it \
                             from the remembered coordinates"
                        ),
                        Severity::Warning,
                        now,
                    );
                } else {
                    self.say(
                        format!(
                            "the operator does not know '{name}' and no coordinates are remembered"
                        ),
                        Severity::Warning,
                        now,
                    );
                }
                true
            }
            _ => false,
        }
    }
}
