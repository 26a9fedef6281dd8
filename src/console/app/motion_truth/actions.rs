//! What ends a tracked action, as telemetry shows it. Pure; applied in `evidence.rs`.

use std::time::Instant;

use super::target::foreign_move;
use super::{ACTION_GRACE, MOVED_DEG, NO_MOTION_GRACE, TrackedAction};
use crate::kortex::arm_state::{abort_reason, at_rest, fault_reason};
use crate::kortex::{ActionStatus, Coded, Flag, Progress, Telemetry};

/// What one poll says of a tracked action's end.
pub(super) enum End {
    /// It failed: why, and whether the arm is in fault (the message stays until it is not).
    Failed { reason: String, fault: bool },
    /// The arm runs, or ended, a move that is not ours (`target`): what shows it.
    MovedByAnotherClient(String),
    /// It ended and the arm is at rest (where it was sent, for a go-to).
    Done,
}

/// A stored run's progress as an end: completed at rest, or aborted, faulted or not taken.
pub(super) fn run_end(progress: Progress) -> Option<End> {
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

/// The end of an action not followed by id (home, go-to, step): the action status where current,
/// joints at rest after moving, a joint-fault warning at rest, or a fault. A go-to's end is ours
/// only if `target` says so.
pub(super) fn heuristic_end(
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
