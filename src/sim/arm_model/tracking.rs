//! Closed-loop tracking of continuous cartesian motions (twists and polar pans).
//!
//! Integrating a twist through damped-least-squares IK open loop drifts: each 1 ms step's
//! linearisation error and the damping's bias add up (a 255 mm +X jog used to end 3.3 mm off in
//! Z). So the arm keeps a [`Reference`]: the pose the commanded motion would have reached from
//! the pose where it began, and feeds a proportional correction of the error back into the
//! twist it asks the IK for. The correction goes through the same speed caps as the motion.

use nalgebra::{Rotation3, Vector3};

use super::SimMotion;
use crate::sim::kinematics::{Pose, pose_error};

/// How fast a tracking error is closed, 1/s (a 0.1 mm error asks for 4 mm/s).
pub(super) const GAIN: f64 = 40.0;

/// The largest position error the reference may hold ahead of the arm, m. Where the arm cannot
/// follow (a joint at its speed limit, near a singularity) the reference waits for it instead
/// of running away, so the arm has no distance to make up when it is free again.
const MAX_HELD_POSITION: f64 = 0.002;

/// The largest orientation error the reference may hold, rad.
const MAX_HELD_ROTATION: f64 = 0.5 * std::f64::consts::PI / 180.0;

/// Where the running continuous motion should have the tool by now.
#[derive(Debug, Clone)]
pub(super) struct Reference {
    /// The motion this reference integrates; another motion starts a new reference.
    motion: SimMotion,
    pub(super) pose: Pose,
}

impl Reference {
    pub(super) fn new(motion: SimMotion, pose: Pose) -> Reference {
        Reference { motion, pose }
    }

    /// Whether this reference belongs to `motion`.
    pub(super) fn follows(&self, motion: &SimMotion) -> bool {
        self.motion == *motion
    }

    /// Moves on to `next`, but never more than the held errors away from `actual`.
    pub(super) fn move_to(&mut self, next: Pose, actual: &Pose) {
        let err = pose_error(actual, &next);
        let dp = err.fixed_rows::<3>(0).into_owned();
        let dr = err.fixed_rows::<3>(3).into_owned();
        self.pose = Pose {
            position: actual.position + limit(dp, MAX_HELD_POSITION),
            rotation: Rotation3::new(limit(dr, MAX_HELD_ROTATION)) * actual.rotation,
        };
    }
}

/// The proportional correction from `actual` towards `reference`: linear m/s, angular rad/s.
pub(super) fn correction(actual: &Pose, reference: &Pose) -> (Vector3<f64>, Vector3<f64>) {
    let err = pose_error(actual, reference);
    (err.fixed_rows::<3>(0) * GAIN, err.fixed_rows::<3>(3) * GAIN)
}

/// `pose` moved by a base-frame twist held for `dt` seconds.
pub(super) fn advanced(pose: &Pose, linear: Vector3<f64>, angular: Vector3<f64>, dt: f64) -> Pose {
    Pose {
        position: pose.position + linear * dt,
        rotation: Rotation3::new(angular * dt) * pose.rotation,
    }
}

fn limit(v: Vector3<f64>, max: f64) -> Vector3<f64> {
    let n = v.norm();
    if n > max { v * (max / n) } else { v }
}
