//! Hold-to-jog: which jog keys are held, what motion that makes, and when to re-send or stop.
//!
//! Pure and clocked from outside: every call takes `now`. Two ways to know a key is held:
//! - [`ReleaseMode::Reported`]: the terminal reports releases (kitty keyboard protocol). A press
//!   starts motion; a release stops it. Evidence is still required: a held key that sends
//!   nothing (no repeat, no release) for [`KEY_EVENT_TIMEOUT`] stops, and a second press with no
//!   release between proves the terminal does not report releases: the engine stops and falls
//!   back to [`ReleaseMode::AutoRepeat`] for the rest of the session.
//! - [`ReleaseMode::AutoRepeat`]: it does not (tmux, VTE, xterm, the Linux console), so a key
//!   counts as held while its auto-repeat keeps arriving. A tap cannot be told from the start of
//!   a hold until the repeats come, so, as on a teach pendant, a tap is a step
//!   ([`JogEffect::Step`], cartesian keys only) and continuous motion starts only once the
//!   repeat pattern confirms a hold: a pause (the onset) followed by closely spaced, regular
//!   repeats. It stops about three repeat intervals after the last repeat.
//!
//! Nothing starts by itself: when the engine stops ([`JogEngine::stop_all`], a timeout), the keys
//! still down become *latched*. Events of a latched key only keep the latch fresh; it ends with
//! a release event, or with a pause in the key's events longer than its release timeout. Events
//! that arrive while motion is not allowed go to [`JogEngine::latch`].

mod events;
mod held;
mod timing;

use std::collections::BTreeMap;
use std::time::{Duration, Instant};

use super::action::Action;
// The motion the held keys ask for is the link's vocabulary: re-exported for the console.
pub use crate::link::interface::JogMotion;
pub use held::KEY_EVENT_TIMEOUT;
use held::{Held, KeyState};
pub use timing::{DEFAULT_INTERVAL, MAX_ONSET, REPEAT_GAP_MAX, RepeatTiming};

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
    /// A cartesian jog key was tapped (auto-repeat fallback): move one small, bounded step in
    /// this direction (a unit cartesian motion; the console chooses the distance).
    Step(JogMotion),
    /// Something the technician must be told.
    Notice(JogNotice),
}

/// Events worth a message on the screen.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JogNotice {
    /// Release events mode: a held key sent no event for this long, so the jog stopped.
    NoKeyEvents(Duration),
    /// Release events mode: a held key was pressed again without a release in between. The
    /// terminal does not report releases; the engine switched to the auto-repeat fallback.
    ReleasesMissing,
    /// Auto-repeat fallback: an arrow, joint or turn key was tapped. Those have no bounded step:
    /// only a hold moves them.
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

    /// How releases are known now: [`ReleaseMode::Reported`] can turn into
    /// [`ReleaseMode::AutoRepeat`] when the terminal proves it does not report releases.
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

    /// The jog key whose release alone stops the arm now: releases are reported, the arm jogs,
    /// and that key is the only one down. `None` otherwise (another key down keeps a motion
    /// going, or releases are not reported). What the console's terminal reader writes the stop
    /// set ahead for (`link::talos::StopAhead`): the release still comes here and stops.
    pub fn stopped_by_release(&self) -> Option<Action> {
        if self.mode != ReleaseMode::Reported || self.active.is_none() {
            return None;
        }
        let mut held = self.held.iter();
        match (held.next(), held.next()) {
            (Some((action, h)), None) if h.state == KeyState::Moving => Some(*action),
            _ => None,
        }
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

    /// A jog key event while motion is allowed. Non-jog actions must go to
    /// [`JogEngine::stop_all`] instead.
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

    /// A jog key event while motion is not allowed (link down, overlay open, step mode, screen
    /// too small): the key is tracked as latched, so it cannot move once motion is allowed
    /// again until it is released and pressed anew.
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

    /// As [`JogEngine::latch`], and whether the event is a fresh press: the key was neither
    /// held nor latched. Step mode steps only on those, so a held key's auto-repeat (which
    /// arrives as presses in the fallback) does not step again and again.
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

    /// Stops any jog; every key still down becomes latched: for a non-jog key, focus loss, link
    /// loss, an overlay, quit. Returns `Stop` if anything was moving or about to move.
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

    /// Whether [`JogEngine::tick`] at `now` would re-send START: the runtime first handles
    /// any key input that has already arrived, so a release is never overtaken by a refresh.
    pub fn refresh_due(&self, now: Instant) -> bool {
        self.active.is_some()
            && self
                .last_start
                .is_some_and(|last| now >= last + self.refresh)
    }

    /// Time passing: steps for taps, expires keys whose events stopped, and re-sends START
    /// when due.
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
