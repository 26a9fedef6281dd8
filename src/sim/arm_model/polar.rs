//! Polar pans: an orbit about the base Z axis and a change of elevation about the base origin.

use nalgebra::{Rotation3, Unit, Vector3};

use crate::sim::kinematics::Pose;

/// The base-frame twist for a polar pan at `azimuth` and `altitude` rad/s: an orbit about base Z
/// and an elevation change about the origin; the tool turns to keep its bearing.
pub fn polar_twist(pose: &Pose, azimuth: f64, altitude: f64) -> (Vector3<f64>, Vector3<f64>) {
    let p = pose.position;
    let horizontal = Vector3::new(p.x, p.y, 0.0);
    let mut omega = Vector3::new(0.0, 0.0, azimuth);
    if horizontal.norm() > 1e-6 {
        // Rotating about z × r̂ lowers the point; elevation rises about its opposite.
        let axis = Unit::new_normalize(Vector3::z().cross(&horizontal));
        omega -= axis.into_inner() * altitude;
    }
    (omega.cross(&p), omega)
}

/// A pose moved by a polar pan of `azimuth` and `altitude` radians.
pub fn polar_target(pose: &Pose, azimuth: f64, altitude: f64) -> Pose {
    let p = pose.position;
    let horizontal = Vector3::new(p.x, p.y, 0.0);
    let mut rotation = Rotation3::from_axis_angle(&Vector3::z_axis(), azimuth);
    if horizontal.norm() > 1e-6 {
        let axis = Unit::new_normalize(Vector3::z().cross(&horizontal));
        rotation *= Rotation3::from_axis_angle(&axis, -altitude);
    }
    Pose {
        position: rotation * p,
        rotation: rotation * pose.rotation,
    }
}
