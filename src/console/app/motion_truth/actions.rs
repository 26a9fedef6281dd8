//! A tracked action's end: seen in telemetry (done, aborted, faulted), or its time running out.

use std::time::Instant;

use super::{ACTION_GRACE, ACTION_TIMEOUT, MOVED_DEG, NO_MOTION_GRACE, NO_TELEMETRY_ACTION_TIME};
use crate::console::app::message::Until;
use crate::console::app::{App, Severity};
use crate::kortex::arm_state::{abort_reason, at_rest, fault_reason};
use crate::kortex::{ActionStatus, Coded, Flag, Telemetry};

impl App {
    /// Watches a tracked action's end in fresh telemetry.
    pub(super) fn watch_action(&mut self, t: &Telemetry, now: Instant) {
        let Some(action) = self.truth.action.as_mut() else {
            return;
        };
        let Some(accepted) = action.accepted else {
            return;
        };
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
        let verb = action.kind.verb();
        // A joint-fault warning raised since the start: the arm stopped at a limit.
        let joint_fault =
            t.warnings.contains(Flag::JointFault) && (action.seen_motion || !action.warned_before);
        let aborted = (status_current && t.action.status == Coded::Known(ActionStatus::Aborted))
            || (rest && joint_fault);
        let fault = fault_reason(t);
        // A fault's message stays until the fault is gone; an abort's is a notice.
        let until = match fault {
            Some(_) => Until::fault(None, true),
            None => Until::TimeOut { done: None },
        };
        let failure = fault.or_else(|| aborted.then(|| abort_reason(t)));
        if let Some(reason) = failure {
            self.truth.action = None;
            self.truth.stop_needed = true;
            let text = format!("{verb} failed: {reason}");
            self.say_until(text, Severity::Error, until, now);
            return;
        }
        let done = rest
            && match t.action.status {
                Coded::Known(ActionStatus::Completed) => status_current,
                Coded::Known(ActionStatus::Started) => false,
                _ => action.seen_motion || now >= accepted + NO_MOTION_GRACE,
            };
        if done {
            // The arm reported the end and telemetry shows it at rest: settled.
            self.truth.action = None;
            self.truth.unsettled = false;
            self.say(format!("{verb} done"), Severity::Info, now);
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
