//! Kinova Gen3 7-DOF figures (Gen3 user guide, via the field notes), shared by the simulator and
//! the console's panels.

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
