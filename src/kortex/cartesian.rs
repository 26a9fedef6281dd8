//! Cartesian quantities as the ICD lays them out: x, y, z, then theta x, y, z.

use serde::Serialize;

/// Position of a value in a six-float cartesian block.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Axis {
    X = 0,
    Y = 1,
    Z = 2,
    ThetaX = 3,
    ThetaY = 4,
    ThetaZ = 5,
}

/// A tool pose: position in m, orientation in deg (extrinsic XYZ Euler, Kinova's convention).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Pose {
    pub x: f32,
    pub y: f32,
    pub z: f32,
    pub theta_x: f32,
    pub theta_y: f32,
    pub theta_z: f32,
}

/// A cartesian velocity: linear in m/s, angular in deg/s.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Twist {
    pub x: f32,
    pub y: f32,
    pub z: f32,
    pub theta_x: f32,
    pub theta_y: f32,
    pub theta_z: f32,
}

/// Force (N) and torque (N m) at the tool.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Wrench {
    pub force_x: f32,
    pub force_y: f32,
    pub force_z: f32,
    pub torque_x: f32,
    pub torque_y: f32,
    pub torque_z: f32,
}

/// `from_array` / `to_array` in the ICD's order (x, y, z, theta x, y, z).
macro_rules! six_floats {
    ($($t:ident { $($field:ident),* })*) => {$(
        impl $t {
            pub const fn from_array(v: [f32; 6]) -> $t {
                let [$($field),*] = v;
                $t { $($field),* }
            }

            pub fn to_array(self) -> [f32; 6] {
                [$(self.$field),*]
            }
        }
    )*};
}

six_floats! {
    Pose { x, y, z, theta_x, theta_y, theta_z }
    Twist { x, y, z, theta_x, theta_y, theta_z }
    Wrench { force_x, force_y, force_z, torque_x, torque_y, torque_z }
}

impl Twist {
    pub const ZERO: Twist = Twist::from_array([0.0; 6]);

    /// Speed of the tool point, m/s.
    pub fn linear_speed(self) -> f32 {
        (self.x * self.x + self.y * self.y + self.z * self.z).sqrt()
    }

    /// Rotation rate, deg/s.
    pub fn angular_speed(self) -> f32 {
        (self.theta_x * self.theta_x + self.theta_y * self.theta_y + self.theta_z * self.theta_z)
            .sqrt()
    }

    pub fn is_zero(self) -> bool {
        self.to_array().iter().all(|v| *v == 0.0)
    }
}

impl Pose {
    /// How far the tool point of `self` is from `other`'s, m.
    pub fn distance_to(&self, other: &Pose) -> f32 {
        let d = [self.x - other.x, self.y - other.y, self.z - other.z];
        (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
    }

    /// The angle of the turn from `self`'s orientation to `other`'s, deg (0-180): two Euler
    /// triples that name one orientation (theta y past 90, a theta wrapped by 360) are 0 apart.
    pub fn turn_to(&self, other: &Pose) -> f32 {
        turn_between_deg(
            [self.theta_x, self.theta_y, self.theta_z],
            [other.theta_x, other.theta_y, other.theta_z],
        )
    }
}

/// The angle of the turn between two orientations given as extrinsic XYZ Euler angles in
/// degrees (Kinova's convention: R = Rz(θz)·Ry(θy)·Rx(θx)), deg: from the trace of the one
/// rotation relative to the other. NaN in, NaN out.
pub fn turn_between_deg(a: [f32; 3], b: [f32; 3]) -> f32 {
    let (ra, rb) = (rotation(a), rotation(b));
    // trace(Raᵀ·Rb) = Σ Ra[i][j]·Rb[i][j]
    let trace: f64 = (0..3)
        .flat_map(|i| (0..3).map(move |j| (i, j)))
        .map(|(i, j)| ra[i][j] * rb[i][j])
        .sum();
    ((trace - 1.0) / 2.0).clamp(-1.0, 1.0).acos().to_degrees() as f32
}

type Matrix = [[f64; 3]; 3];

fn rotation([x, y, z]: [f32; 3]) -> Matrix {
    let (sx, cx) = f64::from(x).to_radians().sin_cos();
    let (sy, cy) = f64::from(y).to_radians().sin_cos();
    let (sz, cz) = f64::from(z).to_radians().sin_cos();
    let rx = [[1.0, 0.0, 0.0], [0.0, cx, -sx], [0.0, sx, cx]];
    let ry = [[cy, 0.0, sy], [0.0, 1.0, 0.0], [-sy, 0.0, cy]];
    let rz = [[cz, -sz, 0.0], [sz, cz, 0.0], [0.0, 0.0, 1.0]];
    product(&product(&rz, &ry), &rx)
}

fn product(a: &Matrix, b: &Matrix) -> Matrix {
    let mut out = [[0.0; 3]; 3];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, cell) in row.iter_mut().enumerate() {
            *cell = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f32, b: f32) -> bool {
        (a - b).abs() < 1e-3
    }

    #[test]
    fn a_turn_is_the_angle_between_the_orientations_whatever_triple_names_them() {
        assert!(close(
            turn_between_deg([90.0, 0.0, 90.0], [90.0, 0.0, 90.0]),
            0.0
        ));
        // A turn about one axis alone is its angle.
        assert!(close(
            turn_between_deg([0.0, 0.0, 10.0], [0.0, 0.0, 40.0]),
            30.0
        ));
        assert!(close(
            turn_between_deg([90.0, 0.0, 90.0], [90.0, 0.0, -90.0]),
            180.0
        ));
        // 360 apart, and the other Euler triple of one orientation, (x+180, 180-y, z+180).
        assert!(close(
            turn_between_deg([10.0, 0.0, 350.0], [10.0, 0.0, -10.0]),
            0.0
        ));
        assert!(close(
            turn_between_deg([30.0, 20.0, 40.0], [210.0, 160.0, 220.0]),
            0.0
        ));
        // Two axes at once: Rz(90)·Rx(90) against Rz(90)·Ry(-120)·Rx(90) is a 120 degree turn
        // about the tool's own axis.
        assert!(close(
            turn_between_deg([90.0, 0.0, 90.0], [90.0, -120.0, 90.0]),
            120.0
        ));
        assert!(turn_between_deg([f32::NAN, 0.0, 0.0], [0.0; 3]).is_nan());
    }

    #[test]
    fn a_distance_is_between_the_tool_points() {
        let a = Pose::from_array([0.4, 0.1, 0.3, 90.0, 0.0, 90.0]);
        let b = Pose::from_array([0.4, 0.13, 0.34, 0.0, 0.0, 0.0]);
        assert!(close(a.distance_to(&b), 0.05));
        assert!(close(a.turn_to(&a), 0.0));
    }
}
