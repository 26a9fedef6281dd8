//! The keys: the jog engine, step mode, and traces that keep auto-repeat and hasty keys from being
//! taken for presses. In an open form every keystroke is text except the auto-repeat of the key
//! that opened it; in the fallback that is only an event continuing its run (within
//! [`CONTINUES_RUN`] repeat intervals).

use std::time::{Duration, Instant};

use super::super::question::QuestionGuard;
use super::super::{KeyInput, Overlay, Step};
use crate::console::jog::{JogEngine, KeyKind, MAX_ONSET, ReleaseMode, RepeatTiming};
use crate::console::keymap::KeyName;

/// Within this many repeat intervals a same-key event continues a run (a keystroke is slower).
const CONTINUES_RUN: (u32, u32) = (3, 2);

/// A key and its latest event, to tell whether the next one continues its auto-repeat run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct KeyTrace {
    key: KeyName,
    at: Instant,
}

impl KeyTrace {
    fn new(key: KeyName, at: Instant) -> KeyTrace {
        KeyTrace { key, at }
    }
}

#[derive(Debug, Clone)]
pub(in crate::console::app) struct Keys {
    jog: JogEngine,
    step: Step,
    /// The key that closed an overlay, last seen: its auto-repeat must not start a jog.
    swallowed: Option<(KeyName, Instant)>,
    /// The latest key event, and the form opener while its auto-repeat may come (fallback: the
    /// run continues from its latest event).
    last_key: Option<KeyTrace>,
    form_opener: Option<KeyTrace>,
    /// Keeps pasted and hasty keys from answering a question.
    question_guard: QuestionGuard,
}

/// What the keys show: the jog engine's mode and joint, the step.
#[derive(Debug, Clone, PartialEq)]
pub struct KeysView {
    pub release_mode: ReleaseMode,
    /// The measured auto-repeat timing (auto-repeat fallback).
    pub repeat_timing: RepeatTiming,
    /// The joint a single-joint jog moves (1 to 7).
    pub joint: u8,
    pub step: Step,
}

impl Keys {
    pub(in crate::console::app) fn new(release_mode: ReleaseMode, refresh: Duration) -> Keys {
        Keys {
            jog: JogEngine::new(release_mode, refresh),
            step: Step::default(),
            swallowed: None,
            last_key: None,
            form_opener: None,
            question_guard: QuestionGuard::default(),
        }
    }

    pub(in crate::console::app) fn jog(&self) -> &JogEngine {
        &self.jog
    }

    /// The jog engine, to feed it the jog keys and ticks (it keeps its own state private).
    pub(in crate::console::app) fn jog_mut(&mut self) -> &mut JogEngine {
        &mut self.jog
    }

    pub(in crate::console::app) fn step(&self) -> Step {
        self.step
    }

    /// Step mode on or off; whether it is now on.
    pub(in crate::console::app) fn on_toggle_step(&mut self) -> bool {
        self.step.enabled = !self.step.enabled;
        self.step.enabled
    }

    pub(in crate::console::app) fn on_step_size(&mut self, bigger: bool) {
        self.step.resize(bigger);
    }

    /// How close an event of the same key must follow its previous one to continue a run.
    fn run_window(&self) -> Duration {
        let (num, den) = CONTINUES_RUN;
        self.jog.timing().interval_or_default() * num / den
    }

    /// Records a press or repeat; returns whether it continued the same key's run.
    pub(in crate::console::app) fn trace_key(&mut self, key: &KeyInput, now: Instant) -> bool {
        if key.kind == KeyKind::Release {
            if self.last_key.is_some_and(|t| t.key == key.key) {
                self.last_key = None;
            }
            if self.form_opener.is_some_and(|o| o.key == key.key) {
                self.form_opener = None;
            }
            return false;
        }
        let window = self.run_window();
        let continues = key.kind == KeyKind::Repeat
            || self
                .last_key
                .is_some_and(|t| t.key == key.key && now.saturating_duration_since(t.at) <= window);
        self.last_key = Some(KeyTrace::new(key.key, now));
        continues
    }

    /// A press or repeat at `now`: whether it came in a burst (see `question`).
    pub(in crate::console::app) fn burst(&mut self, now: Instant) -> bool {
        self.question_guard.key(now)
    }

    /// Why a key at `now` may not answer the open question, if it may not.
    pub(in crate::console::app) fn question_refusal(
        &self,
        burst: bool,
        now: Instant,
    ) -> Option<&'static str> {
        self.question_guard.refuses(burst, now)
    }

    /// After each input: a question that has just opened is timed from now.
    pub(in crate::console::app) fn note_overlay(&mut self, overlay: &Overlay, now: Instant) {
        self.question_guard.note(overlay, now);
    }

    /// `key` just opened or closed a non-form overlay: its auto-repeat is swallowed.
    pub(in crate::console::app) fn swallow(&mut self, key: &KeyInput, now: Instant) {
        self.swallowed = Some((key.key, now));
    }

    /// A form was opened by `key`: remember it if its auto-repeat may follow.
    pub(in crate::console::app) fn form_opened_by(
        &mut self,
        key: &KeyInput,
        repeating: bool,
        now: Instant,
    ) {
        // A key that closed an earlier overlay has no say in the form: its next press is text.
        self.swallowed = None;
        let remember = self.jog.mode() == ReleaseMode::Reported || repeating;
        self.form_opener = remember.then_some(KeyTrace::new(key.key, now));
    }

    /// Whether `key` repeats the form's opener (not text); any other event ends that run.
    pub(in crate::console::app) fn repeat_of_form_opener(
        &mut self,
        key: &KeyInput,
        form_open: bool,
        now: Instant,
    ) -> bool {
        if !form_open {
            self.form_opener = None;
            return false;
        }
        let Some(opener) = self.form_opener else {
            return false;
        };
        let repeat = opener.key == key.key
            && match (self.jog.mode(), key.kind) {
                (_, KeyKind::Repeat) => true,
                (ReleaseMode::AutoRepeat, KeyKind::Press) => {
                    now.saturating_duration_since(opener.at) <= self.run_window()
                }
                _ => false,
            };
        self.form_opener = repeat.then_some(KeyTrace::new(opener.key, now));
        repeat
    }

    /// Whether `key` repeats the key that just opened or closed an overlay: holding `h` must not
    /// cancel the home question, nor `w` held to close the help start a jog.
    pub(in crate::console::app) fn auto_repeat_of_overlay_key(
        &mut self,
        key: &KeyInput,
        overlay: &Overlay,
        now: Instant,
    ) -> bool {
        let form = matches!(overlay, Overlay::Form(_));
        if key.kind == KeyKind::Repeat && *overlay != Overlay::None && !form {
            return true;
        }
        let Some((held, seen)) = self.swallowed else {
            return false;
        };
        let repeating = held == key.key
            && key.kind == KeyKind::Press
            && self.jog.mode() == ReleaseMode::AutoRepeat
            && now.saturating_duration_since(seen) < MAX_ONSET;
        self.swallowed = repeating.then_some((held, now));
        repeating
    }

    pub(in crate::console::app) fn view(&self) -> KeysView {
        KeysView {
            release_mode: self.jog.mode(),
            repeat_timing: self.jog.timing(),
            joint: self.jog.joint(),
            step: self.step,
        }
    }
}
