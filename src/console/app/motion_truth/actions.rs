//! A tracked action's end: seen in telemetry (done, aborted, faulted, a stored run not taken),
//! or its time running out.

use std::time::Instant;

use super::target::foreign_move;
use super::{
    ACTION_GRACE, ACTION_TIMEOUT, MOVED_DEG, NO_MOTION_GRACE, NO_TELEMETRY_ACTION_TIME,
    TrackedAction,
};
use crate::console::app::message::Until;
use crate::console::app::{App, Severity};
use crate::kortex::arm_state::{abort_reason, at_rest, fault_reason};
use crate::kortex::{ActionStatus, Coded, Flag, Progress, Telemetry};

/// What one poll says of a tracked action's end.
enum End {
    /// It failed: why, and whether the arm is in fault (the message stays until it is not).
    Failed { reason: String, fault: bool },
    /// The arm runs, or ended, a move that is not ours (`target`): what shows it.
    MovedByAnotherClient(String),
    /// It ended and the arm is at rest (where it was sent, for a go-to).
    Done,
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

/// A stored run's progress as an end: completed at rest, or aborted, faulted or not taken.
fn run_end(progress: Progress) -> Option<End> {
    match progress {
        Progress::Completed => Some(End::Done),
        Progress::Fault(reason) => Some(End::Failed {
            reason,
            fault: true,
        }),
        Progress::Aborted(reason) | Progress::NotTaken(reason) => Some(End::Failed {
            reason,
            fault: false,
        }),
        Progress::OtherMove(evidence) => Some(End::MovedByAnotherClient(evidence)),
        Progress::Pending | Progress::Started | Progress::Running => None,
    }
}

/// The end of an action with no run to follow by id (home, a go-to, a step): the arm's action
/// status where it is current, joints at rest after having moved (Talos hardware telemetry has
/// no status), a joint-fault warning at rest, or a fault. A go-to's end is ours only if the
/// status names our move and the arm is at rest where it was sent (`target`).
fn heuristic_end(
    action: &mut TrackedAction,
    accepted: Instant,
    t: &Telemetry,
    now: Instant,
) -> Option<End> {
    let rest = at_rest(t);
    let moved = action.from.is_some_and(|from| {
        from.iter().zip(&t.joints).any(|(a, j)| {
            let d = (j.position - a).rem_euclid(360.0);
            d.min(360.0 - d) > MOVED_DEG
        })
    });
    action.seen_motion |= !rest || moved;
    if t.action.status == Coded::Known(ActionStatus::Started) {
        action.seen_started = true;
    }
    // A status read before the command took effect may belong to an earlier action.
    let status_current =
        action.seen_started || action.seen_motion || now >= accepted + ACTION_GRACE;
    // A joint-fault warning raised since the start: the arm stopped at a limit.
    let joint_fault =
        t.warnings.contains(Flag::JointFault) && (action.seen_motion || !action.warned_before);
    let aborted = (status_current && t.action.status == Coded::Known(ActionStatus::Aborted))
        || (rest && joint_fault);
    if let Some(reason) = fault_reason(t) {
        return Some(End::Failed {
            reason,
            fault: true,
        });
    }
    if let Some(evidence) = foreign_move(action, accepted, t, now) {
        return Some(End::MovedByAnotherClient(evidence));
    }
    if aborted {
        return Some(End::Failed {
            reason: abort_reason(t),
            fault: false,
        });
    }
    let done = rest
        && match t.action.status {
            Coded::Known(ActionStatus::Completed) => status_current,
            Coded::Known(ActionStatus::Started) => false,
            _ => action.seen_motion || now >= accepted + NO_MOTION_GRACE,
        };
    if !done {
        return None;
    }
    match action
        .target
        .and_then(|target| target.missed_by(&t.tcp.pose))
    {
        Some(evidence) => Some(End::MovedByAnotherClient(evidence)),
        None => Some(End::Done),
    }
}
