//! Keystrokes into an open form: every one is text, except the auto-repeat of a key that was
//! already held, repeating, when it opened the form.
//!
//! With reported key events a repeat says so itself. In the auto-repeat fallback a repeat looks
//! like a press, so only an event of the opening key that continues its run (within
//! [`CONTINUES_RUN`] repeat intervals of that key's previous event) is taken for a repeat; a
//! fresh keystroke, even of the same key, is text.

use std::time::{Duration, Instant};

use super::{App, KeyInput};
use crate::console::jog::{KeyKind, ReleaseMode};
use crate::console::keymap::KeyName;

/// An event of the same key this many repeat intervals after its previous one continues an
/// auto-repeat run (the keyboard's interval jitters; a second keystroke is slower).
const CONTINUES_RUN: (u32, u32) = (3, 2);

/// The latest key event, to tell whether the next one continues its auto-repeat run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct KeyTrace {
    key: KeyName,
    at: Instant,
}

/// The key that opened the form, while its auto-repeat may still arrive.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct FormOpener {
    key: KeyName,
    /// Its latest event (fallback: the run continues from here).
    last: Instant,
}

impl App {
    /// How close an event of the same key must follow its previous one to continue a run.
    fn run_window(&self) -> Duration {
        let (num, den) = CONTINUES_RUN;
        self.keys.jog.timing().interval_or_default() * num / den
    }

    /// Records a press or repeat; returns whether it continued the previous event's run of the
    /// same key (a key already repeating).
    pub(super) fn trace_key(&mut self, key: &KeyInput, now: Instant) -> bool {
        if key.kind == KeyKind::Release {
            if self.keys.last_key.is_some_and(|t| t.key == key.key) {
                self.keys.last_key = None;
            }
            if self.keys.form_opener.is_some_and(|o| o.key == key.key) {
                self.keys.form_opener = None;
            }
            return false;
        }
        let window = self.run_window();
        let continues = key.kind == KeyKind::Repeat
            || self
                .keys
                .last_key
                .is_some_and(|t| t.key == key.key && now.saturating_duration_since(t.at) <= window);
        self.keys.last_key = Some(KeyTrace {
            key: key.key,
            at: now,
        });
        continues
    }

    /// A form was just opened by `key`: remember it if its auto-repeat may follow. With reported
    /// events that is any key (its repeats say so); in the fallback only a key that was already
    /// repeating, since a fresh press's next event may be a keystroke.
    pub(super) fn form_opened_by(&mut self, key: &KeyInput, repeating: bool, now: Instant) {
        // A key that closed an earlier overlay has no say in the form: its next press is text.
        self.keys.swallowed = None;
        let remember = match self.keys.jog.mode() {
            ReleaseMode::Reported => true,
            ReleaseMode::AutoRepeat => repeating,
        };
        self.keys.form_opener = remember.then_some(FormOpener {
            key: key.key,
            last: now,
        });
    }

    /// Whether `key` is the auto-repeat of the key that opened the open form, and so not text.
    /// Any other event ends the opener's run: after it, every keystroke is text.
    pub(super) fn repeat_of_form_opener(&mut self, key: &KeyInput, now: Instant) -> bool {
        if !self.screen.form_open() {
            self.keys.form_opener = None;
            return false;
        }
        let Some(opener) = self.keys.form_opener else {
            return false;
        };
        let repeat = opener.key == key.key
            && match (self.keys.jog.mode(), key.kind) {
                (_, KeyKind::Repeat) => true,
                (ReleaseMode::AutoRepeat, KeyKind::Press) => {
                    now.saturating_duration_since(opener.last) <= self.run_window()
                }
                _ => false,
            };
        self.keys.form_opener = repeat.then_some(FormOpener {
            key: opener.key,
            last: now,
        });
        repeat
    }
}
