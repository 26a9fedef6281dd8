//! How key events change the held keys and their motion: the engine's inner steps.

use std::time::Instant;

use super::held::{Held, KeyState, expiry};
use super::{
    JogEffect, JogEngine, JogMotion, JogNotice, KeyKind, REPEAT_GAP_MAX, ReleaseMode, motion_of,
};
use crate::console::action::{Action, JogAxis, JogFamily};

impl JogEngine {
    pub(super) fn insert_pressed(
        &mut self,
        action: Action,
        axis: JogAxis,
        direction: i8,
        now: Instant,
        effects: &mut Vec<JogEffect>,
    ) {
        let mut held = Held::new(axis, direction, KeyState::Moving, now);
        match self.mode {
            ReleaseMode::Reported => {
                self.presses += 1;
                held.order = self.presses;
                self.held.insert(action, held);
                effects.extend(self.update(now));
            }
            ReleaseMode::AutoRepeat => {
                // A tap or the start of a hold: decided by what follows.
                held.state = KeyState::Pending;
                held.step_due = held.steps().then_some(now + REPEAT_GAP_MAX);
                self.held.insert(action, held);
            }
        }
    }

    pub(super) fn release(&mut self, action: Action, now: Instant, effects: &mut Vec<JogEffect>) {
        // Releases may be duplicated (some terminals synthesise them): idempotent.
        let Some(held) = self.held.remove(&action) else {
            return;
        };
        // A released key whose tap was waiting for a possible repeat: it was a tap.
        if held.state == KeyState::Pending && held.step_due.is_some() {
            effects.extend(self.tap(&held));
        }
        effects.extend(self.update(now));
    }

    pub(super) fn reported_event(
        &mut self,
        action: Action,
        kind: KeyKind,
        now: Instant,
        effects: &mut Vec<JogEffect>,
    ) {
        let Some(held) = self.held.get_mut(&action) else {
            if kind == KeyKind::Repeat {
                // A repeat with no press seen (focus back mid-hold): no move.
                let Some((axis, sign)) = action.jog() else {
                    return;
                };
                let held = Held::new(axis, sign.value(), KeyState::Latched, now);
                self.held.insert(action, held);
            }
            return;
        };
        let since_press = held.repeats == 0;
        let gap = held.record(now);
        match (held.state, kind) {
            (_, KeyKind::Press) => {
                // Pressed again without a release: fall back to auto-repeat.
                self.mode = ReleaseMode::AutoRepeat;
                effects.extend(self.stop_all(now));
                effects.push(JogEffect::Notice(JogNotice::ReleasesMissing));
            }
            (KeyState::Moving, _) => {
                if since_press {
                    self.timing.sample_onset(gap);
                } else {
                    self.timing.sample_interval(gap);
                }
            }
            // A repeat of a latched key only keeps the latch fresh.
            _ => {}
        }
    }

    pub(super) fn fallback_event(
        &mut self,
        action: Action,
        kind: KeyKind,
        now: Instant,
        effects: &mut Vec<JogEffect>,
    ) {
        let Some(held) = self.held.get_mut(&action) else {
            if kind == KeyKind::Repeat {
                // The terminal says this key was pressed before: no reason to move.
                effects.extend(self.latch(action, kind, now));
            }
            return;
        };
        let gap = held.record(now);
        match held.state {
            KeyState::Moving => self.timing.sample_interval(gap),
            KeyState::Latched => {}
            KeyState::Pending if gap >= REPEAT_GAP_MAX => {
                // A new tap, or the onset of a hold: the next event tells.
                held.step_due = held.steps().then_some(now + REPEAT_GAP_MAX);
            }
            KeyState::Pending => {
                // The previous event was followed this closely: a repeat, not a tap.
                held.step_due = None;
                let confirmed = self.timing.confirms_hold(
                    held.run_onset,
                    held.run_span(),
                    held.run_gaps.0,
                    gap,
                );
                if confirmed {
                    self.presses += 1;
                    held.state = KeyState::Moving;
                    held.order = self.presses;
                    let (onset, gaps) = (held.run_onset, held.run_gaps);
                    if let Some(onset) = onset {
                        self.timing.sample_onset(onset);
                    }
                    gaps.0
                        .into_iter()
                        .chain(gaps.1)
                        .for_each(|g| self.timing.sample_interval(g));
                    effects.extend(self.update(now));
                }
            }
        }
    }

    /// Due taps and expired keys, up to `now`.
    pub(super) fn catch_up(&mut self, now: Instant) -> Vec<JogEffect> {
        let mut effects = Vec::new();
        // Expiries first: a key released by timeout stops before any step goes out.
        let mut silent_for = None;
        let mut expired_taps = Vec::new();
        let mut changed = false;
        let (mode, timing) = (self.mode, self.timing);
        self.held.retain(|_, h| {
            let at = expiry(mode, &timing, h);
            if now < at {
                return true;
            }
            changed |= h.state == KeyState::Moving;
            match (mode, h.state) {
                (ReleaseMode::Reported, KeyState::Moving) => {
                    // No evidence it is down: stop, but keep it latched.
                    silent_for = Some(at.saturating_duration_since(h.last_event));
                    h.latch();
                    h.last_event = now;
                    true
                }
                (ReleaseMode::AutoRepeat, KeyState::Moving) => {
                    // Repeats stopped (released or stalled): stop; latched until they pause.
                    h.latch();
                    h.last_event = now;
                    true
                }
                _ => {
                    // A lone event is a tap; with no step, only a word.
                    let tap = h.state == KeyState::Pending
                        && h.last_event_alone()
                        && (h.step_due.is_some() || !h.steps());
                    if tap {
                        expired_taps.push(*h);
                    }
                    false
                }
            }
        });
        if changed {
            effects.extend(self.update(now));
        }
        if let Some(silent_for) = silent_for {
            effects.push(JogEffect::Notice(JogNotice::NoKeyEvents(silent_for)));
        }
        let mut due: Vec<Held> = expired_taps;
        for held in self.held.values_mut() {
            if held.state == KeyState::Pending && held.step_due.is_some_and(|at| now >= at) {
                due.push(*held);
                held.step_due = None;
            }
        }
        for held in due {
            effects.extend(self.tap(&held));
        }
        effects
    }

    /// A tap's effect: a cartesian step unless a jog runs (a discrete move must not interfere).
    pub(super) fn tap(&self, held: &Held) -> Option<JogEffect> {
        match held.axis.family() {
            JogFamily::Cartesian if self.active.is_none() => {
                Some(JogEffect::Step(held.unit_motion(self.joint)))
            }
            JogFamily::Cartesian => None,
            JogFamily::Polar | JogFamily::Joint | JogFamily::Orientation => {
                Some(JogEffect::Notice(JogNotice::TapNeedsHold))
            }
        }
    }

    pub(super) fn expiry(&self, held: &Held) -> Instant {
        expiry(self.mode, &self.timing, held)
    }

    /// Recomputes the motion from the moving keys and says what changed.
    pub(super) fn update(&mut self, now: Instant) -> Vec<JogEffect> {
        let wanted = self.motion();
        if wanted == self.active {
            return Vec::new();
        }
        let mut effects = Vec::new();
        // Each family is its own variant of the motion.
        let family_changed = match (self.active, wanted) {
            (Some(a), Some(b)) => std::mem::discriminant(&a) != std::mem::discriminant(&b),
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

    /// The motion of the most recently started key's family, all its moving keys combined.
    pub(super) fn motion(&self) -> Option<JogMotion> {
        let moving = || self.held.values().filter(|h| h.state == KeyState::Moving);
        let newest = moving().max_by_key(|h| h.order)?;
        let sum = |axis: JogAxis| -> i8 {
            let total: i8 = moving()
                .filter(|h| h.axis == axis)
                .map(|h| h.direction)
                .sum();
            total.clamp(-1, 1)
        };
        let family = newest.axis.family();
        let motion = motion_of(family, self.joint, sum);
        // Opposite keys cancel: no motion rather than a zero-speed START.
        (motion != motion_of(family, self.joint, |_| 0)).then_some(motion)
    }
}
