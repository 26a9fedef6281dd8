//! Arm events in the state machine: link status, telemetry, the command log, failures,
//! positions the operator knows or not, commands done and the stop guard.

use std::time::Instant;

use super::message::Until;
use super::{App, Effect, Overlay, Severity};
use crate::link::interface::{
    ArmCommand, ArmError, ArmEvent, CommandKind, GuardStatus, LinkStatus,
};

impl App {
    pub(super) fn on_arm(&mut self, event: ArmEvent, now: Instant, effects: &mut Vec<Effect>) {
        self.truth_on_arm(&event, now);
        self.messages_on_arm(&event);
        if self.edits_on_arm(&event, now, effects) {
            return;
        }
        match event {
            ArmEvent::Status(status) => {
                if let LinkStatus::Down { reason } = &status {
                    // Stop through whatever link is left; the held keys stay latched so nothing
                    // restarts when the link comes back.
                    self.stop_jog(now, effects);
                    let text = format!("link lost: {reason}");
                    self.say_until(text, Severity::Error, Until::LinkUp, now);
                }
                let came_up = self.arm.on_link(status);
                if came_up && self.config.positions_on_operator {
                    // The ICD cannot list positions: ask about remembered names, so the panel
                    // marks the ones this operator does not know (and shows where the others
                    // are now).
                    self.check_names_on_operator(effects);
                }
            }
            ArmEvent::Telemetry(t) => {
                self.watch_cap(&t, now, effects);
                self.watch_arm_state(&t, now, effects);
                self.watch_other_clients(&t, now, effects);
                self.arm.on_telemetry(*t, now);
            }
            // The motion truth keeps the source (see `truth_on_arm`).
            ArmEvent::TelemetrySource(_) => {}
            ArmEvent::Latency(latency) => self.arm.on_latency(latency),
            ArmEvent::Speed(speed) => {
                if self.arm.on_speed(speed) {
                    self.other_client_note_speed(now);
                }
            }
            ArmEvent::Notice(text) => self.say(text, Severity::Warning, now),
            ArmEvent::Log(entry) => self.screen.on_log(entry),
            ArmEvent::Failed {
                error: error @ (ArmError::GuardStoppedArm(_) | ArmError::GuardStopFailed(_)),
                ..
            } => self.on_guard_stopped(&error, now, effects),
            ArmEvent::Failed { command, error } => {
                // A jog the arm did not take must not be left to the watchdog: stop and latch
                // the held keys, so only a new press moves again.
                if command == CommandKind::Jog {
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
                    self.say(
                        format!("the operator does not know '{name}'"),
                        Severity::Warning,
                        now,
                    );
                }
            }
            ArmEvent::Done { command } => self.on_done(command, now, effects),
            ArmEvent::Guard(status) => {
                // Without a ready guard the driver refuses motion and stops any: forget
                // the held keys so nothing restarts when the guard is back.
                if !matches!(status, GuardStatus::Ready { .. }) {
                    self.stop_jog(now, effects);
                }
                if let GuardStatus::Down { reason } = &status {
                    self.say_until(
                        format!("stop guard down, no motion until it is back: {reason}"),
                        Severity::Error,
                        Until::GuardReady,
                        now,
                    );
                }
                self.arm.on_guard(status);
            }
            // Evidence only: see `truth_on_arm`.
            ArmEvent::StopConfirmed | ArmEvent::StopUnconfirmed { .. } => {}
        }
    }

    /// The stop guard stopped the arm. The driver reports it as a failed jog (the held keys are
    /// latched as for one), whatever ran: the line names what it stopped, the tracked action
    /// (`go to 'bench' stopped: the stop guard stopped the arm: ...`), a jog or nothing, and the
    /// action is forgotten, so the arm's abort that follows is not said again as its failure. A
    /// STOP of our own confirms the end of what was ours.
    fn on_guard_stopped(&mut self, error: &ArmError, now: Instant, effects: &mut Vec<Effect>) {
        let jogging = self.keys.jog().is_jogging();
        self.stop_jog(now, effects);
        let stopped = match self.truth.action() {
            Some(action) => Some(action.kind.verb()),
            None => jogging.then(|| "jog".to_string()),
        };
        self.truth.forget_action();
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
        self.say(text, Severity::Error, now);
    }
}
