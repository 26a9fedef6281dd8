//! Closed-loop tracking of continuous cartesian motions: open-loop IK integration drifts, so the
//! arm keeps a [`Reference`] on the commanded path and feeds a proportional correction of the
//! tool's error into the twist, through the same caps. The reference runs at the commanded rate
//! while the arm keeps up within a small lag; further behind, it moves only as far as the arm
//! progressed, so an arm slowed by a cap, a joint limit or a singularity is pulled back to the
//! path, never along a runaway reference.

use nalgebra::{Rotation3, Vector3};

use super::velocity::cap;
use super::{STEP, SimMotion, polar_target};
use crate::sim::kinematics::{Pose, pose_error};

/// How fast a tracking error is closed, 1/s (a 0.1 mm error asks for 4 mm/s).
pub(super) const GAIN: f64 = 40.0;

/// How far the reference may lead the arm along its path, m and rad, before it waits for it.
const MAX_LAG_POSITION: f64 = 0.001;
const MAX_LAG_ROTATION: f64 = 0.25 * std::f64::consts::PI / 180.0;

/// The largest position error the reference may hold, m: a backstop.
const MAX_HELD_POSITION: f64 = 0.002;

/// The largest orientation error the reference may hold, rad.
const MAX_HELD_ROTATION: f64 = 0.5 * std::f64::consts::PI / 180.0;

/// A base-frame twist: linear m/s, angular rad/s.
type Twist = (Vector3<f64>, Vector3<f64>);

/// How the reference moves on in one step at full progress.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Advance {
    /// Along a base-frame twist.
    Twist,
    /// Along a polar pan by these angles (rad).
    Polar { azimuth: f64, altitude: f64 },
}

/// Where the running continuous motion should have the tool.
#[derive(Debug, Clone)]
pub(super) struct Reference {
    /// The motion this reference follows; another motion starts a new reference.
    motion: SimMotion,
    pub(super) pose: Pose,
    /// This step's commanded twist (m/s, rad/s) and how it moves the reference.
    pending: Option<(Twist, Advance)>,
}

impl Reference {
    pub(super) fn new(motion: SimMotion, pose: Pose) -> Reference {
        Reference {
            motion,
            pose,
            pending: None,
        }
    }

    pub(super) fn follows(&self, motion: &SimMotion) -> bool {
        self.motion == *motion
    }

    /// Records `feed` for this step and returns it plus the correction towards the reference.
    pub(super) fn command(&mut self, actual: &Pose, feed: Twist, advance: Advance) -> Twist {
        self.pending = Some((feed, advance));
        let err = pose_error(actual, &self.pose);
        (
            feed.0 + err.fixed_rows::<3>(0) * GAIN,
            feed.1 + err.fixed_rows::<3>(3) * GAIN,
        )
    }

    /// Moves the reference by the share of the commanded twist the arm `achieved` from `actual`.
    pub(super) fn advance(&mut self, actual: &Pose, achieved: Twist) {
        let Some(((linear, angular), advance)) = self.pending.take() else {
            return;
        };
        let err = pose_error(actual, &self.pose);
        // How far the reference leads along the twist, and the share of the twist achieved.
        let (lead, max_lead, progress) = if linear.norm_squared() > 0.0 {
            let lead = err.fixed_rows::<3>(0).dot(&linear.normalize());
            let progress = achieved.0.dot(&linear) / linear.norm_squared();
            (lead, MAX_LAG_POSITION, progress)
        } else if angular.norm_squared() > 0.0 {
            let lead = err.fixed_rows::<3>(3).dot(&angular.normalize());
            let progress = achieved.1.dot(&angular) / angular.norm_squared();
            (lead, MAX_LAG_ROTATION, progress)
        } else {
            (0.0, 0.0, 0.0)
        };
        let progress = if lead < max_lead {
            1.0
        } else {
            progress.clamp(0.0, 1.0)
        };
        let next = match advance {
            Advance::Twist => Pose {
                position: self.pose.position + linear * (progress * STEP),
                rotation: Rotation3::new(angular * (progress * STEP)) * self.pose.rotation,
            },
            Advance::Polar { azimuth, altitude } => {
                polar_target(&self.pose, azimuth * progress, altitude * progress)
            }
        };
        self.hold_near(next, actual);
    }

    /// Takes `next`, but never more than the held errors away from `actual`.
    fn hold_near(&mut self, next: Pose, actual: &Pose) {
        let err = pose_error(actual, &next);
        let dp = err.fixed_rows::<3>(0).into_owned();
        let dr = err.fixed_rows::<3>(3).into_owned();
        if dp.norm() <= MAX_HELD_POSITION && dr.norm() <= MAX_HELD_ROTATION {
            self.pose = next;
            return;
        }
        self.pose = Pose {
            position: actual.position + cap(dp, MAX_HELD_POSITION),
            rotation: Rotation3::new(cap(dr, MAX_HELD_ROTATION)) * actual.rotation,
        };
    }
}
