//! Key input faster than anyone types, in bulk: a paste in a terminal without bracketed paste,
//! or a flood. Past [`BURST_LIMIT`] bytes in one burst its keys are dropped until it ends.

use std::time::{Duration, Instant};

/// Reads this close together are one burst. Held keys repeat every 30 ms or more.
pub const BURST_GAP: Duration = Duration::from_millis(20);
/// More key bytes than this in one burst is a flood: no one types 4 KiB without a pause.
pub const BURST_LIMIT: usize = 4 * 1024;
/// A flood ends only after this long without input: a sender (or this reader) descheduled for
/// a moment on a loaded machine must not split one flood into several, each with its own 4 KiB
/// of keys let through and its own message.
pub const FLOOD_QUIET: Duration = Duration::from_millis(100);

/// What a read's keys are.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    Keys,
    /// This read made the burst a flood: its keys are dropped, and the console told once.
    FloodBegins,
    /// The flood goes on: its keys are dropped.
    Flooding,
}

/// The current burst of key bytes.
#[derive(Debug, Default)]
pub struct Burst {
    last_read: Option<Instant>,
    bytes: usize,
    flooding: bool,
}

impl Burst {
    /// A read of `key_bytes` key bytes at `now`.
    pub fn read(&mut self, key_bytes: usize, now: Instant) -> Verdict {
        let gap_ends_it = match self.flooding {
            true => FLOOD_QUIET,
            false => BURST_GAP,
        };
        let continues = self
            .last_read
            .is_some_and(|last| now.saturating_duration_since(last) <= gap_ends_it);
        if !continues {
            self.bytes = 0;
            self.flooding = false;
        }
        self.last_read = Some(now);
        self.bytes = self.bytes.saturating_add(key_bytes);
        match (self.flooding, self.bytes > BURST_LIMIT) {
            (true, _) => Verdict::Flooding,
            (false, true) => {
                self.flooding = true;
                Verdict::FloodBegins
            }
            (false, false) => Verdict::Keys,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn typing_is_keys_and_a_flood_is_dropped_until_a_pause() {
        let t0 = Instant::now();
        let mut burst = Burst::default();
        // Typing, a key every 40 ms, for longer than the limit in bytes.
        for i in 0..1000 {
            let at = t0 + Duration::from_millis(40 * i);
            assert_eq!(burst.read(10, at), Verdict::Keys);
        }
        let t1 = t0 + Duration::from_secs(60);
        assert_eq!(burst.read(BURST_LIMIT, t1), Verdict::Keys);
        assert_eq!(
            burst.read(1, t1 + Duration::from_millis(1)),
            Verdict::FloodBegins
        );
        assert_eq!(
            burst.read(1, t1 + Duration::from_millis(15)),
            Verdict::Flooding
        );
        let stalled = t1 + Duration::from_millis(15) + BURST_GAP * 3;
        assert_eq!(
            burst.read(1, stalled),
            Verdict::Flooding,
            "a stall longer than a burst's gap does not split a flood"
        );
        assert_eq!(
            burst.read(1, stalled + FLOOD_QUIET),
            Verdict::Flooding,
            "a gap of exactly the quiet still continues the flood"
        );
        let after = stalled + FLOOD_QUIET * 2 + Duration::from_millis(1);
        assert_eq!(burst.read(1, after), Verdict::Keys, "a pause ends it");
    }
}
