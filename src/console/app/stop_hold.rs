//! The technician's STOP holds: for [`STOP_HOLD`] after space (or quick stop), telemetry showing
//! the arm moving sends STOP again, at most every [`RESEND_EVERY`]. Another client's refresh can
//! restart the arm just after our STOP, leaving it nothing to see; a STOP sent again lands at
//! another moment, where that client sees it.

use std::time::{Duration, Instant};

/// How long after the technician's STOP motion seen in the telemetry is stopped again.
pub const STOP_HOLD: Duration = Duration::from_secs(1);
/// At most one STOP sent again per this: a poll or three at 30 Hz.
pub const RESEND_EVERY: Duration = Duration::from_millis(100);
/// Motion this long after the STOP is not slowing down under it: the message line says so.
pub const SLOWING_DOWN: Duration = Duration::from_millis(300);

#[derive(Debug, Clone, Default)]
pub struct StopHold {
    /// When the STOP went out, until when it holds, and when a STOP last went out for it.
    since: Option<Instant>,
    until: Option<Instant>,
    last_sent: Option<Instant>,
    /// STOPs sent again in all, for the tests and the log.
    resent: u64,
}

impl StopHold {
    /// STOPs this console sent again because the arm moved after its STOP.
    pub fn resent(&self) -> u64 {
        self.resent
    }

    pub(super) fn arm(&mut self, now: Instant) {
        self.since = Some(now);
        self.until = Some(now + STOP_HOLD);
        self.last_sent = Some(now);
    }

    /// Our own motion starts: the arm moving is then ours.
    pub(super) fn release(&mut self) {
        self.until = None;
    }

    /// Whether a sample showing the arm `moving` at `now` sends STOP again.
    pub(super) fn resend(&mut self, moving: bool, now: Instant) -> bool {
        let held = self.until.is_some_and(|until| now < until);
        let due = self.last_sent.is_none_or(|at| now >= at + RESEND_EVERY);
        if !(held && moving && due) {
            return false;
        }
        self.last_sent = Some(now);
        self.resent += 1;
        true
    }

    /// Whether motion at `now` is past the arm slowing down under the STOP: then it is said.
    pub(super) fn past_slowing_down(&self, now: Instant) -> bool {
        self.since.is_some_and(|since| now >= since + SLOWING_DOWN)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn motion_within_the_hold_is_stopped_again_at_most_every_resend_period() {
        let t0 = Instant::now();
        let mut hold = StopHold::default();
        assert!(!hold.resend(true, t0), "no STOP held");
        hold.arm(t0);
        assert!(
            !hold.resend(true, t0 + RESEND_EVERY / 2),
            "too soon after the STOP"
        );
        assert!(hold.resend(true, t0 + RESEND_EVERY));
        assert!(!hold.resend(true, t0 + RESEND_EVERY + Duration::from_millis(33)));
        assert!(!hold.resend(false, t0 + 3 * RESEND_EVERY), "at rest");
        assert!(hold.resend(true, t0 + 3 * RESEND_EVERY));
        assert!(!hold.resend(true, t0 + STOP_HOLD), "the hold is over");
        assert!(!hold.past_slowing_down(t0 + SLOWING_DOWN / 2));
        assert!(hold.past_slowing_down(t0 + SLOWING_DOWN));
        assert_eq!(hold.resent(), 2);
    }

    #[test]
    fn our_own_motion_releases_the_hold() {
        let t0 = Instant::now();
        let mut hold = StopHold::default();
        hold.arm(t0);
        hold.release();
        assert!(!hold.resend(true, t0 + RESEND_EVERY));
    }
}
