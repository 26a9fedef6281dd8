//! The position book in the state machine, from its file to the operator: loading off the event
//! loop (`book_load`), saving each change on the writer's thread (`saving`), merges with another
//! writer's changes (a name both changed is kept twice, `pick~2`, and the technician asked), and
//! re-saving names a Talos operator lost (`resave`). Edits are in `edits`, the named-position keys
//! in `saved_positions`.

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
                self.error(format!("positions not loaded: {error}"), now);
                self.book.on_load_failed(error.to_string());
            }
        }
    }

    /// Names repaired as the file loaded: each logged, the first shown on the bottom line.
    fn tell_repaired_names(&mut self, notes: Vec<String>, now: Instant) {
        let Some(first) = notes.first() else {
            return;
        };
        for note in &notes {
            tracing::warn!("positions: {note}");
        }
        let more = and_more(notes.len());
        self.warn(format!("positions file: {first}{more}"), now);
    }

    /// Asks the operator about the first [`CHECKED_ON_CONNECT`] remembered names.
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

    /// No saving until the book is loaded: it would write a partial book over the file.
    pub(super) fn hold_saves_until_loaded(&mut self, now: Instant, effects: &mut Vec<Effect>) {
        let (text, severity) = match self.book.state() {
            BookState::Ready => return,
            BookState::Loading { file } => (
                format!("positions still loading from {file}: the change is saved once loaded"),
                Severity::Warning,
            ),
            BookState::Failed { error } => (
                format!("positions not saved: the file could not be read ({error})"),
                Severity::Error,
            ),
        };
        let before = effects.len();
        effects.retain(|e| !matches!(e, Effect::SavePositions(_)));
        if effects.len() != before {
            self.say(text, severity, now);
        }
    }

    /// A write found another writer's changes: a name changed on both sides, or an entry set aside,
    /// is a warning (and a question when nothing else goes on); what was merged in is said after
    /// `saved`.
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
        if let Some(first) = written.conflicts.first() {
            let text = format!("{}{}", first.describe(), and_more(written.conflicts.len()));
            self.warn(text, now);
            self.ask_which(written);
        } else if let Some(first) = written.notes.first() {
            self.warn(format!("positions file: {first}"), now);
        } else if let Some(first) = written.moved.first() {
            let text = format!("{}{}", first.describe(), and_more(written.moved.len()));
            self.warn(text, now);
        } else if written.taken > 0 {
            let saved = saved.map(|n| format!("saved '{n}'; ")).unwrap_or_default();
            let text = format!(
                "{saved}positions file changed by another program: {} change(s) merged in, \
                 nothing lost",
                written.taken
            );
            self.info(text, now);
        }
    }

    /// Asks about the first position kept twice, unless a question or motion is under way.
    fn ask_which(&mut self, written: &Written) {
        let busy = !self.screen.overlay_is_none()
            || self.keys.jog().is_jogging()
            || self.tours.phase().is_some()
            || self.motion_truth.action().is_some();
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
            self.warn(text, now);
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
        self.info(text, now);
        self.save_book(&[&name, &copy], effects);
    }

    /// Changes to `changed` are to be written: asks for the whole book to be saved.
    pub(super) fn save_book<S: AsRef<str>>(&mut self, changed: &[S], effects: &mut Vec<Effect>) {
        let book = self
            .book
            .on_changed(changed.iter().map(|n| n.as_ref().to_string()));
        effects.push(Effect::SavePositions(book));
    }

    /// After every input: counts the saves leaving `handle`, as the writer counts them.
    pub(super) fn count_saves(&mut self, effects: &[Effect]) {
        let asked = effects
            .iter()
            .filter(|e| matches!(e, Effect::SavePositions(_)))
            .count() as u64;
        self.book.on_saves_asked(asked);
    }

    /// `name` was saved: "saving…" until written, then "saved" (at once without a file).
    pub(super) fn say_saved(&mut self, name: &str, now: Instant) {
        if self.book.announce(name) {
            let text = format!("saving '{name}'…");
            self.say_until(text, Severity::Info, Until::BookWritten, now);
        } else {
            self.info(format!("saved '{name}'"), now);
        }
    }

    pub(super) fn on_positions_saved(&mut self, mut outcome: SaveOutcome, now: Instant) {
        let reported = self.book.reported(outcome.upto);
        let written = outcome.error.is_none();
        if let Some(found) = outcome.found.take() {
            self.book.on_found(&found);
            self.tell_found(&found.written, reported.as_deref(), now);
        } else if let Some(name) = reported.filter(|_| written) {
            self.info(format!("saved '{name}'"), now);
        }
        match self.book.on_saved(outcome) {
            Saved::Quietly => {}
            Saved::Recovered(n) => self.info(format!("positions saved ({n} that had failed)"), now),
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

    /// Quitting with unsaved positions: the book is handed over once more before the end.
    pub(super) fn retry_save_at_quit(&mut self, effects: &mut Vec<Effect>) {
        if let Some(names) = self.book.unsaved_to_retry() {
            tracing::warn!(
                "quitting with {} positions not saved: writing the book once more",
                names.len()
            );
            self.save_book(&names, effects);
        }
    }

    /// The go-to key: the usual question, or the re-save offer for a name the operator lost.
    pub(super) fn ask_go_to(&mut self, name: String, now: Instant) {
        // Not asked when the answer could only be that it cannot work.
        if let Some(why) = self.go_to_refusal(&name) {
            self.warn(why, now);
            return;
        }
        if self.refuse_motion(now) {
            return;
        }
        if !self.lost_by_operator(&name) {
            self.screen.show(Overlay::Confirm(Confirm::GoTo(name)));
        } else if self.remembered_cartesian(&name).is_some() {
            self.screen.show(Overlay::Confirm(Confirm::Resave(name)));
        } else {
            self.warn(
                format!("'{name}' is unknown to the operator and no coordinates are remembered"),
                now,
            );
        }
    }

    /// The operator keeps the positions and said it does not know `name`.
    pub(super) fn lost_by_operator(&self, name: &str) -> bool {
        let entry = self.book.positions().get(name);
        self.config.positions_on_operator && entry.is_some_and(|e| e.unknown_to_operator)
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
            self.warn(format!("'{name}' has no coordinates remembered"), now);
            return;
        };
        effects.push(Effect::Arm(ArmCommand::SetCartesianPosition {
            name: name.clone(),
            x,
            y,
            z,
        }));
        self.info(format!("re-saving '{name}' on the operator"), now);
        self.book.resave_mut().then_go = Some((name, now));
    }

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
            self.info(
                format!("re-saved '{pending}' (too late to move there unasked: go to it again)"),
                now,
            );
            return;
        }
        self.going_to(&pending);
        self.info(format!("re-saved '{pending}': moving there"), now);
        effects.push(Effect::Arm(ArmCommand::GoToPosition { name: pending }));
    }

    /// Anything but the operator's answer drops a pending go-to: only "yes" moves the arm.
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

    /// A failed position command (UNKNOWN_POSITION offers the re-save); returns whether told here.
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
                self.book.on_unknown_to_operator(&name);
                let text = if self.remembered_cartesian(&name).is_none() {
                    format!("the operator does not know '{name}' and no coordinates are remembered")
                } else if self.screen.overlay_is_none() && !self.keys.jog().is_jogging() {
                    self.screen
                        .show(Overlay::Confirm(Confirm::Resave(name.clone())));
                    format!("the operator does not know '{name}'")
                } else {
                    format!(
                        "the operator does not know '{name}': go to it again to re-save it from \
                         the remembered coordinates"
                    )
                };
                self.warn(text, now);
                true
            }
            _ => false,
        }
    }
}

/// After the first of `count` things said, how many more the log has.
fn and_more(count: usize) -> String {
    match count {
        0 | 1 => String::new(),
        n => format!(" (and {} more: see the log)", n - 1),
    }
}
