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

/// A tool pose: position in m, orientation in deg (extrinsic XYZ Euler angles, Kinova's
/// convention).
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

/// `from_array` / `to_array` in the ICD's order (x, y, z, theta x, y, z) for the two blocks
/// that share that layout.
macro_rules! six_floats {
    ($($t:ident),*) => {$(
        impl $t {
            pub fn from_array(v: [f32; 6]) -> $t {
                let [x, y, z, theta_x, theta_y, theta_z] = v;
                $t { x, y, z, theta_x, theta_y, theta_z }
            }

            pub fn to_array(self) -> [f32; 6] {
                [self.x, self.y, self.z, self.theta_x, self.theta_y, self.theta_z]
            }
        }
    )*};
}

six_floats!(Pose, Twist);

impl Twist {
    pub const ZERO: Twist = Twist {
        x: 0.0,
        y: 0.0,
        z: 0.0,
        theta_x: 0.0,
        theta_y: 0.0,
        theta_z: 0.0,
    };

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

impl Wrench {
    pub fn from_array(v: [f32; 6]) -> Wrench {
        Wrench {
            force_x: v[0],
            force_y: v[1],
            force_z: v[2],
            torque_x: v[3],
            torque_y: v[4],
            torque_z: v[5],
        }
    }
}
