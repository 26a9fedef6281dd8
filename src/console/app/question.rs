//! A question is answered by a person: no key within [`QUESTION_QUIET`] nor in a burst.

use std::time::{Duration, Instant};

use super::Overlay;
use crate::console::form::Confirm;

/// How long a new question ignores keys.
pub const QUESTION_QUIET: Duration = Duration::from_millis(150);
/// Keys this close together were not typed one by one.
pub const BURST_KEY_GAP: Duration = Duration::from_millis(5);

#[derive(Debug, Clone, Default)]
pub(super) struct QuestionGuard {
    /// The question open and when it opened.
    asked: Option<(Confirm, Instant)>,
    previous_key: Option<Instant>,
}

impl QuestionGuard {
    /// After each input: a question that has just opened is timed from now.
    pub(super) fn note(&mut self, overlay: &Overlay, now: Instant) {
        self.asked = match (overlay, self.asked.take()) {
            (Overlay::Confirm(open), Some((asked, at))) if *open == asked => Some((asked, at)),
            (Overlay::Confirm(open), _) => Some((open.clone(), now)),
            _ => None,
        };
    }

    /// A press or repeat at `now`: whether it came in a burst.
    pub(super) fn key(&mut self, now: Instant) -> bool {
        self.previous_key
            .replace(now)
            .is_some_and(|previous| now.saturating_duration_since(previous) < BURST_KEY_GAP)
    }

    /// Why a key at `now` (`burst`: [`QuestionGuard::key`]) may not answer the question, if so.
    pub(super) fn refuses(&self, burst: bool, now: Instant) -> Option<&'static str> {
        let (_, asked) = self.asked.as_ref()?;
        if now.saturating_duration_since(*asked) < QUESTION_QUIET {
            Some("key ignored: the question has only just opened")
        } else if burst {
            Some("key ignored: keys came too fast to be typed")
        } else {
            None
        }
    }
}
