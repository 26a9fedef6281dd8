//! How the running motion becomes joint velocities: twists and pans through the tracked reference,
//! discrete moves approaching their target, all under the caps, configured limits and joint top
//! speeds.

use nalgebra::{Vector3, Vector6};

use super::kinematics::{self, JOINTS, Joints, MAX_JOINT_SPEED_DEG, Pose};
use super::{
    ARRIVED_POSITION, ARRIVED_ROTATION, ActionStatus, Arm, Jacobian, ReferenceFrame, STEP,
    SimMotion, joint_delta, polar_twist, tracking,
};

/// Within IK's tolerance and hardly able to get closer, a discrete move has arrived (m, rad).
const STALLED_POSITION: f64 = 1e-4;
const STALLED_ROTATION: f64 = 0.01 * std::f64::consts::PI / 180.0;

/// A discrete move approaches its target proportionally to the distance left (1/s), no slower than
/// a floor (m/s, rad/s), so the last fraction of a mm takes ms, not an exponential tail.
const APPROACH_GAIN: f64 = 8.0;
const APPROACH_FLOOR_LINEAR: f64 = 0.002;
const APPROACH_FLOOR_ANGULAR: f64 = 0.2 * std::f64::consts::PI / 180.0;

impl Arm {
    /// Joint velocities the motion asks for at `pose`, whose Jacobian is `j`.
    pub(super) fn desired_velocity(&mut self, pose: &Pose, j: &Jacobian) -> Joints {
        match self.motion.clone() {
            SimMotion::Idle => [0.0; JOINTS],
            SimMotion::Twist {
                linear,
                angular,
                frame,
            } => {
                // A tool-frame twist turns with the commanded tool, not its tracking error.
                let reference = self.reference_pose(pose);
                let rotation = reference.rotation;
                let (linear, angular) = match frame {
                    ReferenceFrame::Base => (linear, angular),
                    ReferenceFrame::Tool => (rotation * linear, rotation * angular),
                    ReferenceFrame::Mixed => (linear, rotation * angular),
                };
                let feed = self.capped_twist(linear, angular);
                self.follow(pose, j, feed, tracking::Advance::Twist)
            }
            SimMotion::Polar { azimuth, altitude } => {
                let reference = self.reference_pose(pose);
                let (linear, angular) = polar_twist(&reference, azimuth, altitude);
                // The whole pan slows together, so it keeps its shape under either cap.
                let scale = [
                    self.linear_cap() / linear.norm(),
                    self.speed_limit_angular / angular.norm(),
                ]
                .into_iter()
                .fold(1.0, f64::min);
                let advance = tracking::Advance::Polar {
                    azimuth: azimuth * scale * STEP,
                    altitude: altitude * scale * STEP,
                };
                self.follow(pose, j, (linear * scale, angular * scale), advance)
            }
            SimMotion::ToPose {
                target,
                linear_speed,
                angular_speed,
            } => {
                let err = kinematics::pose_error(pose, &target);
                let dp = err.fixed_rows::<3>(0).into_owned();
                let dr = err.fixed_rows::<3>(3).into_owned();
                if dp.norm() < ARRIVED_POSITION && dr.norm() < ARRIVED_ROTATION {
                    self.finish();
                    return [0.0; JOINTS];
                }
                let linear = approach(dp, linear_speed, APPROACH_FLOOR_LINEAR);
                let angular = approach(dr, angular_speed, APPROACH_FLOOR_ANGULAR);
                let qd = self.track(j, linear, angular);
                if dp.norm() < STALLED_POSITION
                    && dr.norm() < STALLED_ROTATION
                    && !makes_headway(j, &qd, self.capped_twist(linear, angular))
                {
                    // As close as IK promised with no way closer: arrived where it can.
                    self.finish();
                    return [0.0; JOINTS];
                }
                qd
            }
            SimMotion::ToJoints { target, fraction } => {
                let delta: Joints = std::array::from_fn(|i| joint_delta(i, self.q[i], target[i]));
                if delta.iter().all(|d| d.abs() < 1e-5) {
                    self.finish();
                    return [0.0; JOINTS];
                }
                // Time for the slowest joint, then every joint moves to arrive together.
                let duration = (0..JOINTS)
                    .map(|i| delta[i].abs() / (MAX_JOINT_SPEED_DEG[i].to_radians() * fraction))
                    .fold(STEP, f64::max);
                std::array::from_fn(|i| delta[i] / duration)
            }
            SimMotion::JointVelocity { joint, velocity } => {
                let mut qd = [0.0; JOINTS];
                if let Some(v) = qd.get_mut(joint) {
                    *v = velocity;
                }
                qd
            }
        }
    }

    /// The tool point's speed cap in force, m/s.
    fn linear_cap(&self) -> f64 {
        self.tcp_cap
            .map_or(self.speed_limit_linear, |c| c.min(self.speed_limit_linear))
    }

    /// Scales joint velocities down (never up) so the tool point, through the Jacobian, stays under
    /// the motion's cap and the configured linear limit (damped least squares can trade a little
    /// rotation for translation). Returns them and the tool's twist (m/s, rad/s).
    pub(super) fn limit_tcp_speed(
        &self,
        qd: Joints,
        j: &Jacobian,
    ) -> (Joints, (Vector3<f64>, Vector3<f64>)) {
        let twist = j * nalgebra::SVector::<f64, JOINTS>::from(qd);
        let (linear, angular) = (
            twist.fixed_rows::<3>(0).into_owned(),
            twist.fixed_rows::<3>(3).into_owned(),
        );
        let cap = self.linear_cap();
        let speed = linear.norm();
        if speed > cap && speed > 0.0 {
            let scale = cap / speed;
            (qd.map(|v| v * scale), (linear * scale, angular * scale))
        } else {
            (qd, (linear, angular))
        }
    }

    /// Arrived: a sequence goes on to its next move, anything else completes.
    fn finish(&mut self) {
        self.reference = None;
        self.watchdog = None;
        match self.queued.pop_front() {
            Some(next) => self.motion = next,
            None => {
                self.motion = SimMotion::Idle;
                self.action_status = ActionStatus::Completed;
            }
        }
    }

    /// The continuous motion's reference pose; new, at `pose`, when the motion begins or changes.
    fn reference_pose(&mut self, pose: &Pose) -> Pose {
        match &self.reference {
            Some(reference) if reference.follows(&self.motion) => reference.pose,
            _ => {
                self.reference = Some(tracking::Reference::new(self.motion.clone(), *pose));
                *pose
            }
        }
    }

    /// Joint velocities for `feed` plus the correction to the reference, which moves by `advance`.
    fn follow(
        &mut self,
        pose: &Pose,
        j: &Jacobian,
        feed: (Vector3<f64>, Vector3<f64>),
        advance: tracking::Advance,
    ) -> Joints {
        let (linear, angular) = match &mut self.reference {
            Some(reference) => reference.command(pose, feed, advance),
            None => feed,
        };
        self.track(j, linear, angular)
    }

    /// A base-frame twist capped at the desired speed limits and the motion's cap, scaled as a
    /// whole (the tool never turns faster than it moves).
    fn capped_twist(
        &self,
        linear: Vector3<f64>,
        angular: Vector3<f64>,
    ) -> (Vector3<f64>, Vector3<f64>) {
        // Never up; a still (or NaN) speed keeps its twist.
        let scale = (self.linear_cap() / linear.norm()).min(1.0);
        (
            linear * scale,
            cap(angular * scale, self.speed_limit_angular),
        )
    }

    /// Joint velocities for a base-frame twist, capped as [`Arm::capped_twist`] says.
    fn track(&self, j: &Jacobian, linear: Vector3<f64>, angular: Vector3<f64>) -> Joints {
        let (linear, angular) = self.capped_twist(linear, angular);
        let xdot = Vector6::new(
            linear.x, linear.y, linear.z, angular.x, angular.y, angular.z,
        );
        kinematics::dls_velocity_with(j, &xdot, 0.05)
    }
}

/// Closes a discrete move's `err`: proportional, between `floor` and `max`, never overshooting.
fn approach(err: Vector3<f64>, max: f64, floor: f64) -> Vector3<f64> {
    let n = err.norm();
    if n == 0.0 {
        return err;
    }
    let speed = (n * APPROACH_GAIN).max(floor).min(max).min(n / STEP);
    err * (speed / n)
}

/// Whether `qd` realises a tenth of `wanted` (linear, or angular when there is no linear part).
fn makes_headway(j: &Jacobian, qd: &Joints, wanted: (Vector3<f64>, Vector3<f64>)) -> bool {
    let twist = j * nalgebra::SVector::<f64, JOINTS>::from(*qd);
    let (realised, wanted) = if wanted.0.norm_squared() > 0.0 {
        (twist.fixed_rows::<3>(0).into_owned(), wanted.0)
    } else {
        (twist.fixed_rows::<3>(3).into_owned(), wanted.1)
    };
    wanted.norm_squared() == 0.0 || realised.dot(&wanted) >= 0.1 * wanted.norm_squared()
}

/// `v` shortened to `max` when longer.
pub(super) fn cap(v: Vector3<f64>, max: f64) -> Vector3<f64> {
    let n = v.norm();
    if n > max && n > 0.0 { v * (max / n) } else { v }
}

/// Scales the whole vector so no joint exceeds its top speed (keeps the direction).
pub(super) fn limit_joint_speeds(qd: Joints) -> Joints {
    let ratio = (0..JOINTS)
        .map(|i| qd[i].abs() / MAX_JOINT_SPEED_DEG[i].to_radians())
        .fold(1.0, f64::max);
    qd.map(|v| v / ratio)
}
