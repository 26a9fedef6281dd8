//! How old the link and telemetry are, and the next instant the screen changes without input.

use std::time::{Duration, Instant};

use super::{ACTION_TIMEOUT, MotionTruth, NO_TELEMETRY_ACTION_TIME, STALE_AFTER, STOP_GRACE};
use crate::console::app::age::AGE_TENTHS_UNTIL;

impl MotionTruth {
    /// Telemetry is old after 500 ms, or three of the link's shortest recent intervals if slower.
    pub fn stale_after(&self) -> Duration {
        let period = self.intervals.iter().min().copied().unwrap_or_default();
        STALE_AFTER.max(period * 3)
    }

    /// How long a tracked action is watched: with telemetry until it times out, without it until
    /// it is taken as ended.
    pub(super) fn action_time_limit(&self) -> Duration {
        if self.expects_telemetry() {
            ACTION_TIMEOUT
        } else {
            NO_TELEMETRY_ACTION_TIME
        }
    }

    /// How long the link has been silent past its limit, if it has.
    pub(super) fn stale_for(&self, now: Instant) -> Option<Duration> {
        self.expect?;
        let mut age = None;
        if self.expects_telemetry()
            && let Some(since) = self.telemetry_at.max(self.link_up_at)
        {
            let silent = now.saturating_duration_since(since);
            age = (silent >= self.stale_after()).then_some(silent);
        }
        if let Some(since) = self.waiting_since {
            let silent = now.saturating_duration_since(since);
            if silent >= STALE_AFTER {
                age = age.max(Some(silent));
            }
        }
        age
    }

    /// The next instant something shown changes without any input.
    pub(super) fn next_deadline(&self, now: Instant, link_up: bool) -> Option<Instant> {
        // The earliest instant after `now` (a fold, not a `Vec`: this runs every turn).
        let mut next: Option<Instant> = None;
        let mut candidate = |at: Instant| {
            if at > now {
                next = Some(next.map_or(at, |next| next.min(at)));
            }
        };
        if link_up && self.expect.is_some() {
            if self.expects_telemetry()
                && let Some(since) = self.telemetry_at.max(self.link_up_at)
            {
                candidate(since + self.stale_after());
            }
            if let Some(since) = self.waiting_since {
                candidate(since + STALE_AFTER);
            }
        }
        // The shown ages count up while anything is old: in tenths, then whole seconds.
        let telemetry_age = self
            .telemetry_at
            .map(|at| now.saturating_duration_since(at))
            .filter(|age| *age >= self.stale_after());
        let link_age = self.stale_for(now).filter(|_| link_up);
        if let Some(age) = telemetry_age.max(link_age) {
            let step = if age < AGE_TENTHS_UNTIL {
                Duration::from_millis(100)
            } else {
                Duration::from_secs(1)
            };
            candidate(now + step);
        }
        if let Some(at) = self.stop_sent {
            candidate(at + STOP_GRACE);
        }
        if let Some(at) = self.stop_confirmed_at {
            candidate(at + STOP_GRACE);
        }
        if let Some(action) = &self.action {
            candidate(action.sent + self.action_time_limit());
        }
        next
    }
}
