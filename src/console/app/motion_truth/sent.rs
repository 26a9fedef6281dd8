//! What the console sends, noted after every input: a stale link lets no motion start, a
//! failed or unwatched action gets a STOP, and each command sent is remembered as evidence
//! awaited (an answer, a STOP's confirmation, an action's end).

use std::time::Instant;

use super::{ActionKind, GoToTarget, StoredAction, TrackedAction};
use crate::console::app::age::age_text;
use crate::console::app::message::Until;
use crate::console::app::{App, Effect, Severity};
use crate::kortex::{Flag, MoveType, OurMove, StoredRun};
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
