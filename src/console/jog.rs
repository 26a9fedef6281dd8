//! Hold-to-jog: which jog keys are held, what motion that makes, and when to re-send or stop.
//!
//! Pure and clocked from outside: every call takes `now`. Two ways to know a key is held:
//! - [`ReleaseMode::Reported`]: the terminal reports releases (kitty keyboard protocol).
//! - [`ReleaseMode::AutoRepeat`]: it does not (tmux, VTE, xterm, the Linux console), so a key
//!   counts as held while its auto-repeat keeps arriving. The repeat onset and interval are
//!   measured at run time; a key is released about three intervals after its last repeat, and no
//!   later than the slowest plausible onset after a single press.
//!
//! The engine never starts motion by itself: only a key press does.

use std::collections::BTreeMap;
use std::time::{Duration, Instant};

use super::action::{Action, JogAxis, JogFamily};

/// How key releases are known.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReleaseMode {
    Reported,
    AutoRepeat,
}

/// The kind of a key event as the engine needs it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KeyKind {
    Press,
    Repeat,
    Release,
}

/// The motion the held keys ask for. Directions are -1, 0 or 1.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JogMotion {
    Cartesian {
        x: i8,
        y: i8,
        z: i8,
    },
    Polar {
        azimuth: i8,
        altitude: i8,
    },
    /// Joint 1..=7.
    Joint {
        joint: u8,
        direction: i8,
    },
}

/// What the engine wants sent.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JogEffect {
    /// Start, change or refresh continuous motion.
    Start(JogMotion),
    /// Stop all continuous motion.
    Stop,
}

/// Slowest auto-repeat onset in the field (X11: 660 ms) plus margin: the longest a single tap
/// can keep the arm moving in the fallback mode before any repeat was measured.
pub const MAX_ONSET: Duration = Duration::from_millis(700);
/// Repeat interval assumed before one is measured (Linux console, 11 Hz).
const DEFAULT_INTERVAL: Duration = Duration::from_millis(91);
/// Repeats more than this many intervals late mean the key is up.
const INTERVALS_TO_RELEASE: u32 = 3;
/// Plausible measurements; anything else is a separate press, not a repeat.
const ONSET_RANGE: (Duration, Duration) = (Duration::from_millis(100), Duration::from_millis(1000));
const INTERVAL_RANGE: (Duration, Duration) =
    (Duration::from_millis(10), Duration::from_millis(300));
/// With reported releases, a key whose repeats stop for this many intervals (and at least
/// [`STALE_MIN`]) is treated as released: a guard against a lost release event.
const STALE_INTERVALS: u32 = 6;
const STALE_MIN: Duration = Duration::from_millis(500);

/// Auto-repeat timing measured from the keyboard.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct RepeatTiming {
    pub onset: Option<Duration>,
    pub interval: Option<Duration>,
}

impl RepeatTiming {
    fn interval_or_default(&self) -> Duration {
        self.interval.unwrap_or(DEFAULT_INTERVAL)
    }

    /// How long after a press, with no repeat yet, the key counts as released.
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

    fn sample_onset(&mut self, d: Duration) {
        if (ONSET_RANGE.0..=ONSET_RANGE.1).contains(&d) {
            self.onset = Some(average(self.onset, d));
        }
    }

    fn sample_interval(&mut self, d: Duration) {
        if (INTERVAL_RANGE.0..=INTERVAL_RANGE.1).contains(&d) {
            self.interval = Some(average(self.interval, d));
        }
    }
}

/// Exponential moving average, weight 1/4 on the new sample.
fn average(old: Option<Duration>, new: Duration) -> Duration {
    match old {
        Some(old) => (old * 3 + new) / 4,
        None => new,
    }
}

#[derive(Debug, Clone, Copy)]
struct Held {
    axis: JogAxis,
    direction: i8,
    pressed_at: Instant,
    last_event: Instant,
    repeats: u32,
    /// Press order, to pick the family when keys of several families are held.
    order: u64,
}

/// The hold-to-jog state machine.
#[derive(Debug, Clone)]
pub struct JogEngine {
    mode: ReleaseMode,
    timing: RepeatTiming,
    refresh: Duration,
    held: BTreeMap<Action, Held>,
    presses: u64,
    /// The motion last started and not yet stopped.
    active: Option<JogMotion>,
    last_start: Option<Instant>,
    joint: u8,
}

impl JogEngine {
    /// `refresh` is how often START is re-sent while keys are held (10 Hz by default).
    pub fn new(mode: ReleaseMode, refresh: Duration) -> Self {
        JogEngine {
            mode,
            timing: RepeatTiming::default(),
            refresh,
            held: BTreeMap::new(),
            presses: 0,
            active: None,
            last_start: None,
            joint: 1,
        }
    }

    pub fn mode(&self) -> ReleaseMode {
        self.mode
    }

    pub fn timing(&self) -> RepeatTiming {
        self.timing
    }

    pub fn active(&self) -> Option<JogMotion> {
        self.active
    }

    pub fn held_actions(&self) -> impl Iterator<Item = Action> + '_ {
        self.held.keys().copied()
    }

    pub fn is_jogging(&self) -> bool {
        self.active.is_some()
    }

    /// The joint a joint jog drives (1..=7).
    pub fn joint(&self) -> u8 {
        self.joint
    }

    /// Selects the joint for joint jogs; stops a joint jog in progress first.
    pub fn select_joint(&mut self, joint: u8, now: Instant) -> Vec<JogEffect> {
        let mut effects = Vec::new();
        if matches!(self.active, Some(JogMotion::Joint { .. })) {
            effects = self.stop_all(now);
        }
        self.joint = joint.clamp(1, 7);
        effects
    }

    /// A jog key event. Non-jog actions must go to [`JogEngine::stop_all`] instead.
    pub fn key(&mut self, action: Action, kind: KeyKind, now: Instant) -> Vec<JogEffect> {
        let Some((axis, sign)) = action.jog() else {
            return Vec::new();
        };
        match (kind, self.held.get_mut(&action)) {
            (KeyKind::Release, _) => {
                // Releases may be duplicated (some terminals synthesise them): idempotent.
                self.held.remove(&action);
            }
            (KeyKind::Press | KeyKind::Repeat, Some(held)) => {
                // Without reported releases, a press of a held key is its auto-repeat.
                if held.repeats == 0 {
                    self.timing
                        .sample_onset(now.saturating_duration_since(held.pressed_at));
                } else {
                    self.timing
                        .sample_interval(now.saturating_duration_since(held.last_event));
                }
                held.repeats += 1;
                held.last_event = now;
                return Vec::new();
            }
            (KeyKind::Repeat, None) => {
                // A repeat with no press seen (focus came back mid-hold): not a reason to move.
                return Vec::new();
            }
            (KeyKind::Press, None) => {
                self.presses += 1;
                self.held.insert(
                    action,
                    Held {
                        axis,
                        direction: sign.value(),
                        pressed_at: now,
                        last_event: now,
                        repeats: 0,
                        order: self.presses,
                    },
                );
            }
        }
        self.update(now)
    }

    /// Releases every key and stops any jog: for a non-jog key, focus loss, link loss, quit.
    /// Returns `Stop` if anything was moving or about to move.
    pub fn stop_all(&mut self, _now: Instant) -> Vec<JogEffect> {
        let was_busy = self.active.is_some() || !self.held.is_empty();
        self.held.clear();
        self.active = None;
        self.last_start = None;
        if was_busy {
            vec![JogEffect::Stop]
        } else {
            Vec::new()
        }
    }

    /// Time passing: expires keys whose repeats stopped, and re-sends START when due.
    pub fn tick(&mut self, now: Instant) -> Vec<JogEffect> {
        let before = self.held.len();
        let timing = self.timing;
        let mode = self.mode;
        self.held
            .retain(|_, h| expiry(mode, &timing, h).is_none_or(|at| now < at));
        if self.held.len() != before {
            return self.update(now);
        }
        match (self.active, self.last_start) {
            (Some(motion), Some(last)) if now >= last + self.refresh => {
                self.last_start = Some(now);
                vec![JogEffect::Start(motion)]
            }
            _ => Vec::new(),
        }
    }

    /// The next instant [`JogEngine::tick`] has something to do, if any.
    pub fn next_deadline(&self) -> Option<Instant> {
        let refresh = self
            .active
            .and(self.last_start)
            .map(|last| last + self.refresh);
        let expiries = self
            .held
            .values()
            .filter_map(|h| expiry(self.mode, &self.timing, h));
        refresh.into_iter().chain(expiries).min()
    }

    /// Recomputes the motion from the held keys and says what changed.
    fn update(&mut self, now: Instant) -> Vec<JogEffect> {
        let wanted = self.motion();
        if wanted == self.active {
            return Vec::new();
        }
        let mut effects = Vec::new();
        let family_changed = match (self.active, wanted) {
            (Some(a), Some(b)) => family_of(a) != family_of(b),
            _ => false,
        };
        if family_changed {
            effects.push(JogEffect::Stop);
        }
        self.active = wanted;
        match wanted {
            Some(motion) => {
                self.last_start = Some(now);
                effects.push(JogEffect::Start(motion));
            }
            None => {
                self.last_start = None;
                effects.push(JogEffect::Stop);
            }
        }
        effects
    }

    /// The motion of the most recently pressed key's family, all its held keys combined.
    fn motion(&self) -> Option<JogMotion> {
        let newest = self.held.values().max_by_key(|h| h.order)?;
        let family = newest.axis.family();
        let sum = |axis: JogAxis| -> i8 {
            let total: i8 = self
                .held
                .values()
                .filter(|h| h.axis == axis)
                .map(|h| h.direction)
                .sum();
            total.clamp(-1, 1)
        };
        let motion = match family {
            JogFamily::Cartesian => JogMotion::Cartesian {
                x: sum(JogAxis::X),
                y: sum(JogAxis::Y),
                z: sum(JogAxis::Z),
            },
            JogFamily::Polar => JogMotion::Polar {
                azimuth: sum(JogAxis::Azimuth),
                altitude: sum(JogAxis::Altitude),
            },
            JogFamily::Joint => JogMotion::Joint {
                joint: self.joint,
                direction: sum(JogAxis::Joint),
            },
        };
        // Opposite keys cancel: no motion rather than a zero-speed START.
        (!is_zero(motion)).then_some(motion)
    }
}

fn is_zero(motion: JogMotion) -> bool {
    match motion {
        JogMotion::Cartesian { x, y, z } => x == 0 && y == 0 && z == 0,
        JogMotion::Polar { azimuth, altitude } => azimuth == 0 && altitude == 0,
        JogMotion::Joint { direction, .. } => direction == 0,
    }
}

fn family_of(motion: JogMotion) -> JogFamily {
    match motion {
        JogMotion::Cartesian { .. } => JogFamily::Cartesian,
        JogMotion::Polar { .. } => JogFamily::Polar,
        JogMotion::Joint { .. } => JogFamily::Joint,
    }
}

/// When a held key counts as released without a release event, if ever.
fn expiry(mode: ReleaseMode, timing: &RepeatTiming, held: &Held) -> Option<Instant> {
    match mode {
        ReleaseMode::AutoRepeat if held.repeats == 0 => {
            Some(held.pressed_at + timing.first_timeout())
        }
        ReleaseMode::AutoRepeat => Some(held.last_event + timing.repeat_timeout()),
        // Releases are reported; once the keyboard is seen to auto-repeat, a hold whose repeats
        // stop for long is treated as released in case its release event was lost.
        ReleaseMode::Reported => timing
            .interval
            .filter(|_| held.repeats > 0)
            .map(|interval| held.last_event + (interval * STALE_INTERVALS).max(STALE_MIN)),
    }
}
