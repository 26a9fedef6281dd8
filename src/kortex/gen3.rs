//! Kinova Gen3 7-DOF figures (Gen3 user guide, via the field notes) and its forward kinematics
//! (classic DH), shared by the simulator, the driver and the panels. Angles in radians unless named
//! `_deg`.

use nalgebra::{Matrix4, SMatrix, Vector3};

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

/// A reported angle (any range; the Gen3 reports 0 to 360) as the same angle in (-180, 180],
/// about which a limited joint's limits are symmetric.
pub fn signed_deg(deg: f32) -> f32 {
    let wrapped = deg.rem_euclid(360.0);
    if wrapped > 180.0 {
        wrapped - 360.0
    } else {
        wrapped
    }
}

/// Joint `index`'s (0-6) margin to its nearer limit, degrees; `None` for a continuous joint
/// or a non-finite angle.
pub fn limit_margin(index: usize, position_deg: f32) -> Option<f32> {
    let limit = JOINT_LIMITS_DEG.get(index).copied().flatten()? as f32;
    position_deg
        .is_finite()
        .then(|| limit - signed_deg(position_deg).abs())
}

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

/// Each joint's frame (index i is joint i+1, axis Z) and the tool frame, base frame.
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

/// Each joint's lever arm (m): turning joint i at w rad/s moves the tool point `lever[i] * w`.
pub fn lever_arms(q: &[f64; 7]) -> [f64; 7] {
    let (before, tool) = frames(q);
    let p = column(&tool, 3);
    before.map(|f| column(&f, 2).cross(&(p - column(&f, 3))).norm())
}

/// The geometric Jacobian at the tool interface point, base frame: column i is joint i+1, rows vx,
/// vy, vz (m/s per rad/s) then wx, wy, wz (rad/s per rad/s).
pub fn jacobian_of_frames(before: &[Matrix4<f64>; 7], tool: &Matrix4<f64>) -> SMatrix<f64, 6, 7> {
    let p = column(tool, 3);
    let mut j = SMatrix::<f64, 6, 7>::zeros();
    for (i, f) in before.iter().enumerate() {
        let z = column(f, 2);
        let v = z.cross(&(p - column(f, 3)));
        j.fixed_view_mut::<3, 1>(0, i).copy_from(&v);
        j.fixed_view_mut::<3, 1>(3, i).copy_from(&z);
    }
    j
}

/// The geometric Jacobian for joint angles `q` (radians): see [`jacobian_of_frames`].
pub fn jacobian(q: &[f64; 7]) -> SMatrix<f64, 6, 7> {
    let (before, tool) = frames(q);
    jacobian_of_frames(&before, &tool)
}

/// The largest finite [`condition_number`]: below `largest · ε` a singular value is rounding noise,
/// so a rank-deficient Jacobian reads as this (about 4.5e15), not infinity.
pub const MAX_CONDITION_NUMBER: f64 = 1.0 / f64::EPSILON;

/// The Jacobian's condition number at `q` (rad): largest over smallest singular value, growing
/// without bound near a singularity. Its rows mix m/s with rad/s, so [`SINGULARITY_WARNING`] is
/// pinned to this model and these units. A rank-deficient pose gives [`MAX_CONDITION_NUMBER`], a
/// non-finite angle (or an SVD that does not converge) `f64::INFINITY`; never NaN.
pub fn condition_number(q: &[f64; 7]) -> f64 {
    // A NaN in the matrix could keep the SVD iterating: refuse it before.
    if !q.iter().all(|a| a.is_finite()) {
        return f64::INFINITY;
    }
    let Some(svd) = jacobian(q).try_svd(false, false, f64::EPSILON, 1000) else {
        return f64::INFINITY;
    };
    // The angular rows hold each joint's unit axis: the largest singular value is at least 1.
    let largest = svd.singular_values.max();
    let smallest = svd.singular_values.min();
    let kappa = largest / smallest.max(largest * f64::EPSILON);
    if kappa.is_finite() {
        kappa.clamp(1.0, MAX_CONDITION_NUMBER)
    } else {
        f64::INFINITY
    }
}

/// Above this [`condition_number`] the console names the arm as near a singularity. Near a straight
/// elbow κ is about 760 / |J4| (J4 in degrees), so 75 names the arm from 10.1° short of straight;
/// the poses measured are in `docs/development.md`.
pub const SINGULARITY_WARNING: f64 = 75.0;

/// Below this lever arm (m) a joint's rate is bounded by its own jog speed alone.
pub const MIN_LEVER_ARM: f64 = 0.01;

/// The fastest joint `joint` (1-7) at `position_deg` may turn, deg/s, for the tool point to stay
/// under `max_linear` m/s for `horizon` s. The lever arm is taken `max_linear * horizon` longer
/// than now (it grows no faster than the tool moves), so the bound holds until renewed.
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

    #[test]
    fn the_jacobian_matches_finite_differences_and_holds_the_joint_axes() {
        let q = [10.0, 20.0, 170.0, 240.0, 15.0, 50.0, 80.0].map(f64::to_radians);
        let j = jacobian(&q);
        let h = 1e-6;
        let (before, _) = frames(&q);
        for i in 0..7 {
            let mut turned = q;
            turned[i] += h;
            let d = (tool_position(&turned) - tool_position(&q)) / h;
            for k in 0..3 {
                assert!((j[(k, i)] - d[k]).abs() < 1e-4, "joint {} row {k}", i + 1);
                // The angular rows are the joint's axis, a unit vector.
                assert!((j[(k + 3, i)] - before[i][(k, 2)]).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn the_condition_number_grows_as_the_elbow_straightens() {
        let home = HOME_DEG.map(f64::to_radians);
        let at_home = condition_number(&home);
        assert!(at_home < SINGULARITY_WARNING, "{at_home}");
        assert!((at_home - 11.5).abs() < 0.1, "{at_home}");
        // J4 from a right angle towards straight (0): ever worse conditioned.
        let mut last = 0.0;
        for j4 in [-90.0, -60.0, -40.0, -20.0, -11.0, -10.0, -5.0, -2.0, -0.5] {
            let mut q = HOME_DEG;
            q[3] = j4;
            let kappa = condition_number(&q.map(f64::to_radians));
            assert!(kappa > last, "J4 {j4}: {kappa} after {last}");
            last = kappa;
            // The threshold falls between 11 and 10 degrees short of straight.
            assert_eq!(kappa > SINGULARITY_WARNING, j4 > -10.5, "J4 {j4}: {kappa}");
        }
    }

    #[test]
    fn a_rank_deficient_jacobian_gives_a_huge_finite_figure_never_nan() {
        // All zero: every axis is vertical (J1, J3, J5, J7) or along one horizontal (J2, J4,
        // J6), so no joint turns the tool about the third direction: rank 5 at most.
        let kappa = condition_number(&[0.0; 7]);
        assert!(kappa.is_finite() && kappa > 1e12, "{kappa}");
        assert!(kappa <= MAX_CONDITION_NUMBER);
        // The elbow exactly straight: the tool cannot move along the arm.
        let mut q = HOME_DEG;
        q[3] = 0.0;
        let kappa = condition_number(&q.map(f64::to_radians));
        assert!(kappa.is_finite() && kappa > 1e12, "{kappa}");
        // J2 and J6 at 0: J1 and J3 turn about one line, J5 and J7 about another; two pairs of
        // equal columns leave rank 5. Either pair alone leaves 6 (the seventh joint).
        let mut q = HOME_DEG;
        q[1] = 0.0;
        q[5] = 0.0;
        let kappa = condition_number(&q.map(f64::to_radians));
        assert!(kappa.is_finite() && kappa > 1e12, "{kappa}");
        q[1] = 15.0;
        assert!(condition_number(&q.map(f64::to_radians)) < SINGULARITY_WARNING);
        // Angles that are not numbers give no figure that could pass for a safe one.
        let mut q = HOME_DEG.map(f64::to_radians);
        q[1] = f64::NAN;
        assert_eq!(condition_number(&q), f64::INFINITY);
        q[1] = f64::INFINITY;
        assert_eq!(condition_number(&q), f64::INFINITY);
    }
}
