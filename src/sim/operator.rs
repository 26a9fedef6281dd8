//! The simulated Talos operator: what each ICD command means to the simulated arm. Pure:
//! [`Operator::handle`] takes a request and the arm and returns the reply.
//!
//! Where the ICD is silent it does what `docs/simulator.md` says (the speed cap over every
//! motion, the 500 ms watchdog, a holder's closed connection); besides: either STOP stops any
//! continuous motion, an all-zero START too; discrete moves honour Delay, and a non-zero Time
//! sets their speed (never over the maximum).
//! - Polar coordinates are about the base origin: delta is elevation, azimuth from +X towards +Y,
//!   radius in tenths of mm. An anchored position moves with its parent; deleting the parent
//!   freezes it.

use std::collections::BTreeMap;

use nalgebra::Vector3;

use super::arm_model::{Arm, ReferenceFrame, Refusal, SimMotion, polar_target};
use super::kinematics::{self, HOME_DEG};
use crate::talos::hardware::HwRequest;
use crate::talos::message::DecodeError;

mod clients;
mod hardware;
mod positions;
mod restore;
use crate::talos::{Reply, Request, ReturnCode};
pub use clients::ClientId;
use hardware::hardware_operation;
pub use positions::SavedPosition;
pub use restore::RememberedPosition;

/// The simulated operator's version, reported by Handshake.
pub const VERSION: (u8, u8) = (1, 0);

/// Cartesian jog speed at 100 % by default, m/s (ISO 10218-1 reduced speed).
pub const MAX_JOG_LINEAR: f64 = 0.25;
/// Polar pan rate at 100 %, deg/s.
pub const MAX_JOG_ANGULAR_DEG: f64 = 30.0;
/// Joint-space moves (home, go to) at 100 % run at this fraction of the joints' top speed.
const MAX_JOINT_FRACTION: f64 = 0.5;
const DEFAULT_SPEED: u8 = 50;

/// The operator's state beyond the arm.
#[derive(Debug, Clone)]
pub struct Operator {
    speed: u8,
    /// Cartesian speed at 100 %, m/s.
    max_jog_linear: f64,
    positions: BTreeMap<String, SavedPosition>,
    /// The client whose command last started or refreshed the running continuous motion.
    holder: Option<ClientId>,
}

impl Default for Operator {
    fn default() -> Self {
        Operator {
            speed: DEFAULT_SPEED,
            max_jog_linear: MAX_JOG_LINEAR,
            positions: BTreeMap::new(),
            holder: None,
        }
    }
}

fn refusal_code(refusal: Refusal) -> ReturnCode {
    match refusal {
        Refusal::InFault => ReturnCode::ARM_FAULT,
        Refusal::Unreachable => ReturnCode::UNREACHABLE,
        Refusal::JointLimit(_) => ReturnCode::JOINT_LIMIT,
        Refusal::OutOfRange | Refusal::NotFinite => ReturnCode::OUT_OF_RANGE,
    }
}

impl Operator {
    /// An operator whose cartesian jog speed at 100 % is `max` m/s (clamped to 0.001-0.5).
    pub fn with_max_jog_linear(max: f64) -> Operator {
        Operator {
            max_jog_linear: if max.is_finite() {
                max.clamp(0.001, 0.5)
            } else {
                MAX_JOG_LINEAR
            },
            ..Operator::default()
        }
    }

    pub fn speed(&self) -> u8 {
        self.speed
    }

    pub fn positions(&self) -> &BTreeMap<String, SavedPosition> {
        &self.positions
    }

    fn fraction(&self) -> f64 {
        f64::from(self.speed) / 100.0
    }

    /// The tool speed cap at the current speed, m/s.
    fn jog_cap(&self) -> f64 {
        self.max_jog_linear * self.fraction()
    }

    /// The tool speed cap of a discrete move: a timed one may run up to the full cap.
    fn move_cap(&self, time_ms: u32) -> f64 {
        if time_ms == 0 {
            self.jog_cap()
        } else {
            self.max_jog_linear
        }
    }

    /// The answer to a frame that did not decode as a request.
    pub fn reply_to_undecodable(error: &DecodeError) -> ReturnCode {
        match error {
            DecodeError::UnknownCommand(_) => ReturnCode::UNKNOWN_COMMAND,
            _ => ReturnCode::MALFORMED_PAYLOAD,
        }
    }

    pub fn handle(&mut self, arm: &mut Arm, request: Request) -> Reply {
        let command = request.command();
        match self.dispatch(arm, request) {
            Ok(reply) => reply,
            Err(code) => Reply::error(command, code),
        }
    }

    fn dispatch(&mut self, arm: &mut Arm, request: Request) -> Result<Reply, ReturnCode> {
        let ok = ReturnCode::OK;
        let command = request.command();
        let done = Reply::error(command, ok);
        match request {
            Request::Handshake { .. } => {
                return Ok(Reply::Handshake {
                    return_code: ok,
                    major_version: VERSION.0,
                    minor_version: VERSION.1,
                });
            }
            Request::PolarPan {
                delta_azimuth,
                delta_altitude,
                delay_ms,
                time_ms,
            } => {
                let (az, alt) = (f64::from(delta_azimuth), f64::from(delta_altitude));
                let target = polar_target(&arm.pose(), az.to_radians(), alt.to_radians());
                let angle = az.hypot(alt).to_radians();
                let rate = self.timed_speed(angle, time_ms, MAX_JOG_ANGULAR_DEG.to_radians());
                // Orbiting at `rate` moves the tool at rate × radius.
                let radius = arm.pose().position.norm().max(0.05);
                let motion = SimMotion::ToPose {
                    target,
                    linear_speed: rate * radius,
                    angular_speed: rate,
                };
                self.command(arm, motion, delay_ms, self.move_cap(time_ms))?;
            }
            Request::Home { delay_ms } => {
                let motion = SimMotion::ToJoints {
                    target: kinematics::to_radians(&HOME_DEG),
                    fraction: self.fraction() * MAX_JOINT_FRACTION,
                };
                self.command(arm, motion, delay_ms, self.jog_cap())?;
            }
            Request::PolarPanStart {
                moving_azimuth,
                moving_altitude,
            } => {
                if moving_azimuth == 0 && moving_altitude == 0 {
                    arm.stop();
                    return Ok(done);
                }
                let rate = MAX_JOG_ANGULAR_DEG.to_radians() * self.fraction();
                let motion = SimMotion::Polar {
                    azimuth: f64::from(moving_azimuth) * rate,
                    altitude: f64::from(moving_altitude) * rate,
                };
                self.continuous(arm, motion)?;
            }
            Request::PolarPanStop | Request::CartesianMoveStop => arm.stop(),
            Request::CartesianMove {
                delta_x,
                delta_y,
                delta_z,
                delay_ms,
                time_ms,
            } => {
                let delta = Vector3::new(delta_x, delta_y, delta_z).map(f64::from) / 10_000.0;
                let mut target = arm.pose();
                target.position += delta;
                let speed = self.timed_speed(delta.norm(), time_ms, self.max_jog_linear);
                let motion = SimMotion::ToPose {
                    target,
                    linear_speed: speed,
                    angular_speed: MAX_JOG_ANGULAR_DEG.to_radians(),
                };
                self.command(arm, motion, delay_ms, self.move_cap(time_ms))?;
            }
            Request::CartesianMoveStart {
                moving_x,
                moving_y,
                moving_z,
            } => {
                let direction = Vector3::new(moving_x, moving_y, moving_z).map(f64::from);
                if direction.norm() == 0.0 {
                    arm.stop();
                    return Ok(done);
                }
                // Diagonals are normalised so the TCP never exceeds the jog speed.
                let motion = SimMotion::Twist {
                    linear: direction.normalize() * self.max_jog_linear * self.fraction(),
                    angular: Vector3::zeros(),
                    frame: ReferenceFrame::Base,
                };
                self.continuous(arm, motion)?;
            }
            Request::HardwareOperation {
                subcommand,
                payload,
                ..
            } => {
                let hw = HwRequest::decode(subcommand, &payload)
                    .map_err(|e| ReturnCode(e.return_code()))?;
                let reply = hardware_operation(arm, hw, self.jog_cap())?;
                return Ok(Reply::HardwareOperation {
                    return_code: ok,
                    subcommand,
                    payload: reply.encode_payload(),
                });
            }
            Request::GetSpeed => {
                return Ok(Reply::GetSpeed {
                    return_code: ok,
                    speed: self.speed,
                });
            }
            Request::SetSpeed { speed } => {
                if !(1..=100).contains(&speed) {
                    return Err(ReturnCode::OUT_OF_RANGE);
                }
                self.speed = speed;
            }
            Request::SavePosition {
                name,
                anchor,
                parent,
            } => self.save(arm, name, anchor, parent)?,
            Request::DeletePosition { name } => self.delete(&name)?,
            Request::GoToPosition { name } => {
                let motion = self.go_to(&name)?;
                self.command(arm, motion, 0, self.jog_cap())?;
            }
            Request::SetPolarPosition {
                name,
                delta,
                azimuth,
                radius,
            } => {
                let [el, az] =
                    [delta, azimuth].map(|tenths| (f64::from(tenths) / 10.0).to_radians());
                let r = f64::from(radius) / 10_000.0;
                let xyz = Vector3::new(
                    r * el.cos() * az.cos(),
                    r * el.cos() * az.sin(),
                    r * el.sin(),
                );
                self.set_absolute_position(arm, name, xyz)?;
            }
            Request::GetPolarPosition { name } => {
                let p = self.absolute(&name, 0)?.position;
                let horizontal = p.x.hypot(p.y);
                return Ok(Reply::GetPolarPosition {
                    return_code: ok,
                    delta: tenths(p.z.atan2(horizontal).to_degrees()),
                    azimuth: tenths(p.y.atan2(p.x).to_degrees()),
                    radius: tenths(p.norm() * 1000.0),
                });
            }
            Request::SetCartesianPosition { name, x, y, z } => {
                let xyz = Vector3::new(x, y, z).map(f64::from) / 10_000.0;
                self.set_absolute_position(arm, name, xyz)?;
            }
            Request::GetCartesianPosition { name } => {
                let p = self.absolute(&name, 0)?.position;
                return Ok(Reply::GetCartesianPosition {
                    return_code: ok,
                    x: tenths(p.x * 1000.0),
                    y: tenths(p.y * 1000.0),
                    z: tenths(p.z * 1000.0),
                });
            }
        }
        Ok(done)
    }

    /// Speed so `amount` takes `time_ms`, capped at `max`; without a time, the speed setting.
    fn timed_speed(&self, amount: f64, time_ms: u32, max: f64) -> f64 {
        if time_ms == 0 {
            return max * self.fraction();
        }
        (amount / (f64::from(time_ms) / 1000.0)).clamp(1e-4, max)
    }

    /// Starts a discrete `motion` (no watchdog) with the tool point kept under `cap` m/s.
    fn command(
        &self,
        arm: &mut Arm,
        motion: SimMotion,
        delay_ms: u32,
        cap: f64,
    ) -> Result<(), ReturnCode> {
        arm.command_capped(motion, f64::from(delay_ms) / 1000.0, false, Some(cap))
            .map_err(refusal_code)
    }

    /// A continuous START: a repeat of the running motion only refreshes the watchdog.
    fn continuous(&self, arm: &mut Arm, motion: SimMotion) -> Result<(), ReturnCode> {
        continuous(arm, motion, self.jog_cap())
    }
}

fn tenths(value: f64) -> i32 {
    (value * 10.0)
        .round()
        .clamp(f64::from(i32::MIN), f64::from(i32::MAX)) as i32
}

/// A continuous motion under `cap` m/s; a repeat only refreshes the watchdog (and cap).
fn continuous(arm: &mut Arm, motion: SimMotion, cap: f64) -> Result<(), ReturnCode> {
    if *arm.motion() == motion {
        arm.refresh_watchdog();
        arm.set_tcp_cap(Some(cap));
        return Ok(());
    }
    arm.command_capped(motion, 0.0, true, Some(cap))
        .map_err(refusal_code)
}

#[cfg(test)]
mod tests;
