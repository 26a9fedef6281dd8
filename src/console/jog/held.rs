//! One held jog key: its state, the rhythm of its events, and when it counts as released.

use std::time::{Duration, Instant};

use super::timing::{REPEAT_GAP_MAX, RepeatTiming};
use super::{JogMotion, ReleaseMode, unit_motion};
use crate::console::action::{JogAxis, JogFamily};

/// A key silent this long with reported releases is stopped: the terminal must prove it.
pub const KEY_EVENT_TIMEOUT: Duration = Duration::from_secs(1);
/// Fallback: a latched key's repeats end at a pause of this and three intervals.
const LATCH_SILENCE_MIN: Duration = Duration::from_millis(250);
/// Reported releases: repeats stopped this many intervals (at least [`STALE_MIN`]) mean released.
const STALE_INTERVALS: u32 = 6;
const STALE_MIN: Duration = Duration::from_millis(500);

/// What a held key does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum KeyState {
    /// Fallback: down, not yet known to be held (a tap's step may be due).
    Pending,
    /// Takes part in the motion.
    Moving,
    /// Down since before a stop: never moves until released and pressed again.
    Latched,
}

#[derive(Debug, Clone, Copy)]
pub(super) struct Held {
    pub(super) axis: JogAxis,
    pub(super) direction: i8,
    pub(super) state: KeyState,
    pub(super) last_event: Instant,
    /// Events after the first.
    pub(super) repeats: u32,
    /// The pause before the current run (the onset); `None` if it began with the first event.
    pub(super) run_onset: Option<Duration>,
    /// The first event of the current run.
    pub(super) run_start: Instant,
    /// The last two gaps inside the current run, oldest first.
    pub(super) run_gaps: (Option<Duration>, Option<Duration>),
    /// A tap's step, due at this instant unless another event of the key comes first.
    pub(super) step_due: Option<Instant>,
    /// Order of press or confirmation, to pick the family when several move.
    pub(super) order: u64,
}

impl Held {
    pub(super) fn new(axis: JogAxis, direction: i8, state: KeyState, now: Instant) -> Held {
        Held {
            axis,
            direction,
            state,
            last_event: now,
            repeats: 0,
            run_onset: None,
            run_start: now,
            run_gaps: (None, None),
            step_due: None,
            order: 0,
        }
    }

    /// Records one more event of the key; returns the gap since the previous one.
    pub(super) fn record(&mut self, now: Instant) -> Duration {
        let gap = now.saturating_duration_since(self.last_event);
        if gap < REPEAT_GAP_MAX {
            self.run_gaps = (self.run_gaps.1, Some(gap));
        } else {
            self.run_onset = Some(gap);
            self.run_start = now;
            self.run_gaps = (None, None);
        }
        self.repeats += 1;
        self.last_event = now;
        gap
    }

    pub(super) fn run_span(&self) -> Duration {
        self.last_event.saturating_duration_since(self.run_start)
    }

    /// Whether a tap of this key moves a step: only cartesian keys have a bounded one.
    pub(super) fn steps(&self) -> bool {
        self.axis.family() == JogFamily::Cartesian
    }

    /// Whether the key's last event stood alone (a press or a tap), not in a run of repeats.
    pub(super) fn last_event_alone(&self) -> bool {
        self.run_gaps.1.is_none()
    }

    pub(super) fn latch(&mut self) {
        self.state = KeyState::Latched;
        self.step_due = None;
    }

    /// The unit motion of this key alone, for a tap's step.
    pub(super) fn unit_motion(&self, joint: u8) -> JogMotion {
        unit_motion(self.axis, self.direction, joint)
    }
}

/// When a held key counts as released (or unproven) if no further event comes.
pub(super) fn expiry(mode: ReleaseMode, timing: &RepeatTiming, held: &Held) -> Instant {
    let silence = match (mode, held.state) {
        (ReleaseMode::AutoRepeat, KeyState::Moving) => timing.repeat_timeout(),
        // Next repeat due within an interval; a latch errs on holding on.
        (ReleaseMode::AutoRepeat, KeyState::Latched) if !held.last_event_alone() => {
            timing.repeat_timeout().max(LATCH_SILENCE_MIN)
        }
        (ReleaseMode::AutoRepeat, _) if !held.last_event_alone() => timing.repeat_timeout(),
        (ReleaseMode::AutoRepeat, _) => timing.first_timeout(),
        // Repeats that stop for long mean released, in case the release event was lost.
        (ReleaseMode::Reported, KeyState::Moving) => match timing.interval {
            Some(interval) if held.repeats > 0 => {
                (interval * STALE_INTERVALS).clamp(STALE_MIN, KEY_EVENT_TIMEOUT)
            }
            _ => KEY_EVENT_TIMEOUT,
        },
        (ReleaseMode::Reported, _) => KEY_EVENT_TIMEOUT,
    };
    held.last_event + silence
}
