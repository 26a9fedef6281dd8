//! Hold-to-jog: which jog keys are held, what motion that makes, when to re-send or stop. Pure,
//! clocked from outside.
//! - [`ReleaseMode::Reported`] (kitty protocol): a press starts, a release stops. A key silent for
//!   [`KEY_EVENT_TIMEOUT`] stops too, and a second press without a release falls back to
//!   auto-repeat for the session.
//! - [`ReleaseMode::AutoRepeat`]: a key is held while its repeats arrive. A tap is a step
//!   ([`JogEffect::Step`]); motion starts once the onset and regular repeats confirm a hold, and
//!   stops about three intervals after the last repeat.
//!
//! Nothing starts by itself: keys still down when the engine stops become latched until released
//! (or silent past their release timeout); events while motion is not allowed go to
//! [`JogEngine::latch`].

mod events;
mod held;
mod timing;

use std::collections::BTreeMap;
use std::time::{Duration, Instant};

use super::action::{Action, JogAxis, JogFamily};
// The motion the held keys ask for is the link's vocabulary: re-exported for the console.
pub use crate::link::interface::JogMotion;
pub use held::KEY_EVENT_TIMEOUT;
use held::{Held, KeyState};
pub use timing::{DEFAULT_INTERVAL, MAX_ONSET, REPEAT_GAP_MAX, RepeatTiming};

/// The motion of `family`, `along(axis)` (-1, 0 or 1) on each of its axes.
fn motion_of(family: JogFamily, joint: u8, along: impl Fn(JogAxis) -> i8) -> JogMotion {
    match family {
        JogFamily::Cartesian => JogMotion::Cartesian {
            x: along(JogAxis::X),
            y: along(JogAxis::Y),
            z: along(JogAxis::Z),
        },
        JogFamily::Polar => JogMotion::Polar {
            azimuth: along(JogAxis::Azimuth),
            altitude: along(JogAxis::Altitude),
        },
        JogFamily::Joint => JogMotion::Joint {
            joint,
            direction: along(JogAxis::Joint),
        },
        JogFamily::Orientation => JogMotion::Orientation {
            rx: along(JogAxis::Rx),
            ry: along(JogAxis::Ry),
            rz: along(JogAxis::Rz),
        },
    }
}

/// The motion of one jog key alone: `direction` along `axis` (`joint` for a joint jog).
pub fn unit_motion(axis: JogAxis, direction: i8, joint: u8) -> JogMotion {
    motion_of(
        axis.family(),
        joint,
        |a| if a == axis { direction } else { 0 },
    )
}

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

/// What the engine wants sent or said.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JogEffect {
    /// Start, change or refresh continuous motion.
    Start(JogMotion),
    /// Stop all continuous motion.
    Stop,
    /// A cartesian key tapped (fallback): a small bounded step this way.
    Step(JogMotion),
    /// Something the technician must be told.
    Notice(JogNotice),
}

/// Events worth a message on the screen.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JogNotice {
    /// Release events mode: a held key sent no event for this long, so the jog stopped.
    NoKeyEvents(Duration),
    /// A key pressed again without a release: the engine switched to auto-repeat.
    ReleasesMissing,
    /// Fallback: an arrow, joint or turn key was tapped; only a hold moves those.
    TapNeedsHold,
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

    /// How releases are known; `Reported` may turn into `AutoRepeat` for the session.
    pub fn mode(&self) -> ReleaseMode {
        self.mode
    }

    pub fn timing(&self) -> RepeatTiming {
        self.timing
    }

    pub fn active(&self) -> Option<JogMotion> {
        self.active
    }

    /// Whether `action`'s key is down since before a stop, so it cannot move until released.
    pub fn is_latched(&self, action: Action) -> bool {
        self.held
            .get(&action)
            .is_some_and(|h| h.state == KeyState::Latched)
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

    /// A jog key event while motion is allowed (non-jog keys go to [`JogEngine::stop_all`]).
    pub fn key(&mut self, action: Action, kind: KeyKind, now: Instant) -> Vec<JogEffect> {
        let Some((axis, sign)) = action.jog() else {
            return Vec::new();
        };
        let mut effects = self.catch_up(now);
        if kind == KeyKind::Release {
            self.release(action, now, &mut effects);
            return effects;
        }
        match self.mode {
            ReleaseMode::Reported => self.reported_event(action, kind, now, &mut effects),
            ReleaseMode::AutoRepeat => self.fallback_event(action, kind, now, &mut effects),
        }
        if !self.held.contains_key(&action) {
            self.insert_pressed(action, axis, sign.value(), now, &mut effects);
        }
        effects
    }

    /// A jog key event while motion is not allowed: latched until a fresh press.
    pub fn latch(&mut self, action: Action, kind: KeyKind, now: Instant) -> Vec<JogEffect> {
        let Some((axis, sign)) = action.jog() else {
            return Vec::new();
        };
        let mut effects = self.catch_up(now);
        if kind == KeyKind::Release {
            self.release(action, now, &mut effects);
            return effects;
        }
        match self.held.get_mut(&action) {
            Some(held) => {
                held.record(now);
                held.latch();
            }
            None => {
                let held = Held::new(axis, sign.value(), KeyState::Latched, now);
                self.held.insert(action, held);
            }
        }
        effects.extend(self.update(now));
        effects
    }

    /// As [`JogEngine::latch`], and whether it is a fresh press (step mode steps only on those).
    pub fn latch_press(
        &mut self,
        action: Action,
        kind: KeyKind,
        now: Instant,
    ) -> (bool, Vec<JogEffect>) {
        let mut effects = self.catch_up(now);
        let fresh = kind == KeyKind::Press && !self.held.contains_key(&action);
        effects.extend(self.latch(action, kind, now));
        (fresh, effects)
    }

    /// Stops any jog, keys still down latched; returns `Stop` if anything moved or was about to.
    pub fn stop_all(&mut self, _now: Instant) -> Vec<JogEffect> {
        let was_busy =
            self.active.is_some() || self.held.values().any(|h| h.state == KeyState::Pending);
        self.held.values_mut().for_each(Held::latch);
        self.active = None;
        self.last_start = None;
        if was_busy {
            vec![JogEffect::Stop]
        } else {
            Vec::new()
        }
    }

    /// Whether [`JogEngine::tick`] now would re-send START (the runtime takes waiting input first).
    pub fn refresh_due(&self, now: Instant) -> bool {
        self.active.is_some()
            && self
                .last_start
                .is_some_and(|last| now >= last + self.refresh)
    }

    /// Time passing: taps step, silent keys expire, START is re-sent when due.
    pub fn tick(&mut self, now: Instant) -> Vec<JogEffect> {
        let mut effects = self.catch_up(now);
        if let (Some(motion), Some(last)) = (self.active, self.last_start)
            && now >= last + self.refresh
        {
            self.last_start = Some(now);
            effects.push(JogEffect::Start(motion));
        }
        effects
    }

    /// The next instant [`JogEngine::tick`] has something to do, if any.
    pub fn next_deadline(&self) -> Option<Instant> {
        let refresh = self
            .active
            .and(self.last_start)
            .map(|last| last + self.refresh);
        // A latched key's expiry changes nothing outside: it expires lazily.
        let expiries = self
            .held
            .values()
            .filter(|h| h.state != KeyState::Latched)
            .map(|h| self.expiry(h));
        let steps = self.held.values().filter_map(|h| h.step_due);
        refresh.into_iter().chain(expiries).chain(steps).min()
    }
}
