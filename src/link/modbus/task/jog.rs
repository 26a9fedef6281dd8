//! Jogs held while refreshed, written only when they change; a pan recomputed from each pose.

use tokio::time::Instant;

use super::{LinkTask, ModbusError, MotionInForce, StopReason, WriteReport};
use crate::kortex::commands;
use crate::kortex::{PolarPanSettings, Pose, ReferenceFrame, Twist, polar_twist};

impl LinkTask {
    pub(super) async fn jog_twist(
        &mut self,
        frame: ReferenceFrame,
        twist: Twist,
    ) -> Result<WriteReport, ModbusError> {
        if twist.is_zero() {
            return self.stop(StopReason::Requested).await;
        }
        let wanted = MotionInForce::Twist { frame, twist };
        if self.motion == wanted {
            self.refresh_hold();
            return Ok(WriteReport::default());
        }
        if self.ended_by_other_client(&wanted) {
            return Ok(WriteReport::default());
        }
        let writes = commands::twist(frame, twist)?;
        self.motion = wanted;
        self.refresh_hold();
        self.write_replacing(&writes).await
    }

    pub(super) async fn polar_pan(
        &mut self,
        azimuth: f32,
        altitude: f32,
        settings: PolarPanSettings,
    ) -> Result<WriteReport, ModbusError> {
        if azimuth == 0.0 && altitude == 0.0 {
            return self.stop(StopReason::Requested).await;
        }
        let wanted = MotionInForce::Polar {
            azimuth,
            altitude,
            settings,
            twist: Twist::ZERO,
        };
        if self.motion.same_ask(&wanted) {
            self.refresh_hold();
            return Ok(WriteReport::default());
        }
        if self.ended_by_other_client(&wanted) {
            return Ok(WriteReport::default());
        }
        // A fresh pose, not the last poll's: the new direction starts from where the arm is.
        let pose = self.poll_or_stop().await?.tcp.pose;
        let twist = match polar_twist(pose, azimuth, altitude, settings) {
            Ok(twist) => twist,
            Err(e) => {
                if self.motion != MotionInForce::Idle {
                    let _ = self.stop(StopReason::PolarPanUndefined).await;
                }
                return Err(e.into());
            }
        };
        self.motion = MotionInForce::Polar {
            azimuth,
            altitude,
            settings,
            twist,
        };
        self.refresh_hold();
        let writes = commands::twist(ReferenceFrame::Base, twist)?;
        self.write_replacing(&writes).await
    }

    /// Recomputes a running polar pan from the pose just polled.
    pub(super) async fn refresh_polar(&mut self, pose: Pose) {
        let MotionInForce::Polar {
            azimuth,
            altitude,
            settings,
            twist: last,
        } = self.motion
        else {
            return;
        };
        let writes = polar_twist(pose, azimuth, altitude, settings)
            .map_err(ModbusError::from)
            .and_then(|twist| Ok((twist, commands::twist(ReferenceFrame::Base, twist)?)));
        match writes {
            Ok((twist, _)) if twist == last => {}
            Ok((twist, writes)) => {
                self.motion = MotionInForce::Polar {
                    azimuth,
                    altitude,
                    settings,
                    twist,
                };
                let _ = self.write_motion(&writes).await;
            }
            Err(e) => {
                tracing::warn!("polar pan stopped: {e}");
                let _ = self.stop(StopReason::PolarPanUndefined).await;
            }
        }
    }

    pub(super) fn refresh_hold(&mut self) {
        self.hold_until = self.config.twist_hold.map(|hold| Instant::now() + hold);
    }
}
