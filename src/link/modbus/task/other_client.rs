//! A twist or polar pan stopped or replaced by another client: any client's STOP stops the arm, and
//! the same twist asked again (a refresh) must not restart it.
//!
//! Evidence: the action status reads aborted or completed, or the move type leaves twist, while
//! ours is in force; the status is trusted once read started since our write, or [`STATUS_GRACE`]
//! after it. The motion is then dropped without a write until a stop or a different motion.

use std::time::Duration;

use tokio::time::Instant;

use super::{LinkTask, MotionInForce};
use crate::kortex::{ActionStatus, Coded, MoveType, Telemetry};

/// A status read this soon after our twist write may still be the one before it.
pub(super) const STATUS_GRACE: Duration = Duration::from_millis(500);

/// When our twist was written, and whether the arm has reported it started since.
#[derive(Debug, Clone, Copy)]
pub(super) struct TwistStart {
    at: Instant,
    seen_started: bool,
    /// The move type has read twist since our write: only then is another type a change.
    seen_twist: bool,
}

impl TwistStart {
    pub(super) fn now() -> TwistStart {
        TwistStart {
            at: Instant::now(),
            seen_started: false,
            seen_twist: false,
        }
    }
}

impl LinkTask {
    /// A fresh poll: drops the motion in force if another client ended it.
    pub(super) fn note_motion_ended_by_other_client(&mut self, telemetry: &Telemetry) {
        let Some(start) = self.twist_start.as_mut() else {
            return;
        };
        if self.motion == MotionInForce::Idle {
            return;
        }
        let status = telemetry.action.status;
        if status == Coded::Known(ActionStatus::Started) {
            start.seen_started = true;
        }
        let move_type = telemetry.action.move_type;
        if move_type == Coded::Known(MoveType::Twist) {
            start.seen_twist = true;
        }
        if !start.seen_started && start.at.elapsed() < STATUS_GRACE {
            return;
        }
        let ended = matches!(
            status,
            Coded::Known(ActionStatus::Aborted | ActionStatus::Completed)
        );
        let replaced =
            start.seen_twist && matches!(move_type, Coded::Known(m) if m != MoveType::Twist);
        if !(ended || replaced) {
            return;
        }
        tracing::warn!(
            "the arm's action is {} ({}) under our twist: stopped or replaced by another client; \
             not restarting it",
            status.key(),
            telemetry.action.move_type.key()
        );
        self.ended_by_other_client = Some(self.motion);
        self.motion = MotionInForce::Idle;
        self.hold_until = None;
        self.twist_start = None;
    }

    /// Whether `wanted` is the motion another client ended: asked again, it writes nothing.
    pub(super) fn ended_by_other_client(&self, wanted: &MotionInForce) -> bool {
        self.ended_by_other_client
            .is_some_and(|ended| ended.same_ask(wanted))
    }
}
