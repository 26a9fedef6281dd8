//! Capped moves: a Kinova cartesian trajectory or stored action runs at the arm's configured
//! limits, so the link lowers them (holding registers 216-219, never raising) for the move and
//! restores the limits in force before the first capped move: when a poll shows the move ended (or
//! [`START_GRACE`] passed unseen), after any stop, when a twist replaces it, and on close (stopped
//! first, so it never runs on at restored limits).
//!
//! Gap: a process dying between lowering and restoring leaves the lower limits (the safe side); the
//! restore failure is logged and sent as [`ModbusEvent::SpeedLimitsNotRestored`].

use std::time::Duration;

use tokio::time::Instant;

use super::{LinkTask, ModbusError, ModbusEvent, PollScope, StopReason, WriteReport};
use crate::kortex::commands::{self, Write};
use crate::kortex::{ActionStatus, CodeName, Coded, MoveType, SpeedLimits, Telemetry, at_rest};

/// How long a capped move may take to show started before its limits are restored.
pub(super) const START_GRACE: Duration = Duration::from_secs(2);

/// The limits owed back to the arm, and how far the move they were lowered for has got.
#[derive(Debug, Clone, Copy)]
pub(in crate::link::modbus) struct LimitHold {
    pub(super) original: SpeedLimits,
    seen_running: bool,
    sent_at: Instant,
}

impl LinkTask {
    /// Runs `writes` (a move) with the arm's speed limits at most `cap` (m/s, deg/s).
    pub(super) async fn capped_move(
        &mut self,
        writes: &[Write],
        cap: SpeedLimits,
    ) -> Result<WriteReport, ModbusError> {
        let mut report = self.lower_limits(cap).await?;
        match self.execute(writes).await {
            Ok(moved) => {
                report.writes.extend(moved.writes);
                report.elapsed += moved.elapsed;
                Ok(report)
            }
            Err(e) => {
                // The move did not start: nothing needs the lower limits.
                self.restore_limits().await;
                Err(e)
            }
        }
    }

    /// Lowers each limit to `cap` (or owed limits); no write if already right.
    async fn lower_limits(&mut self, cap: SpeedLimits) -> Result<WriteReport, ModbusError> {
        // A fresh read: the limits may have been changed by someone else since the last poll.
        let telemetry = self.poll_scoped(PollScope::Everything).await?;
        let in_force = telemetry.speed_limits;
        let original = self.limit_hold.map_or(in_force, |h| h.original);
        let valid = |v: f32| v.is_finite() && v > 0.0;
        if !(valid(original.linear) && valid(original.angular)) {
            return Err(ModbusError::SpeedLimitsUnknown {
                linear: original.linear,
                angular: original.angular,
            });
        }
        let wanted = SpeedLimits {
            linear: cap.linear.min(original.linear),
            angular: cap.angular.min(original.angular),
        };
        let lowered = wanted != original;
        // Only limits actually lowered are owed back; limits already under the cap are left alone.
        if self.limit_hold.is_none()
            && in_force != wanted
            && let Some(other) = capped_move_running(&telemetry)
        {
            return Err(ModbusError::AnotherMoveRuns(other));
        }
        let mut report = WriteReport::default();
        if in_force != wanted {
            let writes = commands::speed_limits(wanted.linear, wanted.angular)?;
            // Owed back from the moment the write may have landed.
            self.hold(original);
            report = self.execute_read_back(&writes).await?;
            if lowered {
                tracing::info!(
                    "speed limits lowered to {} m/s, {} deg/s for a capped move (were {} m/s, \
                     {} deg/s)",
                    wanted.linear,
                    wanted.angular,
                    original.linear,
                    original.angular
                );
                self.event(ModbusEvent::SpeedLimitsLowered {
                    limits: wanted,
                    previous: original,
                });
            }
        }
        if lowered {
            self.hold(original);
        } else {
            // The move is allowed the original limits, which are now in force.
            self.limit_hold = None;
        }
        Ok(report)
    }

    fn hold(&mut self, original: SpeedLimits) {
        self.limit_hold = Some(LimitHold {
            original,
            seen_running: false,
            sent_at: Instant::now(),
        });
    }

    /// Restores owed limits; kept owed on a broken connection, dropped on refusal.
    pub(super) async fn restore_limits(&mut self) {
        let Some(hold) = self.limit_hold else {
            return;
        };
        let limits = hold.original;
        let result = match commands::speed_limits(limits.linear, limits.angular) {
            Ok(writes) => self.execute_read_back(&writes).await.map(|_| ()),
            Err(e) => Err(e.into()),
        };
        match result {
            Ok(()) => {
                self.limit_hold = None;
                tracing::info!("speed limits restored to {limits:?}");
                self.event(ModbusEvent::SpeedLimitsRestored { limits });
            }
            Err(e) if self.ctx.is_none() => {
                tracing::warn!("speed limits not restored yet ({e}); retrying after the reconnect");
            }
            Err(e) => {
                self.limit_hold = None;
                tracing::error!(
                    "SPEED LIMITS NOT RESTORED: the arm keeps the lowered ones; set {} m/s and {} deg/s again: {e}",
                    limits.linear,
                    limits.angular
                );
                self.event(ModbusEvent::SpeedLimitsNotRestored {
                    limits,
                    error: e.into(),
                });
            }
        }
    }

    /// After a stop: its move no longer needs the lower limits (unless it makes way for the next).
    pub(super) async fn restore_after_stop(&mut self, reason: StopReason) {
        if reason != StopReason::Replaced {
            self.restore_limits().await;
        }
    }

    /// Writes a new twist or polar pan: once written it replaced any capped move.
    pub(super) async fn write_replacing(
        &mut self,
        writes: &[Write],
    ) -> Result<WriteReport, ModbusError> {
        let written = self.write_motion(writes).await;
        if written.is_ok() && self.limit_hold.is_some() {
            self.restore_limits().await;
        }
        written
    }

    /// Follows a capped move through the polls and restores the limits once it has ended.
    pub(super) async fn note_action(&mut self, telemetry: &Telemetry) {
        let Some(hold) = self.limit_hold.as_mut() else {
            return;
        };
        let running = matches!(
            telemetry.action.status,
            Coded::Known(ActionStatus::Started | ActionStatus::Paused)
        );
        if running {
            hold.seen_running = true;
            return;
        }
        if hold.seen_running || hold.sent_at.elapsed() >= START_GRACE {
            self.restore_limits().await;
        }
    }
}

/// Another client's move the arm runs at its speed limits, started and not at rest, in words. Asked
/// only while this link holds no limits of its own.
fn capped_move_running(t: &Telemetry) -> Option<String> {
    let action = &t.action;
    let capped = matches!(
        action.move_type,
        Coded::Known(MoveType::Action | MoveType::Sequence | MoveType::CartesianTrajectory)
    );
    let started = action.status == Coded::Known(ActionStatus::Started);
    (capped && started && !at_rest(t)).then(|| match action.move_type {
        Coded::Known(MoveType::CartesianTrajectory) => "a cartesian trajectory".to_string(),
        Coded::Known(kind) => format!("{} {}", kind.key(), action.id),
        Coded::Unknown(_) => "a move".to_string(),
    })
}
