//! Pasted text is text, never keys: an open form takes it (cut to the field's limit), anything
//! else ignores it with one message. Input the reader refused stops the arm: keys (a release,
//! a STOP) may have been among what was dropped.

use std::time::Instant;

use super::{App, Effect, Severity};
use crate::console::form::FormPaste;

/// A bracketed paste, or input dropped unread.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Pasted {
    Text(String),
    /// Why it was dropped, in words (`paste ignored: …`).
    Refused(String),
}

impl App {
    pub(super) fn on_paste(&mut self, pasted: Pasted, now: Instant, effects: &mut Vec<Effect>) {
        let text = match pasted {
            Pasted::Refused(why) => {
                self.stop_everything(now, effects);
                self.say(format!("{why}; stopped"), Severity::Warning, now);
                return;
            }
            Pasted::Text(text) => text,
        };
        let Some(form) = self.screen.form_mut() else {
            self.say(
                "paste ignored: pasted text is never keys",
                Severity::Info,
                now,
            );
            return;
        };
        match form.paste(&text) {
            FormPaste::Inserted => {}
            FormPaste::Cut { limit } => self.say(
                format!("pasted text cut to the field's {limit}-byte limit"),
                Severity::Warning,
                now,
            ),
            FormPaste::Toggle => self.say(
                "paste ignored: this field is a yes/no toggle",
                Severity::Info,
                now,
            ),
        }
    }
}
