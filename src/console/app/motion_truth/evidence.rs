//! Evidence from the driver: the link's status, telemetry and its timing, answers to what was
//! sent, and a STOP's outcome; what the status bar says about motion from the evidence kept;
//! how old the link and the telemetry are (the rule: `staleness`), and the next instant the
//! screen changes without any input.

use std::time::{Duration, Instant};

use super::{INTERVALS_KEPT, MotionShown, STOP_GRACE, TruthView};
use crate::console::app::age::age_text;
use crate::console::app::message::Until;
use crate::console::app::{App, Severity};
use crate::kortex::arm_state::at_rest;
use crate::link::interface::{ArmEvent, LinkStatus};

impl App {
    /// Evidence from the driver, before the event is otherwise handled.
    pub(in crate::console::app) fn truth_on_arm(&mut self, event: &ArmEvent, now: Instant) {
        let truth = &mut self.truth;
        match event {
            ArmEvent::Status(status) => {
                let came_up = matches!(status, LinkStatus::Up { .. }) && !self.arm.link_up();
                if came_up {
                    truth.link_up_at = Some(now);
                    truth.waiting_since = None;
                    // Back after a loss with motion unaccounted for: a STOP is always safe, and
                    // its confirmation (with telemetry at rest) is the evidence that clears
                    // MAY BE MOVING.
                    if truth.unsettled || truth.action.is_some() {
                        truth.stop_needed = true;
                    }
                }
            }
            ArmEvent::TelemetrySource(source) => truth.expect = Some(*source),
            ArmEvent::Telemetry(t) => {
                if let Some(last) = truth.telemetry_at {
                    let interval = now.saturating_duration_since(last);
                    if truth.intervals.len() >= INTERVALS_KEPT {
                        truth.intervals.pop_front();
                    }
                    truth.intervals.push_back(interval);
                }
                truth.telemetry_at = Some(now);
                truth.telemetry_moving = !at_rest(t);
                if !truth.telemetry_moving
                    && truth
                        .stop_confirmed_at
                        .is_some_and(|confirmed| now >= confirmed)
                {
                    truth.unsettled = false;
                    truth.stop_confirmed_at = None;
                }
            }
            // Sent for polls as well as replies: no answer to a command.
            ArmEvent::Latency(_) => {}
            // The console's own guard process speaks, not the arm.
            ArmEvent::Guard(_) => {}
            // Said by the driver itself, with the answer it reports apart.
            ArmEvent::Notice(_) => {}
            ArmEvent::Log(entry) if entry.poll => {}
            ArmEvent::Log(_)
            | ArmEvent::Speed(_)
            | ArmEvent::Done { .. }
            | ArmEvent::Failed { .. }
            | ArmEvent::Position { .. }
            | ArmEvent::UnknownPosition { .. } => truth.waiting_since = None,
            ArmEvent::StopConfirmed => {
                truth.waiting_since = None;
                truth.stop_sent = None;
                if !truth.motion_since_stop {
                    truth.stop_failure = None;
                    if truth.expects_telemetry() {
                        truth.stop_confirmed_at = Some(now);
                    } else {
                        truth.unsettled = false;
                    }
                }
            }
            ArmEvent::StopUnconfirmed { reason } => {
                truth.waiting_since = None;
                truth.stop_sent = None;
                truth.stop_failure = Some(reason.clone());
                truth.stop_confirmed_at = None;
            }
        }
        match event {
            ArmEvent::Telemetry(t) => self.watch_action(t, now),
            ArmEvent::Done { command } => {
                if let Some(action) = self.truth.action.as_mut()
                    && action.kind.answers(command)
                {
                    action.accepted.get_or_insert(now);
                }
            }
            ArmEvent::Failed { command, .. }
                if self
                    .truth
                    .action
                    .as_ref()
                    .is_some_and(|a| a.kind.failed_by(*command)) =>
            {
                // The failure itself is said by the caller; a STOP settles the doubt.
                self.truth.action = None;
                self.truth.stop_needed = true;
            }
            ArmEvent::StopUnconfirmed { reason } => {
                self.say_until(
                    format!(
                        "STOP NOT CONFIRMED: {reason}. The arm may still be moving: use its e-stop"
                    ),
                    Severity::Error,
                    Until::StopConfirmed,
                    now,
                );
            }
            _ => {}
        }
    }
}

impl App {
    /// The truth's part of the view: the motion shown and the ages that make things stale.
    pub(in crate::console::app) fn truth_view(&self) -> TruthView {
        TruthView {
            motion: self.motion_shown(),
            link_stale: self.link_stale(),
            telemetry_source: self.telemetry_source(),
            telemetry_stale: self.telemetry_stale(),
            cap_watched: self.cap_watched(),
        }
    }

    /// What the status bar says about motion, by precedence: a jog, a tracked action, a STOP
    /// being confirmed, any doubt, idle.
    pub fn motion_shown(&self) -> MotionShown {
        if let Some(motion) = self.keys.jog().active() {
            return MotionShown::Jog(motion);
        }
        let truth = &self.truth;
        if let Some(action) = &truth.action {
            return MotionShown::Action {
                label: action.kind.label(),
                confirmed: truth.expects_telemetry(),
            };
        }
        let Some(now) = self.now else {
            return MotionShown::Idle;
        };
        if let Some(reason) = &truth.stop_failure {
            return MotionShown::MayBeMoving(format!("stop not confirmed: {reason}"));
        }
        if truth.unsettled {
            match self.arm.link() {
                LinkStatus::Up { .. } => {}
                _ => return MotionShown::MayBeMoving("link lost after motion".into()),
            }
            if let Some(age) = self.link_stale() {
                return MotionShown::MayBeMoving(format!(
                    "no word from the arm for {}",
                    age_text(age)
                ));
            }
        }
        let within = |at: Option<Instant>| at.is_some_and(|at| now < at + STOP_GRACE);
        if within(truth.stop_sent) || (truth.unsettled && within(truth.stop_confirmed_at)) {
            return MotionShown::Stopping;
        }
        let telemetry_fresh = self.telemetry_stale().is_none() && truth.telemetry_at.is_some();
        if telemetry_fresh && self.moved_by_another_client() {
            return MotionShown::MovedByAnotherClient;
        }
        if telemetry_fresh && truth.telemetry_moving {
            return MotionShown::MayBeMoving("telemetry shows motion".into());
        }
        if truth.stop_sent.is_some() {
            return MotionShown::MayBeMoving("stop not acknowledged".into());
        }
        if truth.unsettled {
            let why = if truth.stop_confirmed_at.is_some() {
                "no telemetry at rest since the stop"
            } else {
                "motion not shown to have ended: press stop"
            };
            return MotionShown::MayBeMoving(why.into());
        }
        MotionShown::Idle
    }
}

impl App {
    /// How long the link has been silent, when that makes it stale (only while it is up).
    pub fn link_stale(&self) -> Option<Duration> {
        let now = self.now?;
        match self.arm.link() {
            LinkStatus::Up { .. } => self.truth.stale_for(now),
            _ => None,
        }
    }

    /// The age of the telemetry shown, when it is old enough to be drawn as stale.
    pub fn telemetry_stale(&self) -> Option<Duration> {
        let (now, at) = (self.now?, self.truth.telemetry_at?);
        let age = now.saturating_duration_since(at);
        (age >= self.truth.stale_after()).then_some(age)
    }

    /// The truth's part of [`App::next_deadline`].
    pub(in crate::console::app) fn truth_deadline(&self) -> Option<Instant> {
        let now = self.now?;
        self.truth.next_deadline(now, self.arm.link_up())
    }
}
