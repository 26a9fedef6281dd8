//! The simulated arm's vocabulary: the motions it runs and why it refuses one.

use nalgebra::Vector3;

use super::ReferenceFrame;
use crate::sim::kinematics::{Joints, Pose};

/// What the simulated arm is doing (the link and the console have their own motion vocabularies).
#[derive(Debug, Clone, PartialEq)]
pub enum SimMotion {
    Idle,
    /// Linear m/s and angular rad/s, in `frame`.
    Twist {
        linear: Vector3<f64>,
        angular: Vector3<f64>,
        frame: ReferenceFrame,
    },
    /// Orbit about the base Z axis (azimuth) and change of elevation (altitude), rad/s.
    Polar {
        azimuth: f64,
        altitude: f64,
    },
    /// Straight-line move to a pose at bounded speeds (m/s, rad/s).
    ToPose {
        target: Pose,
        linear_speed: f64,
        angular_speed: f64,
    },
    /// Joint-space move, every joint arriving together, at `fraction` of the joints' top speed.
    ToJoints {
        target: Joints,
        fraction: f64,
    },
    /// One joint at a velocity, rad/s (single-joint jog).
    JointVelocity {
        joint: usize,
        velocity: f64,
    },
}

impl SimMotion {
    pub fn is_idle(&self) -> bool {
        matches!(self, SimMotion::Idle)
    }

    /// Every number finite: a client's NaN would drive the integrator to an arbitrary pose.
    pub fn is_finite(&self) -> bool {
        let finite3 = |v: &Vector3<f64>| v.iter().all(|x| x.is_finite());
        match self {
            SimMotion::Idle => true,
            SimMotion::Twist {
                linear, angular, ..
            } => finite3(linear) && finite3(angular),
            SimMotion::Polar { azimuth, altitude } => azimuth.is_finite() && altitude.is_finite(),
            SimMotion::ToPose {
                target,
                linear_speed,
                angular_speed,
            } => {
                finite3(&target.position)
                    && target.rotation.matrix().iter().all(|x| x.is_finite())
                    && linear_speed.is_finite()
                    && angular_speed.is_finite()
            }
            SimMotion::ToJoints { target, fraction } => {
                target.iter().all(|x| x.is_finite()) && fraction.is_finite()
            }
            SimMotion::JointVelocity { velocity, .. } => velocity.is_finite(),
        }
    }
}

/// Why the arm refused a command.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum Refusal {
    #[error("the arm is in fault")]
    InFault,
    #[error("the target is unreachable")]
    Unreachable,
    #[error("the target passes the limit of joint {0}")]
    JointLimit(usize),
    #[error("a value is out of range")]
    OutOfRange,
    #[error("a value is NaN or infinite")]
    NotFinite,
}
