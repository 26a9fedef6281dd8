//! Whether a telemetry snapshot is one a real Gen3 can report, for deciding if motion may start:
//! a value that is not a number, or beyond what the arm can physically do, means the reading (or
//! the arm) cannot be trusted, and nothing is driven on it. Pure.
//!
//! The bounds are generous on purpose (the arm's own limits, from the field notes, with room
//! for overshoot and noise): a reading past them is nonsense, not an arm working hard.
//! - Joint positions are reported 0-360 deg; a signed reading (-180..180) is accepted too.
//! - Joint speeds: at most 80 deg/s (J1-J4) and 70 deg/s (J5-J7), here with 50 % room.
//! - Tool twist: hard limits 0.5 m/s linear and 100 deg/s angular, here with 50 % room.
//! - Tool pose: the Gen3 reaches about 1.2 m from its base; 2 m is nonsense. Angles within
//!   ±360 deg.
//!
//! Kept to one function so it can be merged with a fuller sanity check of every field.

use super::Telemetry;

/// Joint positions accepted, deg: the reported 0-360 and a signed -180..180, with 1 deg of
/// room for rounding at either end.
pub const JOINT_POSITION_DEG: (f32, f32) = (-181.0, 361.0);
/// Joint speed maxima, deg/s (field notes), J1-J7.
pub const JOINT_SPEED_MAX_DEG_S: [f32; 7] = [80.0, 80.0, 80.0, 80.0, 70.0, 70.0, 70.0];
/// Twist hard limits (field notes): m/s and deg/s.
pub const TWIST_LINEAR_MAX_M_S: f32 = 0.5;
pub const TWIST_ANGULAR_MAX_DEG_S: f32 = 100.0;
/// Room over the physical maxima before a speed is nonsense.
pub const SPEED_ROOM: f32 = 1.5;
/// The farthest the tool point can be from the base on any axis, m (generous).
pub const POSE_REACH_M: f32 = 2.0;
/// Tool orientation angles accepted, deg.
pub const POSE_ANGLE_DEG: f32 = 360.0;

/// The first value of `t` that no Gen3 can report, in words (`J3 position NaN`,
/// `J2 speed 1000 deg/s, over 120`), or `None` when every value checked is plausible.
/// Checked: joint positions and speeds, the tool twist and the tool pose.
pub fn implausible_for_motion(t: &Telemetry) -> Option<String> {
    let (low, high) = JOINT_POSITION_DEG;
    for (i, joint) in t.joints.iter().enumerate() {
        let name = format!("J{} position", i + 1);
        if let Some(why) = out_of(&name, joint.position, low, high, "deg") {
            return Some(why);
        }
        let max = JOINT_SPEED_MAX_DEG_S[i] * SPEED_ROOM;
        let name = format!("J{} speed", i + 1);
        if let Some(why) = out_of(&name, joint.velocity, -max, max, "deg/s") {
            return Some(why);
        }
    }
    let v = t.tcp.twist;
    let linear = TWIST_LINEAR_MAX_M_S * SPEED_ROOM;
    let angular = TWIST_ANGULAR_MAX_DEG_S * SPEED_ROOM;
    let twist = [
        ("twist x", v.x, linear, "m/s"),
        ("twist y", v.y, linear, "m/s"),
        ("twist z", v.z, linear, "m/s"),
        ("twist θx", v.theta_x, angular, "deg/s"),
        ("twist θy", v.theta_y, angular, "deg/s"),
        ("twist θz", v.theta_z, angular, "deg/s"),
    ];
    let p = t.tcp.pose;
    let pose = [
        ("pose x", p.x, POSE_REACH_M, "m"),
        ("pose y", p.y, POSE_REACH_M, "m"),
        ("pose z", p.z, POSE_REACH_M, "m"),
        ("pose θx", p.theta_x, POSE_ANGLE_DEG, "deg"),
        ("pose θy", p.theta_y, POSE_ANGLE_DEG, "deg"),
        ("pose θz", p.theta_z, POSE_ANGLE_DEG, "deg"),
    ];
    twist
        .into_iter()
        .chain(pose)
        .find_map(|(name, value, max, unit)| out_of(name, value, -max, max, unit))
}

/// `value` in words if it is not a number or outside `low..=high`.
fn out_of(name: &str, value: f32, low: f32, high: f32, unit: &str) -> Option<String> {
    if value.is_nan() {
        return Some(format!("{name} NaN"));
    }
    if !(low..=high).contains(&value) {
        let bound = if value < low { low } else { high };
        return Some(format!("{name} {value} {unit}, beyond {bound}"));
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kortex::RegisterImage;

    fn telemetry() -> Telemetry {
        let mut t = Telemetry::decode(&RegisterImage::default());
        // The home pose as reported, at rest.
        let q = [0.0, 15.0, 180.0, 230.0, 0.0, 55.0, 90.0];
        for (joint, deg) in t.joints.iter_mut().zip(q) {
            joint.position = deg;
        }
        t.tcp.pose.x = 0.4566;
        t.tcp.pose.z = 0.4338;
        t.tcp.pose.theta_x = 90.0;
        t.tcp.pose.theta_z = 90.0;
        t
    }

    #[test]
    fn a_real_arm_s_readings_pass() {
        let mut t = telemetry();
        assert_eq!(implausible_for_motion(&t), None);
        // At its limits, and signed angles, still pass.
        t.joints[0].position = 360.0;
        t.joints[2].position = -179.5;
        t.joints[1].velocity = -80.0;
        t.joints[6].velocity = 70.0;
        t.tcp.twist.x = 0.5;
        t.tcp.twist.theta_z = -100.0;
        assert_eq!(implausible_for_motion(&t), None);
    }

    #[test]
    fn not_a_number_anywhere_checked_is_named() {
        let mut t = telemetry();
        t.joints[2].position = f32::NAN;
        assert_eq!(
            implausible_for_motion(&t).as_deref(),
            Some("J3 position NaN")
        );
        let mut t = telemetry();
        t.tcp.twist.y = f32::NAN;
        assert_eq!(implausible_for_motion(&t).as_deref(), Some("twist y NaN"));
        let mut t = telemetry();
        t.tcp.pose.theta_y = f32::NAN;
        assert_eq!(implausible_for_motion(&t).as_deref(), Some("pose θy NaN"));
    }

    #[test]
    fn beyond_what_the_arm_can_do_is_named_with_the_bound() {
        let mut t = telemetry();
        t.joints[0].position = 1e9;
        assert_eq!(
            implausible_for_motion(&t).as_deref(),
            Some("J1 position 1000000000 deg, beyond 361")
        );
        let mut t = telemetry();
        // 70 deg/s × 1.5 = 105: J5 at 106 is over.
        t.joints[4].velocity = -106.0;
        assert_eq!(
            implausible_for_motion(&t).as_deref(),
            Some("J5 speed -106 deg/s, beyond -105")
        );
        let mut t = telemetry();
        t.tcp.twist.z = f32::INFINITY;
        assert_eq!(
            implausible_for_motion(&t).as_deref(),
            Some("twist z inf m/s, beyond 0.75")
        );
        let mut t = telemetry();
        t.tcp.pose.x = 3.0;
        assert_eq!(
            implausible_for_motion(&t).as_deref(),
            Some("pose x 3 m, beyond 2")
        );
    }
}
