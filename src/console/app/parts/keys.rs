//! The keys: the jog engine, step mode, and the traces that keep auto-repeat and hasty keys
//! from being taken for new presses.

use std::time::{Duration, Instant};

use super::super::{Step, form_keys, question};
use crate::console::jog::{JogEngine, ReleaseMode};
use crate::console::keymap::KeyName;

/// The keys: the jog engine, step mode, and the traces that keep auto-repeat and hasty keys
/// from being taken for new presses.
#[derive(Debug, Clone)]
pub(in crate::console::app) struct Keys {
    pub(in crate::console::app) jog: JogEngine,
    pub(in crate::console::app) step: Step,
    /// The key that closed an overlay and when it was last seen: its auto-repeat must not be
    /// taken for new presses (and start a jog) once the overlay is gone.
    pub(in crate::console::app) swallowed: Option<(KeyName, Instant)>,
    /// The latest key event, and the key that opened the open form while its auto-repeat may
    /// still come: see `form_keys`.
    pub(in crate::console::app) last_key: Option<form_keys::KeyTrace>,
    pub(in crate::console::app) form_opener: Option<form_keys::FormOpener>,
    /// Keeps pasted and hasty keys from answering a question.
    pub(in crate::console::app) question_guard: question::QuestionGuard,
}

impl Keys {
    pub(in crate::console::app) fn new(release_mode: ReleaseMode, refresh: Duration) -> Keys {
        Keys {
            jog: JogEngine::new(release_mode, refresh),
            step: Step::default(),
            swallowed: None,
            last_key: None,
            form_opener: None,
            question_guard: question::QuestionGuard::default(),
        }
    }
}

