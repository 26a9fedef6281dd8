//! What a write of the book found another writer (a second console, a hand edit) had put in
//! the file since: merged in by the writer (`positions::shared`), told here. A position both
//! changed is kept twice, the other program's under its name and this console's beside it
//! (`pick~2`); the technician is asked whether this console's should have the name instead.

use std::time::Instant;

use super::{App, Effect, Overlay, Severity};
use crate::console::form::Confirm;
use crate::console::positions::merge::Kept;
use crate::console::positions::shared::Written;

impl App {
    /// A write found another writer's changes: a name changed on both sides is a warning naming
    /// it (and a question, when nothing else is going on), as are entries of the file set
    /// aside; what was merged in is said.
    pub(super) fn tell_found(&mut self, written: &Written, now: Instant) {
        for conflict in &written.conflicts {
            tracing::warn!("positions: {}", conflict.describe());
        }
        for note in &written.notes {
            tracing::warn!("positions file: {note}");
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
        } else if written.taken > 0 {
            let text = format!(
                "positions file changed by another program: {} change(s) merged in, nothing lost",
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
