//! The one gate every motion passes: [`App::motion_refusal`] says whether a motion may start
//! and, if not, why. Jogs of every kind, steps, home, go-to and move-to-pose all ask it where
//! they start, and after every input any motion command still emitted while it refuses is
//! dropped (the net under those paths).
//!
//! Reasons, first first: no link, a stale link, the stop guard not ready (any real link), and
//! what the arm itself reports: a fault (an emergency stop is one), a state other than ready or
//! controlled, or telemetry that no Gen3 can report (not a number, out of physical range). A
//! fault, state or reading like that appearing while a motion runs stops it and latches the
//! held keys (see [`App::watch_arm_state`]).

use std::time::Instant;

use super::message::Until;
use super::{App, Effect};
use crate::kortex::{Coded, RobotState, Telemetry};
use crate::link::interface::GuardStatus;

/// Why the arm's own report forbids motion, in the words after `the arm reports`, or `None`.
pub fn arm_refusal(t: &Telemetry) -> Option<String> {
    if !t.faults.is_empty() {
        return Some(t.faults.names().join(", "));
    }
    match t.robot_state {
        Coded::Known(
            RobotState::Ready | RobotState::ControlledBySequence | RobotState::ControlledManually,
        ) => {}
        Coded::Known(RobotState::InFault) => return Some("in_fault".into()),
        state => return Some(format!("state {state}, not ready")),
    }
    // The panels' own test of what is physically possible: what shows as `?` never moves.
    t.insane_fields()
        .first()
        .map(|field| format!("nonsense: {field}"))
}

impl App {
    /// Whether a motion may start now: `None`, or the one sentence why not
    /// (`refused: the arm reports emergency_stop`).
    pub fn motion_refusal(&self) -> Option<String> {
        self.motion_refusal_until().map(|(text, _)| text)
    }

    /// [`App::motion_refusal`] with what ends its message.
    pub(super) fn motion_refusal_until(&self) -> Option<(String, Until)> {
        if !self.arm.link_up() {
            return Some(("no link to the arm: not moving".into(), Until::LinkUp));
        }
        if self.link_stale().is_some() {
            return Some(("link stale: not moving".into(), Until::LinkFresh));
        }
        match self.arm.guard() {
            Some(GuardStatus::Starting) => {
                let text = "refused: the stop guard is not ready yet";
                return Some((text.into(), Until::GuardReady));
            }
            Some(GuardStatus::Down { reason }) => {
                let text = format!("refused: the stop guard is down: {reason}");
                return Some((text, Until::GuardReady));
            }
            _ => {}
        }
        let why = self.arm.refusal()?;
        Some((format!("refused: the arm reports {why}"), Until::ArmReady))
    }

    /// Says why a motion may not start and returns true, or returns false when it may.
    pub(super) fn refuse_motion(&mut self, now: Instant) -> bool {
        let Some((text, until)) = self.motion_refusal_until() else {
            return false;
        };
        self.say_until(text, super::Severity::Warning, until, now);
        true
    }

    /// The net after every input: motion commands emitted while the gate refuses are dropped
    /// (and said, once); a jog the engine still thinks runs is stopped, its keys latched.
    pub(super) fn gate_effects(&mut self, now: Instant, effects: &mut Vec<Effect>) {
        let Some((text, until)) = self.motion_refusal_until() else {
            return;
        };
        let asked = effects.len();
        effects.retain(|e| !matches!(e, Effect::Arm(command) if command.starts_motion()));
        if effects.len() != asked {
            self.say_until(text, super::Severity::Warning, until, now);
            if self.keys.jog().is_jogging() {
                self.stop_jog(now, effects);
            }
        }
    }

    /// Fresh telemetry while a motion the console started runs: a fault, a state or a reading
    /// that forbids motion stops it, and the held keys stay latched until pressed anew.
    pub(super) fn watch_arm_state(
        &mut self,
        t: &Telemetry,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) {
        if !self.keys.jog().is_jogging() && self.truth.action().is_none() {
            return;
        }
        if let Some(why) = arm_refusal(t) {
            self.stop_from_telemetry(format!("stopped: the arm reports {why}"), now, effects);
        }
    }
}
