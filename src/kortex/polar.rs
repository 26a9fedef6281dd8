//! Polar pan over Modbus: the arm has no polar command, so azimuth and altitude become a base-frame
//! twist from the live tool pose, recomputed every poll. The tool turns rigidly about axes through
//! the base origin (azimuth about Z, altitude about the horizontal axis across its bearing), so a
//! camera on it keeps its view of the scene's centre: v = w k x p.

use super::cartesian::{Pose, Twist};
use super::commands::{MAX_ANGULAR_SPEED, MAX_LINEAR_SPEED};

/// Below this distance from base Z (m) the bearing, and so the altitude axis, is undefined.
pub const MIN_RADIUS: f32 = 0.01;

/// How fast a polar pan turns.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PolarPanSettings {
    /// Rotation rate at direction 1, deg/s.
    pub angular_speed: f32,
    /// The tool point's top speed, m/s; default ISO 10218-1's reduced speed (250 mm/s).
    pub max_linear_speed: f32,
}

impl Default for PolarPanSettings {
    fn default() -> Self {
        PolarPanSettings {
            angular_speed: 10.0,
            max_linear_speed: 0.25,
        }
    }
}

/// Why no twist could be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PolarPanError {
    #[error("{what} direction {value} is outside -1..1")]
    DirectionOutOfRange { what: &'static str, value: f32 },
    #[error("the tool pose holds a non-finite value")]
    PoseNotFinite,
    #[error(
        "the tool is {radius:.4} m from the base Z axis: its bearing, and so the altitude axis, is undefined"
    )]
    OnBaseAxis { radius: f32 },
    #[error(
        "polar pan settings out of range: angular speed must be in (0, {MAX_ANGULAR_SPEED}] deg/s and maximum linear speed in (0, {MAX_LINEAR_SPEED}] m/s"
    )]
    BadSettings,
}

/// Checks the directions (each in -1..1) and the settings, before any pose is known.
pub fn check_directions(
    azimuth: f32,
    altitude: f32,
    settings: PolarPanSettings,
) -> Result<(), PolarPanError> {
    for (what, value) in [("azimuth", azimuth), ("altitude", altitude)] {
        if !(-1.0..=1.0).contains(&value) {
            return Err(PolarPanError::DirectionOutOfRange { what, value });
        }
    }
    let speed_ok = settings.angular_speed > 0.0 && settings.angular_speed <= MAX_ANGULAR_SPEED;
    let linear_ok =
        settings.max_linear_speed > 0.0 && settings.max_linear_speed <= MAX_LINEAR_SPEED;
    (speed_ok && linear_ok)
        .then_some(())
        .ok_or(PolarPanError::BadSettings)
}

/// The base-frame twist that pans the tool at `pose`; `azimuth` and `altitude` in -1..1 (positive:
/// counter-clockwise from above; up). Scaled down, never up, to the settings' linear speed and the
/// arm's angular limit.
pub fn polar_twist(
    pose: Pose,
    azimuth: f32,
    altitude: f32,
    settings: PolarPanSettings,
) -> Result<Twist, PolarPanError> {
    check_directions(azimuth, altitude, settings)?;
    if !pose.to_array().iter().all(|v| v.is_finite()) {
        return Err(PolarPanError::PoseNotFinite);
    }
    let (x, y, z) = (f64::from(pose.x), f64::from(pose.y), f64::from(pose.z));
    let radius = x.hypot(y);
    // Rotation axis and rate, deg/s, in the base frame.
    let mut omega = [0.0, 0.0, f64::from(azimuth * settings.angular_speed)];
    if altitude != 0.0 {
        if radius < f64::from(MIN_RADIUS) {
            return Err(PolarPanError::OnBaseAxis {
                radius: radius as f32,
            });
        }
        // k = (sin bearing, -cos bearing, 0): turning about it lifts the tool.
        let rate = f64::from(altitude * settings.angular_speed);
        omega[0] = rate * y / radius;
        omega[1] = -rate * x / radius;
    }
    let w = omega.map(f64::to_radians);
    let linear = [
        w[1] * z - w[2] * y,
        w[2] * x - w[0] * z,
        w[0] * y - w[1] * x,
    ];
    let linear_speed = linear.iter().map(|v| v * v).sum::<f64>().sqrt();
    let angular_speed = omega.iter().map(|v| v * v).sum::<f64>().sqrt();
    let scale = [
        1.0,
        f64::from(settings.max_linear_speed) / linear_speed,
        f64::from(MAX_ANGULAR_SPEED) / angular_speed,
    ]
    .into_iter()
    .filter(|s| s.is_finite())
    .fold(1.0f64, f64::min);
    let ([vx, vy, vz], [wx, wy, wz]) = (linear, omega);
    Ok(Twist::from_array(
        [vx, vy, vz, wx, wy, wz].map(|v| (v * scale) as f32),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Over the reachable space and every direction, altitude included, the tool point never
    /// moves faster than the settings' linear speed, and the linear part is the rigid motion
    /// of the point under the angular part (v = w x p), so the bound is the tool's true speed.
    #[test]
    fn the_tool_point_speed_is_bounded_whatever_the_pose_and_direction() {
        let settings = PolarPanSettings {
            angular_speed: 30.0,
            max_linear_speed: 0.05,
        };
        for x in [-0.9f32, -0.3, 0.05, 0.4566, 0.9] {
            for y in [-0.7f32, 0.0, 0.2, 0.8] {
                for z in [-0.2f32, 0.1, 0.4338, 1.0] {
                    let pose = Pose {
                        x,
                        y,
                        z,
                        theta_x: 90.0,
                        theta_y: 0.0,
                        theta_z: 90.0,
                    };
                    for (az, alt) in [(1.0, 0.0), (0.0, 1.0), (1.0, 1.0), (-1.0, 0.5)] {
                        let t = polar_twist(pose, az, alt, settings).expect("defined off axis");
                        assert!(
                            t.linear_speed() <= 0.05 * 1.0001,
                            "{pose:?} {az} {alt}: {t:?}"
                        );
                        let w = [t.theta_x, t.theta_y, t.theta_z].map(|v| v.to_radians());
                        let rigid = [
                            w[1] * z - w[2] * y,
                            w[2] * x - w[0] * z,
                            w[0] * y - w[1] * x,
                        ];
                        for (v, r) in [t.x, t.y, t.z].iter().zip(rigid) {
                            assert!((v - r).abs() < 1e-5, "{pose:?} {az} {alt}: {t:?}");
                        }
                    }
                }
            }
        }
    }
}
