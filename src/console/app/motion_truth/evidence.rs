//! Evidence from the driver: the link's status, telemetry and its timing, answers to what was
//! sent, and a STOP's outcome.

use std::time::Instant;

use super::INTERVALS_KEPT;
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
