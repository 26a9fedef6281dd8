//! The keyboard's auto-repeat: its measured timing, and what tells a hold from taps.

use std::time::Duration;

/// Slowest onset in the field (X11: 660 ms) plus margin: a lone event's key then counts released.
pub const MAX_ONSET: Duration = Duration::from_millis(700);
/// The longest auto-repeat gap that can confirm a hold (8 Hz; the slowest common repeat is 11 Hz).
/// An event with no other within this gap either side is a tap.
pub const REPEAT_GAP_MAX: Duration = Duration::from_millis(125);
/// Events this close (12.5 Hz) for [`MAX_ONSET`] are a hold even without an onset pause.
const BURST_GAP_MAX: Duration = Duration::from_millis(80);
/// Assumed until measured: 11 Hz, the slowest common repeat (erring toward a held key).
pub const DEFAULT_INTERVAL: Duration = Duration::from_millis(91);
/// Repeats more than this many intervals late mean the key is up.
const INTERVALS_TO_RELEASE: u32 = 3;
/// Plausible repeat onsets; a longer pause before a run of repeats is not a hold.
const ONSET_RANGE: (Duration, Duration) = (Duration::from_millis(100), Duration::from_millis(1000));
/// Shorter gaps are key bounce or a burst, not a repeat interval worth measuring.
const INTERVAL_MIN: Duration = Duration::from_millis(10);

/// Auto-repeat timing measured from the keyboard.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct RepeatTiming {
    pub onset: Option<Duration>,
    pub interval: Option<Duration>,
}

impl RepeatTiming {
    /// The measured repeat interval, or [`DEFAULT_INTERVAL`] before one is measured.
    pub fn interval_or_default(&self) -> Duration {
        self.interval.unwrap_or(DEFAULT_INTERVAL)
    }

    /// How long after a lone event with no repeat yet the key counts as released.
    pub fn first_timeout(&self) -> Duration {
        match self.onset {
            Some(onset) => (onset + onset / 4 + Duration::from_millis(40)).min(MAX_ONSET),
            None => MAX_ONSET,
        }
    }

    /// How long after a repeat, with no further one, the key counts as released.
    pub fn repeat_timeout(&self) -> Duration {
        self.interval_or_default() * INTERVALS_TO_RELEASE
    }

    pub(super) fn sample_onset(&mut self, d: Duration) {
        if (ONSET_RANGE.0..=ONSET_RANGE.1).contains(&d) {
            self.onset = Some(average(self.onset, d));
        }
    }

    pub(super) fn sample_interval(&mut self, d: Duration) {
        if (INTERVAL_MIN..REPEAT_GAP_MAX).contains(&d) {
            self.interval = Some(average(self.interval, d));
        }
    }

    /// Whether a run of a key's closely spaced events is auto-repeat rather than taps: `onset` is
    /// the pause before it (`None` from the first event), `span` its length, `previous` and `last`
    /// its last two gaps.
    pub(super) fn confirms_hold(
        &self,
        onset: Option<Duration>,
        span: Duration,
        previous: Option<Duration>,
        last: Duration,
    ) -> bool {
        let regular = previous.is_some_and(|previous| {
            let (low, high) = (previous.min(last), previous.max(last));
            high - low <= high / 2 + Duration::from_millis(10)
        });
        let Some(onset) = onset else {
            // No pause before the run: only a run too fast and long for a finger is a hold.
            return regular && last <= BURST_GAP_MAX && span >= MAX_ONSET;
        };
        if !(ONSET_RANGE.0..=ONSET_RANGE.1).contains(&onset) || onset < last * 2 {
            return false;
        }
        // A measured keyboard: a repeat about an onset after the pause, the next an interval later.
        if let (Some(measured_onset), Some(measured_interval)) = (self.onset, self.interval) {
            let onset_matches =
                onset.abs_diff(measured_onset) <= measured_onset / 4 + Duration::from_millis(30);
            if onset_matches && last <= measured_interval * 2 + Duration::from_millis(10) {
                return true;
            }
        }
        // Otherwise two short gaps in a row that agree.
        regular
    }
}

/// Exponential moving average, weight 1/4 on the new sample.
fn average(old: Option<Duration>, new: Duration) -> Duration {
    match old {
        Some(old) => (old * 3 + new) / 4,
        None => new,
    }
}
