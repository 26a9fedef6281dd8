//! Kinova Gen3 7-DOF kinematics (DH table in [`crate::kortex::gen3`]): forward kinematics, the
//! Jacobian and damped-least-squares IK. Radians and metres; orientation a rotation matrix (Kinova
//! reports extrinsic XYZ Euler degrees, `R = Rz(θz)·Ry(θy)·Rx(θx)`).

use nalgebra::{Matrix4, Matrix6, Rotation3, SMatrix, UnitQuaternion, Vector3, Vector6};

pub const JOINTS: usize = 7;

/// Joint angles in radians.
pub type Joints = [f64; JOINTS];

use crate::kortex::gen3::frames;
/// The geometric Jacobian, base frame.
pub use crate::kortex::gen3::jacobian;
pub use crate::kortex::gen3::{HOME_DEG, JOINT_LIMITS_DEG, MAX_JOINT_SPEED_DEG, MAX_JOINT_TORQUE};

/// A tool pose in the base frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    pub position: Vector3<f64>,
    pub rotation: Rotation3<f64>,
}

impl Pose {
    /// Kinova's orientation: extrinsic XYZ Euler angles, degrees.
    pub fn euler_deg(&self) -> [f64; 3] {
        let (x, y, z) = self.rotation.euler_angles();
        [x.to_degrees(), y.to_degrees(), z.to_degrees()]
    }

    pub fn from_position_euler_deg(position: [f64; 3], theta_deg: [f64; 3]) -> Pose {
        Pose {
            position: Vector3::from(position),
            rotation: Rotation3::from_euler_angles(
                theta_deg[0].to_radians(),
                theta_deg[1].to_radians(),
                theta_deg[2].to_radians(),
            ),
        }
    }
}

fn pose_of(t: &Matrix4<f64>) -> Pose {
    let r = t.fixed_view::<3, 3>(0, 0).into_owned();
    Pose {
        position: Vector3::new(t[(0, 3)], t[(1, 3)], t[(2, 3)]),
        rotation: Rotation3::from_matrix_unchecked(r),
    }
}

/// Forward kinematics: the tool interface pose for joint angles `q`.
pub fn forward(q: &Joints) -> Pose {
    pose_of(&frames(q).1)
}

/// The tool pose and the Jacobian from one pass (the integrator needs both every step).
pub fn pose_and_jacobian(q: &Joints) -> (Pose, SMatrix<f64, 6, JOINTS>) {
    let (before, tool) = frames(q);
    let j = crate::kortex::gen3::jacobian_of_frames(&before, &tool);
    (pose_of(&tool), j)
}

/// Joint velocities best producing `xdot` (m/s, rad/s, base frame) through the Jacobian `j`,
/// damped near singularities.
pub fn dls_velocity_with(j: &SMatrix<f64, 6, JOINTS>, xdot: &Vector6<f64>, damping: f64) -> Joints {
    let jjt: Matrix6<f64> = j * j.transpose() + Matrix6::identity() * damping * damping;
    let Some(inv) = jjt.try_inverse() else {
        return [0.0; JOINTS];
    };
    let dq = j.transpose() * (inv * xdot);
    let mut out = [0.0; JOINTS];
    out.copy_from_slice(dq.as_slice());
    out
}

/// The 6-vector error from `from` to `to`: position (m) then rotation vector (rad).
pub fn pose_error(from: &Pose, to: &Pose) -> Vector6<f64> {
    let dp = to.position - from.position;
    let dr = rotation_vector(&(to.rotation * from.rotation.inverse()));
    Vector6::new(dp.x, dp.y, dp.z, dr.x, dr.y, dr.z)
}

/// The rotation vector (axis times angle, rad) of `r`, finite down to zero: nalgebra's
/// `scaled_axis` takes `acos` of an argument rounding puts just above 1 near identity, giving NaN
/// (it stopped a move that had arrived); here the angle comes from `atan2`.
pub fn rotation_vector(r: &Rotation3<f64>) -> Vector3<f64> {
    let m = r.matrix();
    // sin(angle) times the axis.
    let v = Vector3::new(
        m[(2, 1)] - m[(1, 2)],
        m[(0, 2)] - m[(2, 0)],
        m[(1, 0)] - m[(0, 1)],
    ) * 0.5;
    let sin = v.norm();
    let cos = (m.trace() - 1.0) * 0.5;
    if cos < -0.99 {
        // Near a half turn the skew part vanishes and says little about the axis.
        return UnitQuaternion::from_rotation_matrix(r).scaled_axis();
    }
    if sin == 0.0 {
        return Vector3::zeros();
    }
    v * (sin.atan2(cos) / sin)
}

/// Why inverse kinematics gave up.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum IkError {
    #[error("target not reached: {position_mm:.1} mm / {rotation_deg:.2} deg away")]
    Unreachable { position_mm: f64, rotation_deg: f64 },
    #[error("the solution passes the limit of joint {joint}")]
    JointLimit { joint: usize },
}

/// Whether joint `i` at `angle` (rad) is inside its limit.
pub fn within_limit(i: usize, angle: f64) -> bool {
    match JOINT_LIMITS_DEG[i] {
        Some(limit) => wrap_pi(angle).abs() <= limit.to_radians() + 1e-9,
        None => true,
    }
}

/// An angle folded into (-pi, pi].
pub fn wrap_pi(angle: f64) -> f64 {
    let two_pi = std::f64::consts::TAU;
    let mut a = angle.rem_euclid(two_pi);
    if a > std::f64::consts::PI {
        a -= two_pi;
    }
    a
}

/// Damped-least-squares IK from `q0` to `target` (1e-4 m, 0.01 deg), limited joints clamped.
pub fn inverse(q0: &Joints, target: &Pose) -> Result<Joints, IkError> {
    let mut q = *q0;
    let mut err = pose_error(&forward(&q), target);
    for _ in 0..400 {
        let position = err.fixed_rows::<3>(0).norm();
        let rotation = err.fixed_rows::<3>(3).norm();
        if position < 1e-4 && rotation < 1e-2_f64.to_radians() {
            return Ok(q);
        }
        // Cap each step so the linearisation holds.
        let scale = (0.05 / position.max(1e-12))
            .min(0.2 / rotation.max(1e-12))
            .min(1.0);
        let dq = dls_velocity_with(&jacobian(&q), &(err * scale), 0.02);
        for i in 0..JOINTS {
            q[i] += dq[i];
            if let Some(limit) = JOINT_LIMITS_DEG[i] {
                let limit = limit.to_radians();
                q[i] = wrap_pi(q[i]).clamp(-limit, limit);
            }
        }
        err = pose_error(&forward(&q), target);
    }
    Err(IkError::Unreachable {
        position_mm: err.fixed_rows::<3>(0).norm() * 1000.0,
        rotation_deg: err.fixed_rows::<3>(3).norm().to_degrees(),
    })
}

/// Why a joint has no pose near its limit.
#[derive(Debug, thiserror::Error)]
pub enum NoNearLimit {
    #[error("--near-limit {0}: the Gen3 has joints 1 to 7")]
    NoSuchJoint(u8),
    #[error("--near-limit {0}: joint {0} turns continuously; J2, J4 and J6 have limits")]
    Continuous(u8),
}

/// How far inside its limit `armjog sim --near-limit` places a joint, degrees.
pub const NEAR_LIMIT_MARGIN_DEG: f64 = 2.0;

/// Home (degrees) with `joint` (1-7) [`NEAR_LIMIT_MARGIN_DEG`] inside its upper limit, for `armjog
/// sim --near-limit`. Refuses a continuous joint and a number out of 1-7.
pub fn near_limit_pose_deg(joint: u8) -> Result<Joints, NoNearLimit> {
    let index = usize::from(joint)
        .checked_sub(1)
        .filter(|i| *i < JOINTS)
        .ok_or(NoNearLimit::NoSuchJoint(joint))?;
    let Some(limit) = JOINT_LIMITS_DEG[index] else {
        return Err(NoNearLimit::Continuous(joint));
    };
    let mut q = HOME_DEG;
    q[index] = limit - NEAR_LIMIT_MARGIN_DEG;
    Ok(q)
}

/// How far short of a straight elbow `armjog sim --near-singularity` bends J4, degrees.
pub const NEAR_SINGULARITY_ELBOW_DEG: f64 = 3.0;

/// Home (degrees) with J4 [`NEAR_SINGULARITY_ELBOW_DEG`] short of straight (reported 357°), for
/// `armjog sim --near-singularity`: κ about 253, inside the console's warning
/// ([`crate::kortex::gen3::SINGULARITY_WARNING`]), every joint far from its limit.
pub fn near_singularity_pose_deg() -> Joints {
    let mut q = HOME_DEG;
    q[3] = -NEAR_SINGULARITY_ELBOW_DEG;
    q
}

pub fn to_radians(deg: &Joints) -> Joints {
    deg.map(f64::to_radians)
}

/// Joint angles as Kinova reports them: 0 to 360 degrees.
pub fn reported_deg(q: &Joints) -> Joints {
    q.map(|a| a.to_degrees().rem_euclid(360.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn assert_close(a: [f64; 3], b: [f64; 3], tol: f64) {
        for k in 0..3 {
            assert!((a[k] - b[k]).abs() <= tol, "{a:?} vs {b:?}");
        }
    }

    #[test]
    fn zero_pose_matches_the_field_notes() {
        let p = forward(&[0.0; JOINTS]);
        assert_close(p.position.into(), [0.0, -0.0246, 1.1873], 1e-3);
    }

    #[test]
    fn home_pose_matches_the_field_notes_within_a_millimetre() {
        let p = forward(&to_radians(&HOME_DEG));
        assert_close(p.position.into(), [0.4566, 0.0010, 0.4338], 1e-3);
        assert_close(p.euler_deg(), [90.0, 0.0, 90.0], 0.05);
    }

    #[test]
    fn jacobian_matches_finite_differences() {
        let q = to_radians(&[10.0, 20.0, 170.0, 240.0, 15.0, 50.0, 80.0]);
        let j = jacobian(&q);
        let h = 1e-6;
        for i in 0..JOINTS {
            let mut qp = q;
            qp[i] += h;
            let d = (forward(&qp).position - forward(&q).position) / h;
            for k in 0..3 {
                assert!((j[(k, i)] - d[k]).abs() < 1e-4, "joint {i} row {k}");
            }
        }
        // One pass gives the same pose and Jacobian as the two separate calls.
        let (pose, j2) = pose_and_jacobian(&q);
        assert_eq!(j2, j);
        assert_eq!(pose, forward(&q));
    }

    #[test]
    fn ik_round_trips_across_the_workspace() {
        let seeds = [
            [0.0, 15.0, 180.0, 230.0, 0.0, 55.0, 90.0],
            [30.0, 30.0, 180.0, 240.0, 10.0, 60.0, 90.0],
            [-40.0, 5.0, 170.0, 220.0, -20.0, 40.0, 60.0],
            [90.0, 40.0, 190.0, 250.0, 30.0, 70.0, 120.0],
        ];
        for target_deg in seeds {
            let target = forward(&to_radians(&target_deg));
            let q = inverse(&to_radians(&HOME_DEG), &target).expect("reachable");
            let got = forward(&q);
            assert!(
                (got.position - target.position).norm() < 1e-3,
                "{target_deg:?}"
            );
            for (i, a) in q.iter().enumerate() {
                assert!(within_limit(i, *a), "joint {i} out of limits");
            }
        }
    }

    #[test]
    fn ik_refuses_a_target_out_of_reach() {
        let far = Pose::from_position_euler_deg([2.0, 0.0, 0.5], [90.0, 0.0, 90.0]);
        assert!(matches!(
            inverse(&to_radians(&HOME_DEG), &far),
            Err(IkError::Unreachable { .. })
        ));
    }

    #[test]
    fn the_rotation_vector_is_finite_and_exact_from_zero_to_a_half_turn() {
        use std::f64::consts::PI;
        let axis = Vector3::new(0.3, -0.5, 0.8).normalize();
        for angle in [0.0, 1e-12, 1e-9, 1e-6, 0.01, 1.0, 3.0, 3.1, PI - 1e-4] {
            let r = Rotation3::new(axis * angle);
            let v = rotation_vector(&r);
            assert!((v - axis * angle).norm() < 1e-9, "{angle}: {v:?}");
        }
        // J1 turned by 1e-12 rad near home: the product's trace rounds above 3, and nalgebra's
        // scaled_axis gives NaN for it (found by search; other tiny turns do it too).
        let mut q = to_radians(&HOME_DEG);
        q[0] += 0.07;
        q[2] += 0.03;
        let from = forward(&q);
        q[0] += 1e-12;
        let near = forward(&q);
        let e = pose_error(&from, &near);
        assert!(e.iter().all(|x| x.is_finite()), "{e:?}");
        assert!(e.fixed_rows::<3>(3).norm() < 1e-9);
    }

    #[test]
    fn near_limit_poses_sit_two_degrees_inside_the_limit_of_limited_joints_only() {
        let q = near_limit_pose_deg(4).unwrap();
        assert!((q[3] - 145.8).abs() < 1e-9, "{q:?}");
        assert_eq!(q[..3], HOME_DEG[..3]);
        assert_eq!(q[4..], HOME_DEG[4..]);
        for joint in [2u8, 6] {
            let q = near_limit_pose_deg(joint).unwrap();
            let i = usize::from(joint - 1);
            let limit = JOINT_LIMITS_DEG[i].unwrap();
            assert!(within_limit(i, q[i].to_radians()));
            assert!((limit - q[i] - 2.0).abs() < 1e-9);
        }
        for joint in [1u8, 3, 5, 7] {
            let e = near_limit_pose_deg(joint).unwrap_err().to_string();
            assert!(e.contains("continuously"), "{e}");
        }
        for joint in [0u8, 8] {
            let e = near_limit_pose_deg(joint).unwrap_err().to_string();
            assert!(e.contains("1 to 7"), "{e}");
        }
    }

    #[test]
    fn the_near_singularity_pose_is_inside_the_warning_and_the_joint_limits() {
        use crate::kortex::gen3::{SINGULARITY_WARNING, condition_number};
        let q = to_radians(&near_singularity_pose_deg());
        let kappa = condition_number(&q);
        assert!(kappa > 2.0 * SINGULARITY_WARNING && kappa < 1e3, "{kappa}");
        for (i, a) in q.iter().enumerate() {
            assert!(within_limit(i, *a), "joint {}", i + 1);
        }
        // The tool is still above the table.
        assert!(forward(&q).position.z > 0.5);
    }

    #[test]
    fn reported_angles_are_0_to_360() {
        let r = reported_deg(&to_radians(&[-10.0, 0.0, 370.0, 230.0, 0.0, 0.0, 0.0]));
        assert!((r[0] - 350.0).abs() < 1e-9 && (r[2] - 10.0).abs() < 1e-9);
    }
}
