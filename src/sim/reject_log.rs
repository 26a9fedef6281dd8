//! Rejected frames logged per connection, [`PER_WINDOW`] a second, then a summary.

use std::fmt;
use std::net::SocketAddr;
use std::time::{Duration, Instant};

/// Rejections logged in full per window.
pub const PER_WINDOW: u32 = 20;
/// The window of the limit.
pub const WINDOW: Duration = Duration::from_secs(1);

/// What to do with one rejection.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Admission {
    /// Log this rejection in full.
    pub log: bool,
    /// Rejections suppressed in the window that just ended, to report first.
    pub suppressed_before: Option<u64>,
}

/// A pure rate limit on log lines; a window opens at the first event after the last one ended.
#[derive(Debug, Clone)]
pub struct RateLimit {
    per_window: u32,
    window: Duration,
    opened: Option<Instant>,
    logged: u32,
    suppressed: u64,
}

impl RateLimit {
    pub fn new(per_window: u32, window: Duration) -> RateLimit {
        RateLimit {
            per_window,
            window,
            opened: None,
            logged: 0,
            suppressed: 0,
        }
    }

    /// One event at `now`.
    pub fn admit(&mut self, now: Instant) -> Admission {
        let suppressed_before = self.poll(now);
        if self.opened.is_none() {
            self.opened = Some(now);
        }
        let log = self.logged < self.per_window;
        if log {
            self.logged += 1;
        } else {
            self.suppressed = self.suppressed.saturating_add(1);
        }
        Admission {
            log,
            suppressed_before,
        }
    }

    /// Ends the window if it is over at `now`, returning how many events it suppressed (if any).
    pub fn poll(&mut self, now: Instant) -> Option<u64> {
        let over = self
            .opened
            .is_some_and(|opened| now.saturating_duration_since(opened) >= self.window);
        if !over {
            return None;
        }
        self.opened = None;
        self.logged = 0;
        self.take_suppressed()
    }

    /// How many events were suppressed and not yet reported (at the end of a connection).
    pub fn finish(&mut self) -> Option<u64> {
        self.take_suppressed()
    }

    fn take_suppressed(&mut self) -> Option<u64> {
        let n = std::mem::take(&mut self.suppressed);
        (n > 0).then_some(n)
    }
}

/// One Talos connection's rejected-frame log, at info with peer and reason, rate-limited.
#[derive(Debug, Clone)]
pub struct RejectLog {
    peer: SocketAddr,
    limit: RateLimit,
}

impl RejectLog {
    pub fn new(peer: SocketAddr) -> RejectLog {
        RejectLog {
            peer,
            limit: RateLimit::new(PER_WINDOW, WINDOW),
        }
    }

    pub fn rejected(&mut self, now: Instant, reason: impl fmt::Display) {
        let admission = self.limit.admit(now);
        if let Some(n) = admission.suppressed_before {
            self.summary(n);
        }
        if admission.log {
            tracing::info!("sim talos: rejected a frame from {}: {reason}", self.peer);
        }
    }

    /// Reports the suppressed rejections of a window that has ended (call on any activity).
    pub fn poll(&mut self, now: Instant) {
        if let Some(n) = self.limit.poll(now) {
            self.summary(n);
        }
    }

    /// Reports what is still suppressed: the connection has ended.
    pub fn finish(&mut self) {
        if let Some(n) = self.limit.finish() {
            self.summary(n);
        }
    }

    fn summary(&self, n: u64) {
        tracing::info!(
            "sim talos: {n} more rejected frames from {} suppressed",
            self.peer
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ms(t0: Instant, ms: u64) -> Instant {
        t0 + Duration::from_millis(ms)
    }

    #[test]
    fn the_first_twenty_a_second_are_logged_then_one_summary_per_second() {
        let t0 = Instant::now();
        let mut limit = RateLimit::new(20, Duration::from_secs(1));
        // A flood of 100 rejections in the first 500 ms.
        let admitted: Vec<Admission> = (0..100).map(|i| limit.admit(ms(t0, i * 5))).collect();
        assert_eq!(admitted.iter().filter(|a| a.log).count(), 20);
        assert!(admitted[..20].iter().all(|a| a.log));
        assert!(admitted.iter().all(|a| a.suppressed_before.is_none()));
        // Nothing to report before the second is over, then the 80 once.
        assert_eq!(limit.poll(ms(t0, 999)), None);
        assert_eq!(limit.poll(ms(t0, 1000)), Some(80));
        assert_eq!(limit.poll(ms(t0, 1500)), None);
        // The next second starts afresh.
        let next = limit.admit(ms(t0, 2000));
        assert_eq!(
            next,
            Admission {
                log: true,
                suppressed_before: None
            }
        );
    }

    #[test]
    fn a_rejection_after_the_window_carries_the_summary_and_is_logged() {
        let t0 = Instant::now();
        let mut limit = RateLimit::new(2, Duration::from_secs(1));
        for i in 0..5 {
            limit.admit(ms(t0, i));
        }
        let later = limit.admit(ms(t0, 1200));
        assert_eq!(
            later,
            Admission {
                log: true,
                suppressed_before: Some(3)
            }
        );
    }

    #[test]
    fn finish_reports_what_is_left_once() {
        let t0 = Instant::now();
        let mut limit = RateLimit::new(1, Duration::from_secs(1));
        limit.admit(t0);
        assert_eq!(limit.finish(), None, "nothing suppressed yet");
        limit.admit(t0);
        limit.admit(t0);
        assert_eq!(limit.finish(), Some(2));
        assert_eq!(limit.finish(), None);
    }

    #[test]
    fn a_slow_trickle_is_always_logged() {
        let t0 = Instant::now();
        let mut limit = RateLimit::new(20, Duration::from_secs(1));
        assert!((0..100).all(|i| limit.admit(ms(t0, i * 100)).log));
    }
}
