//! Kinova Gen3 7-DOF figures (Gen3 user guide, via the field notes) and its forward
//! kinematics from the classic DH table, shared by the simulator, the arm driver (joint jog
//! speed bounds) and the console's panels. Pure: angles in radians unless named `_deg`.

use nalgebra::{Matrix4, Vector3};

/// Joint limits in degrees; `None` for the continuous joints J1, J3, J5, J7.
pub const JOINT_LIMITS_DEG: [Option<f64>; 7] = [
    None,
    Some(128.9),
    None,
    Some(147.8),
    None,
    Some(120.3),
    None,
];

/// Maximum joint speeds in deg/s.
pub const MAX_JOINT_SPEED_DEG: [f64; 7] = [80.0, 80.0, 80.0, 80.0, 70.0, 70.0, 70.0];

/// Maximum joint torques in N·m.
pub const MAX_JOINT_TORQUE: [f64; 7] = [39.0, 39.0, 39.0, 39.0, 9.0, 9.0, 9.0];

/// The home pose, degrees.
pub const HOME_DEG: [f64; 7] = [0.0, 15.0, 180.0, 230.0, 0.0, 55.0, 90.0];

/// (alpha, d, theta offset) per joint row of the classic DH table; `a = 0` for every row.
const DH_ROWS: [(f64, f64, f64); 7] = {
    use std::f64::consts::{FRAC_PI_2, PI};
    [
        (FRAC_PI_2, -0.2848, 0.0),
        (FRAC_PI_2, -0.0118, PI),
        (FRAC_PI_2, -0.4208, PI),
        (FRAC_PI_2, -0.0128, PI),
        (FRAC_PI_2, -0.3143, PI),
        (FRAC_PI_2, 0.0, PI),
        (PI, -0.1674, PI),
    ]
};

fn dh(alpha: f64, d: f64, theta: f64) -> Matrix4<f64> {
    let (st, ct) = theta.sin_cos();
    let (sa, ca) = alpha.sin_cos();
    #[rustfmt::skip]
    let m = Matrix4::new(
        ct, -st * ca, st * sa, 0.0,
        st, ct * ca, -ct * sa, 0.0,
        0.0, sa, ca, d,
        0.0, 0.0, 0.0, 1.0,
    );
    m
}

/// Forward kinematics in homogeneous transforms for joint angles `q` (radians): the frame each
/// joint turns in (index i is joint i+1; its axis is the frame's Z axis) and the tool interface
/// frame, all in the base frame.
pub fn frames(q: &[f64; 7]) -> ([Matrix4<f64>; 7], Matrix4<f64>) {
    // The fixed base row: alpha = pi, d = 0, theta = 0.
    let mut t = dh(std::f64::consts::PI, 0.0, 0.0);
    let mut before = [Matrix4::identity(); 7];
    for (i, (alpha, d, offset)) in DH_ROWS.iter().enumerate() {
        before[i] = t;
        t *= dh(*alpha, *d, q[i] + offset);
    }
    (before, t)
}

fn column(t: &Matrix4<f64>, c: usize) -> Vector3<f64> {
    Vector3::new(t[(0, c)], t[(1, c)], t[(2, c)])
}

/// The tool interface position (m, base frame) for joint angles `q` (radians).
pub fn tool_position(q: &[f64; 7]) -> Vector3<f64> {
    column(&frames(q).1, 3)
}

/// Each joint's lever arm: the distance (m) from its axis to the tool interface. Turning joint
/// i alone at w rad/s moves the tool point at exactly `lever[i] * w` m/s.
pub fn lever_arms(q: &[f64; 7]) -> [f64; 7] {
    let (before, tool) = frames(q);
    let p = column(&tool, 3);
    before.map(|f| column(&f, 2).cross(&(p - column(&f, 3))).norm())
}

/// Below this lever arm (m) a joint barely moves the tool point; its rate is then bounded by
/// its own jog speed alone.
pub const MIN_LEVER_ARM: f64 = 0.01;

/// The fastest joint `joint` (1-7) at `position_deg` (every joint, degrees as reported) may
/// turn, deg/s, for the tool point to move no faster than `max_linear` m/s for the next
/// `horizon` seconds. The lever arm grows at most as fast as the tool moves, so it is taken
/// `max_linear * horizon` longer than it is now: the bound holds until the command is renewed.
pub fn joint_rate_for_tool_speed(
    position_deg: &[f32; 7],
    joint: u8,
    max_linear: f64,
    horizon: f64,
) -> f64 {
    let q = position_deg.map(|d| f64::from(d).to_radians());
    let index = usize::from(joint.clamp(1, 7) - 1);
    let lever = lever_arms(&q)[index] + max_linear * horizon.max(0.0);
    (max_linear / lever.max(MIN_LEVER_ARM)).to_degrees()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_home_pose_puts_the_tool_where_the_field_notes_say() {
        let p = tool_position(&HOME_DEG.map(f64::to_radians));
        assert!(
            (p - Vector3::new(0.4566, 0.0010, 0.4338)).norm() < 1e-3,
            "{p:?}"
        );
    }

    #[test]
    fn lever_arms_give_the_tool_speed_of_each_joint_alone() {
        let q = [10.0, 20.0, 170.0, 240.0, 15.0, 50.0, 80.0].map(f64::to_radians);
        let levers = lever_arms(&q);
        let h = 1e-6;
        for (i, lever) in levers.iter().enumerate() {
            let mut turned = q;
            turned[i] += h;
            let speed = (tool_position(&turned) - tool_position(&q)).norm() / h;
            assert!(
                (speed - lever).abs() < 1e-4,
                "joint {}: {speed} vs {lever}",
                i + 1
            );
        }
        // J1 at home: the tool's horizontal distance from the base Z axis.
        let home = lever_arms(&HOME_DEG.map(f64::to_radians));
        assert!((home[0] - 0.4566f64.hypot(0.0010)).abs() < 1e-3);
        // J7's axis runs through the tool interface.
        assert!(home[6] < 1e-9);
    }

    #[test]
    fn the_joint_rate_bound_keeps_the_tool_at_the_cap() {
        let home = HOME_DEG.map(|d| d as f32);
        // J1 at home: 0.05 m/s over a 0.4566 m lever is 6.27 deg/s.
        let rate = joint_rate_for_tool_speed(&home, 1, 0.05, 0.0);
        assert!(
            (rate - (0.05f64 / 0.4566).to_degrees()).abs() < 0.02,
            "{rate}"
        );
        // Half a second ahead, the lever may have grown by 25 mm.
        let ahead = joint_rate_for_tool_speed(&home, 1, 0.05, 0.5);
        assert!(
            (ahead - (0.05f64 / 0.4816).to_degrees()).abs() < 0.02,
            "{ahead}"
        );
        // J7 turns the tool about itself: only the minimum lever bounds it.
        let rate = joint_rate_for_tool_speed(&home, 7, 0.05, 0.0);
        assert!((rate - (0.05 / MIN_LEVER_ARM).to_degrees()).abs() < 1e-6);
    }
}
