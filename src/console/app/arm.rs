//! The arm in the state machine: the one motion gate ([`App::motion_refusal`]: no link, a stale
//! link, no ready stop guard, or what the arm reports, `parts::arm_refusal`), asked where every
//! motion starts and again after every input as a net; a fault, state or reading that appears while
//! a motion runs stops it and latches the held keys ([`App::watch_arm_state`]). Also the driver's
//! events, the speed cap watched on telemetry (`cap_watch`), and stored actions and sequences by id
//! (asked first, stopped by any key, watched to their end in `motion_truth/actions.rs`).

use std::time::Instant;

use super::cap_watch::{CapWatch, over_cap};
use super::fence_watch;
use super::message::Until;
use super::parts::Leg;
use super::{App, Effect, KeyInput, Overlay, Severity, parts};
use crate::console::form::Form;
use crate::console::jog::JogMotion;
use crate::console::jog::KeyKind;
use crate::kortex::{ReferenceFrame, Stored, Telemetry};
use crate::link::fence::{Fence, Pace, SLOWEST, Verdict, WHOLE};
use crate::link::guard::HEARTBEAT_TIMEOUT;
use crate::link::interface::{
    ArmCommand, ArmError, ArmEvent, CommandKind, GuardStatus, LinkStatus, TelemetrySource,
};
use crate::link::speed::{INITIAL_SPEED, fraction};

/// Why the stored action key does nothing on a link without Modbus.
pub const STORED_REFUSAL: &str = "stored actions and sequences by id need a Modbus link: over \
     Talos only home (h) runs; add --modbus";

impl App {
    pub(super) fn on_arm(&mut self, event: ArmEvent, now: Instant, effects: &mut Vec<Effect>) {
        self.motion_truth_on_arm(&event, now);
        // Arm events that end a message.
        let telemetry_expected = self.motion_truth.expects_telemetry();
        self.screen.messages_on_arm(&event, telemetry_expected);
        if self.edits_on_arm(&event, now, effects) {
            return;
        }
        match event {
            ArmEvent::Status(status) => {
                if let LinkStatus::Down { reason } = &status {
                    // Stop on any link left; held keys stay latched.
                    self.stop_jog(now, effects);
                    let text = format!("link lost: {reason}");
                    self.say_until(text, Severity::Error, Until::LinkUp, now);
                }
                let came_up = self.arm.on_link(status);
                if came_up && self.config.positions_on_operator {
                    // The ICD cannot list positions: ask about remembered names.
                    self.check_names_on_operator(effects);
                }
            }
            ArmEvent::Telemetry(t) => {
                self.watch_cap(&t, now, effects);
                self.watch_arm_state(&t, now, effects);
                self.watch_other_clients(&t, now, effects);
                self.arm.on_telemetry(*t, now);
                self.watch_fence(now, effects);
            }
            // The motion truth keeps the source (see `motion_truth_on_arm`).
            ArmEvent::TelemetrySource(_) => {}
            ArmEvent::Latency(latency) => self.arm.on_latency(latency),
            ArmEvent::Speed(speed) => {
                if self.arm.on_speed(speed) {
                    self.other_client_note_speed(now);
                }
            }
            ArmEvent::Notice(text) => self.warn(text, now),
            ArmEvent::Log(entry) => self.screen.on_log(entry),
            ArmEvent::Failed {
                error: error @ (ArmError::GuardStoppedArm(_) | ArmError::GuardStopFailed(_)),
                ..
            } => self.on_guard_stopped(&error, now, effects),
            ArmEvent::Failed { command, error } => {
                // A refused jog is not left to the watchdog: stop and latch held keys. Nor is a
                // refused fence slow-down: the arm may still go at the faster speed.
                if matches!(command, CommandKind::Jog | CommandKind::FenceSpeed) {
                    self.stop_jog(now, effects);
                }
                if self.position_failed(command, &error, now) {
                    return;
                }
                let until = Until::failure(command, &error);
                let text = format!("{command} failed: {error}");
                self.say_until(text, Severity::Error, until, now);
            }
            ArmEvent::Position { name, coordinates } => {
                self.book.on_operator_knows(&name, coordinates.cartesian);
                self.screen.on_position(name, coordinates);
            }
            ArmEvent::UnknownPosition { name } => {
                self.book.on_unknown_to_operator(&name);
                // Said only when the technician is looking at it; otherwise the panel marks it.
                if self.screen.shows_position(&name) {
                    self.screen.show(Overlay::None);
                    self.warn(format!("the operator does not know '{name}'"), now);
                }
            }
            ArmEvent::Done { command } => self.on_done(command, now, effects),
            ArmEvent::Guard(status) => {
                // No ready guard: the driver stops motion; forget held keys so nothing restarts.
                if !matches!(status, GuardStatus::Ready { .. }) {
                    self.stop_jog(now, effects);
                }
                if let GuardStatus::Down { reason } = &status {
                    let text = format!("stop guard down, no motion until it is back: {reason}");
                    self.say_until(text, Severity::Error, Until::GuardReady, now);
                }
                self.arm.on_guard(status);
            }
            // Evidence only: see `motion_truth_on_arm`.
            ArmEvent::StopConfirmed | ArmEvent::StopUnconfirmed { .. } => {}
        }
    }

    /// The stop guard stopped the arm: reported by the driver as a failed jog (held keys latched),
    /// named after what it stopped. The tracked action is forgotten so the arm's abort that follows
    /// is not said again as its failure.
    fn on_guard_stopped(&mut self, error: &ArmError, now: Instant, effects: &mut Vec<Effect>) {
        let jogging = self.keys.jog().is_jogging();
        self.stop_jog(now, effects);
        let stopped = match self.motion_truth.action() {
            Some(action) => Some(action.kind.verb()),
            None => jogging.then(|| "jog".to_string()),
        };
        // Back from a freeze, the console may have ended the move itself before this report.
        let frozen_with = self.frozen_with.take();
        let stopped = stopped.or_else(|| {
            frozen_with
                .filter(|(_, back)| now <= *back + HEARTBEAT_TIMEOUT)
                .map(|(what, _)| what)
        });
        self.motion_truth.forget_action();
        if stopped.is_some() && !effects.iter().any(Effect::is_stop) {
            effects.push(Effect::Arm(ArmCommand::Stop));
        }
        // A stop the guard could not make is never said as one: the arm may still move.
        let failed = matches!(error, ArmError::GuardStopFailed(_));
        let text = match stopped {
            Some(what) if failed => format!("{what}: {error}; STOP sent"),
            Some(what) => format!("{what} stopped: {error}"),
            None => error.to_string(),
        };
        self.error(text, now);
    }

    /// A console frozen for the guard's heartbeat timeout may get the guard's report after it has
    /// ended the motion itself: what ran when it froze is kept for that report, for the timeout
    /// again.
    pub(super) fn note_freeze(&mut self, now: Instant) {
        if self.now.is_none_or(|last| now < last + HEARTBEAT_TIMEOUT) {
            return;
        }
        let leg_moving = self
            .tours
            .phase()
            .is_some_and(|phase| phase != Leg::Waiting);
        let running = match self.motion_truth.action() {
            _ if leg_moving => Some(self.tours.leg_text()),
            Some(action) => Some(action.kind.verb()),
            None => self.keys.jog().is_jogging().then(|| "jog".to_string()),
        };
        self.frozen_with = running.map(|what| (what, now));
    }

    /// A telemetry sample against the cap, while a motion the console started runs.
    pub(super) fn watch_cap(&mut self, t: &Telemetry, now: Instant, effects: &mut Vec<Effect>) {
        let jog = self.keys.jog().active();
        if jog.is_none() && self.motion_truth.action().is_none() {
            self.arm.on_cap_idle();
            return;
        }
        let cap_mm_s = self.cap.max_mm_s();
        let joint_deg_s = f64::from(self.config.joint_jog_speed);
        let over = over_cap(t, jog, cap_mm_s, joint_deg_s);
        if let Some(text) = self.arm.on_cap_sample(over) {
            self.stop_from_telemetry(text, now, effects);
        }
    }

    /// Stops a motion telemetry forbids, latching held keys; `text` said and logged.
    pub(super) fn stop_from_telemetry(
        &mut self,
        text: String,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) {
        // The action ends here, said once below (not also as "home stopped").
        self.motion_truth.forget_action();
        self.stop_everything(now, effects);
        tracing::warn!("{text}");
        self.error(text, now);
    }

    /// Whether the cap is watched; `None` until the driver says whether telemetry comes.
    pub fn cap_watched(&self) -> Option<bool> {
        self.motion_truth
            .expected_telemetry()
            .map(|source| source != TelemetrySource::None)
    }

    pub fn cap_watch(&self) -> &CapWatch {
        self.arm.cap_watch()
    }

    /// Why a stored run by id cannot start on this link; offered until the driver names its links.
    pub fn stored_refusal(&self) -> Option<&'static str> {
        self.without_modbus().then_some(STORED_REFUSAL)
    }

    /// Whether this link can run a stored action or sequence by id (the footer offers the key).
    pub fn can_run_stored(&self) -> bool {
        self.stored_refusal().is_none()
    }

    /// The stored action key: the form, or why not (the link, or the motion gate).
    pub(super) fn open_stored_form(&mut self, now: Instant) {
        if let Some(why) = self.stored_refusal() {
            self.warn(why, now);
            return;
        }
        if !self.refuse_motion(now) {
            self.screen.show(Overlay::Form(Form::stored()));
        }
    }

    /// Yes to "Run action 5 on the arm?" (the motion gate has just let it through).
    pub(super) fn run_stored(&mut self, stored: Stored, now: Instant, effects: &mut Vec<Effect>) {
        match self.stored_refusal() {
            Some(why) => self.warn(why, now),
            None => effects.push(Effect::Arm(ArmCommand::StartStored(stored))),
        }
    }

    /// A key while a stored run runs stops it and does nothing else; returns whether it did.
    pub(super) fn key_stops_stored_run(
        &mut self,
        key: &KeyInput,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) -> bool {
        let running = self
            .motion_truth
            .action()
            .is_some_and(|action| action.kind.stops_on_any_key());
        if key.kind != KeyKind::Press || !running {
            return false;
        }
        // The key is latched like any key that stops, so a held jog key needs a fresh press.
        self.stop_everything(now, effects);
        self.latch_jog_key(key, now, effects);
        true
    }

    /// `None` if a motion may start now, else the one sentence why not.
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
        if let Some(why) = self.arm.refusal() {
            return Some((format!("refused: the arm reports {why}"), Until::ArmReady));
        }
        self.fence_blind()
    }

    /// With a fence, no motion without fresh telemetry: the fence cannot see the tool.
    fn fence_blind(&self) -> Option<(String, Until)> {
        self.fence.kept.as_ref()?;
        // Said for a while: no report ends it.
        let until = Until::TimeOut { done: None };
        if self.motion_truth.expected_telemetry() == Some(TelemetrySource::None) {
            let text =
                "refused: the fence needs telemetry and this link reports none (add --modbus)";
            return Some((text.into(), until));
        }
        if self.arm.telemetry().is_none() || self.telemetry_stale().is_some() {
            let text = "refused: no fresh telemetry for the fence to see the tool by";
            return Some((text.into(), until));
        }
        None
    }

    /// Says why a motion may not start and returns true, or returns false when it may.
    pub(super) fn refuse_motion(&mut self, now: Instant) -> bool {
        let Some((text, until)) = self.motion_refusal_until() else {
            return false;
        };
        self.say_until(text, Severity::Warning, until, now);
        true
    }

    /// The net after every input: motion emitted while the gate refuses is dropped, a jog stopped.
    pub(super) fn gate_effects(&mut self, now: Instant, effects: &mut Vec<Effect>) {
        let Some((text, until)) = self.motion_refusal_until() else {
            return;
        };
        let asked = effects.len();
        effects.retain(|e| !matches!(e, Effect::Arm(command) if command.starts_motion()));
        if effects.len() != asked {
            self.say_until(text, Severity::Warning, until, now);
            if self.keys.jog().is_jogging() {
                self.stop_jog(now, effects);
            }
        }
    }

    /// The fence over every motion going out, after the gate: a jog shaped (axes taken out, its
    /// share of the speed sent first) or stopped at the fence with its key still held; a target
    /// or straight path across the fence refused; a stop puts the whole speed back.
    pub(super) fn fence_effects(&mut self, now: Instant, effects: &mut Vec<Effect>) {
        let Some(fence) = self.fence.kept.clone() else {
            return;
        };
        let Some(t) = self.arm.telemetry().cloned() else {
            return;
        };
        let mut out = Vec::with_capacity(effects.len() + 1);
        for effect in effects.drain(..) {
            match effect {
                Effect::Arm(ArmCommand::Jog(motion)) => {
                    self.fence_jog(&fence, &t, motion, now, &mut out);
                }
                Effect::Arm(command) if command.starts_motion() => {
                    if let Some(why) = fence_watch::target_refusal(&fence, &t, &command, &self.book)
                    {
                        self.warn(format!("refused: {why}"), now);
                        continue;
                    }
                    self.fence_whole_speed(&mut out);
                    out.push(Effect::Arm(command));
                }
                stop if stop.is_stop() => {
                    out.push(stop);
                    self.fence_whole_speed(&mut out);
                }
                other => out.push(other),
            }
        }
        *effects = out;
    }

    /// Back to the whole speed, if the fence had taken a share.
    fn fence_whole_speed(&mut self, out: &mut Vec<Effect>) {
        if self.fence.sent != WHOLE {
            self.fence.sent = WHOLE;
            out.push(Effect::Arm(ArmCommand::FenceSpeed(WHOLE)));
        }
    }

    /// The verdict on the held `motion` now; `None` when telemetry cannot place the tool.
    fn fence_verdict(&self, fence: &Fence, t: &Telemetry, motion: JogMotion) -> Option<Verdict> {
        let base = !self.config.frames || self.arm.frame() == ReferenceFrame::Base;
        let heading = fence_watch::heading(motion, t, base)?;
        let sample = fence_watch::sample(t, &heading)?;
        let percent = self.arm.speed().unwrap_or(INITIAL_SPEED);
        let pace = Pace {
            speed_mm_s: self.cap.tool_speed_mm_s(percent),
            joint_rate: f64::from(self.config.joint_jog_speed) * fraction(percent),
            lookahead_s: self.fence.lookahead_s(),
        };
        Some(fence.judge(&sample, heading, pace))
    }

    fn fence_jog(
        &mut self,
        fence: &Fence,
        t: &Telemetry,
        motion: JogMotion,
        now: Instant,
        out: &mut Vec<Effect>,
    ) {
        let Some(verdict) = self.fence_verdict(fence, t, motion) else {
            self.fence.stopped = true;
            out.push(Effect::Arm(ArmCommand::Stop));
            self.warn(
                "refused: the telemetry does not place the tool (not a number)",
                now,
            );
            return;
        };
        if verdict.blocked() {
            if !self.fence.stopped {
                self.fence.stopped = true;
                out.push(Effect::Arm(ArmCommand::Stop));
                self.fence_whole_speed(out);
            }
        } else {
            let share = fence_watch::permille(&verdict);
            if share != self.fence.sent {
                self.fence.sent = share;
                out.push(Effect::Arm(ArmCommand::FenceSpeed(share)));
            }
            self.fence.stopped = false;
            out.push(Effect::Arm(ArmCommand::Jog(fence_watch::shaped(
                motion, &verdict,
            ))));
        }
        self.fence.verdict = Some(verdict);
    }

    /// Each sample: a held jog whose verdict changed goes out again (the net shapes it); a planned
    /// move heading into the fence is stopped; idle, where the tool is.
    fn watch_fence(&mut self, now: Instant, effects: &mut Vec<Effect>) {
        let (Some(fence), Some(t)) = (self.fence.kept.clone(), self.arm.telemetry().cloned())
        else {
            return;
        };
        self.fence.on_sample(now);
        if let Some(motion) = self.keys.jog().active() {
            let verdict = self.fence_verdict(&fence, &t, motion);
            let key = |v: &Verdict| (v.axes, fence_watch::permille(v));
            if verdict.as_ref().map(key) != self.fence.verdict.as_ref().map(key) {
                effects.push(Effect::Arm(ArmCommand::Jog(motion)));
            } else {
                self.fence.verdict = verdict;
            }
            return;
        }
        // A planned move is not slowed: its margin is its own speed's (the judge takes a tenth of
        // what it is given at contact). Idle, no heading: only a tool already across shows.
        let moving = self.motion_truth.action().is_some();
        let (heading, speed) = if moving {
            fence_watch::going(&t)
        } else {
            (fence_watch::STILL, 0.0)
        };
        let pace = Pace {
            speed_mm_s: speed / SLOWEST,
            joint_rate: 0.0,
            lookahead_s: self.fence.lookahead_s(),
        };
        let verdict =
            fence_watch::sample(&t, &heading).map(|sample| fence.judge(&sample, heading, pace));
        if moving
            && let Some(v) = verdict.as_ref().filter(|v| v.blocked())
            && let Some(text) = v.state.text()
        {
            self.stop_from_telemetry(format!("stopped: {text}"), now, effects);
        }
        self.fence.verdict = verdict;
    }

    /// Fresh telemetry under our motion: a fault, state or reading that forbids it stops it.
    pub(super) fn watch_arm_state(
        &mut self,
        t: &Telemetry,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) {
        if !self.keys.jog().is_jogging() && self.motion_truth.action().is_none() {
            return;
        }
        if let Some(why) = parts::arm_refusal(t) {
            self.stop_from_telemetry(format!("stopped: the arm reports {why}"), now, effects);
        }
    }
}
