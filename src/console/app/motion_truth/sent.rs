//! What the console sends, noted after every input: a stale link lets no motion start, a
//! failed or unwatched action gets a STOP, and each command sent is remembered as evidence
//! awaited (an answer, a STOP's confirmation, an action's end). A tracked action's end, seen in
//! telemetry (done, aborted, faulted, a stored run not taken; what ends it: `actions`), or its
//! time running out.

use std::time::Instant;

use super::actions::{End, heuristic_end, run_end};
use super::{
    ACTION_TIMEOUT, ActionKind, GoToTarget, NO_TELEMETRY_ACTION_TIME, StoredAction, TrackedAction,
};
use crate::console::app::age::age_text;
use crate::console::app::message::Until;
use crate::console::app::{App, Effect, Severity};
use crate::kortex::{Flag, MoveType, OurMove, StoredRun, Telemetry};
use crate::link::interface::ArmCommand;

impl App {
    /// After every input: a stale link starts no motion (a command held up in a frozen network
    /// could run whenever it thaws) and stops the jog; tracked actions time out; the commands
    /// just emitted are noted.
    pub(in crate::console::app) fn truth_after(
        &mut self,
        goto: Option<String>,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) {
        // Whatever emitted it, no motion starts while the gate refuses (a stale link above all).
        self.gate_effects(now, effects);
        if let Some(age) = self.link_stale() {
            // An action the console can no longer watch is stopped like a jog: the arm must
            // not go on moving unseen.
            if self.truth.action.is_some() {
                self.truth.stop_needed = true;
            }
            if self.keys.jog().is_jogging() {
                self.stop_jog(now, effects);
                self.say_until(
                    format!(
                        "link stale: no word from the arm for {}: jog stopped",
                        age_text(age)
                    ),
                    Severity::Error,
                    Until::LinkFresh,
                    now,
                );
            }
        }
        self.time_out_action(now);
        if std::mem::take(&mut self.truth.stop_needed) && !effects.iter().any(Effect::is_stop) {
            effects.push(Effect::Arm(ArmCommand::Stop));
        }
        for effect in effects.iter() {
            let Effect::Arm(command) = effect else {
                continue;
            };
            self.note_sent(command, goto.clone(), now);
            self.other_client_note_sent(command, now);
        }
    }

    fn note_sent(&mut self, command: &ArmCommand, goto: Option<String>, now: Instant) {
        // Where a go-to must end, and the move the arm's status shows for it (see `target`).
        let (target, move_type) = match command {
            ArmCommand::MoveToPose(pose) => (
                Some(GoToTarget::pose(*pose)),
                Some(OurMove {
                    move_type: MoveType::CartesianTrajectory,
                    id: None,
                }),
            ),
            ArmCommand::GoToPosition { name } => (
                self.book.positions().get(name).and_then(GoToTarget::book),
                None,
            ),
            _ => (None, None),
        };
        let truth = &mut self.truth;
        truth.waiting_since.get_or_insert(now);
        if command.is_stop() {
            truth.stop_sent = Some(now);
            truth.motion_since_stop = false;
            truth.stop_confirmed_at = None;
            if let Some(action) = truth.action.take() {
                let verb = action.kind.verb();
                self.say(format!("{verb} stopped"), Severity::Info, now);
            }
            return;
        }
        let kind = match command {
            ArmCommand::Jog(_) => None,
            ArmCommand::Home => Some(ActionKind::HOME),
            ArmCommand::StartStored(stored) => {
                Some(ActionKind::Stored(StoredAction::ById(*stored)))
            }
            ArmCommand::GoToPosition { name } => Some(ActionKind::GoTo(name.clone())),
            ArmCommand::MoveToPose(_) => Some(ActionKind::GoTo(goto.unwrap_or_default())),
            ArmCommand::Step(_) => Some(ActionKind::Step),
            _ => return,
        };
        truth.unsettled = true;
        truth.motion_since_stop = true;
        truth.stop_confirmed_at = None;
        // A new motion replaces whatever action was running.
        let last = self.arm.telemetry();
        truth.action = kind.map(|kind| TrackedAction {
            run: match kind {
                ActionKind::Stored(StoredAction::ById(stored)) => Some(StoredRun::new(stored)),
                ActionKind::Stored(StoredAction::Home) => {
                    self.config.home_action.map(StoredRun::new)
                }
                _ => None,
            },
            kind,
            sent: now,
            accepted: None,
            target,
            move_type,
            seen_ours: false,
            from: last.map(|t| t.joints.map(|j| j.position)),
            warned_before: last.is_some_and(|t| t.warnings.contains(Flag::JointFault)),
            seen_motion: false,
            seen_started: false,
        });
    }
}

impl App {
    /// Watches a tracked action's end in fresh telemetry: a stored run of a known id by the
    /// arm's action status for that run ([`crate::kortex::StoredRun::observe`], as `armjog
    /// modbus action` reads it), any other by [`heuristic_end`]. Either end is said one way.
    pub(super) fn watch_action(&mut self, t: &Telemetry, now: Instant) {
        let Some(action) = self.truth.action.as_mut() else {
            return;
        };
        let Some(accepted) = action.accepted else {
            return;
        };
        let end = match action.run.as_mut() {
            Some(run) => run_end(run.observe(t, now.saturating_duration_since(accepted))),
            None => heuristic_end(action, accepted, t, now),
        };
        let verb = action.kind.verb();
        match end {
            Some(End::Failed { reason, fault }) => {
                self.truth.action = None;
                self.truth.stop_needed = true;
                // A fault's message stays until the fault is gone; an abort's is a notice.
                let until = match fault {
                    true => Until::fault(None, true),
                    false => Until::TimeOut { done: None },
                };
                let text = format!("{verb} failed: {reason}");
                self.say_until(text, Severity::Error, until, now);
            }
            Some(End::MovedByAnotherClient(evidence)) => {
                // Not ours: stopped like a failure, and never said done.
                self.truth.action = None;
                self.truth.stop_needed = true;
                let text = format!("{verb} not done: MOVED BY ANOTHER CLIENT: {evidence}; stopped");
                self.say(text, Severity::Error, now);
            }
            Some(End::Done) => {
                // The arm reported the end and telemetry shows it at rest: settled.
                self.truth.action = None;
                self.truth.unsettled = false;
                self.say(format!("{verb} done"), Severity::Info, now);
            }
            None => {}
        }
    }

    pub(super) fn time_out_action(&mut self, now: Instant) {
        let Some(action) = &self.truth.action else {
            return;
        };
        let with_telemetry = self.truth.expects_telemetry();
        let limit = if with_telemetry {
            ACTION_TIMEOUT
        } else {
            NO_TELEMETRY_ACTION_TIME
        };
        if now < action.sent + limit {
            return;
        }
        let verb = action.kind.verb();
        self.truth.action = None;
        if with_telemetry {
            self.say(
                format!("{verb}: no end seen within {} s", limit.as_secs()),
                Severity::Warning,
                now,
            );
        } else {
            // Documented choice: without telemetry an action is taken to have ended once its
            // longest expected time has passed.
            self.truth.unsettled = false;
            self.say(
                format!(
                    "{verb}: no telemetry; taken as ended after {} s",
                    limit.as_secs()
                ),
                Severity::Info,
                now,
            );
        }
    }
}
