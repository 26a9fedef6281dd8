//! What telemetry says about the arm, for the console, its audit and `armjog modbus home`: at
//! rest or not, why an action aborted, whether the arm is in fault. Pure.

use super::gen3::JOINT_LIMITS_DEG;
use super::{Coded, Flag, RobotState, Telemetry};

/// Below these the arm is at rest.
pub const REST_JOINT_DEG_S: f32 = 0.5;
pub const REST_LINEAR_M_S: f32 = 0.002;
pub const REST_ANGULAR_DEG_S: f32 = 0.5;
/// A joint this close to its limit may be the one an abort stopped at.
const NEAR_LIMIT_DEG: f32 = 3.0;
/// A joint this close to its limit is at it.
const AT_LIMIT_DEG: f32 = 0.5;

/// Whether telemetry shows the arm at rest (NaN counts as moving).
pub fn at_rest(t: &Telemetry) -> bool {
    let v = t.tcp.twist;
    t.joints.iter().all(|j| j.velocity.abs() < REST_JOINT_DEG_S)
        && [v.x, v.y, v.z].iter().all(|c| c.abs() < REST_LINEAR_M_S)
        && [v.theta_x, v.theta_y, v.theta_z]
            .iter()
            .all(|c| c.abs() < REST_ANGULAR_DEG_S)
}

/// Why an action aborted, naming the joint at its limit if one is.
pub fn abort_reason(t: &Telemetry) -> String {
    let signed = |deg: f32| if deg > 180.0 { deg - 360.0 } else { deg };
    // How far each limited joint is from its limit, deg.
    let margin = |i: usize, position: f32| {
        JOINT_LIMITS_DEG
            .get(i)
            .copied()
            .flatten()
            .map(|limit| limit as f32 - signed(position).abs())
    };
    let nearest = t
        .joints
        .iter()
        .enumerate()
        .filter_map(|(i, j)| margin(i, j.position).map(|m| (i, m)))
        .filter(|(_, m)| *m <= NEAR_LIMIT_DEG)
        .min_by(|a, b| a.1.total_cmp(&b.1));
    // A joint is named as the cause when the arm says a joint faulted or the joint is right
    // at its limit; a joint merely near it (an abort by hand close to a limit) is only where
    // it was.
    let warned = t.warnings.contains(Flag::JointFault);
    match nearest {
        Some((i, m)) if warned || m <= AT_LIMIT_DEG => format!("aborted, J{} at its limit", i + 1),
        Some((i, _)) => format!("aborted, J{} near its limit", i + 1),
        None if warned => "aborted (joint fault warning)".into(),
        None => "aborted".into(),
    }
}

/// What the arm's fault is, if it is in fault.
pub fn fault_reason(t: &Telemetry) -> Option<String> {
    let state_fault = matches!(t.robot_state, Coded::Known(RobotState::InFault));
    if t.faults.is_empty() && !state_fault {
        return None;
    }
    let names = t.faults.names();
    Some(if names.is_empty() {
        "the arm is in fault".into()
    } else {
        format!("the arm is in fault: {}", names.join(", "))
    })
}
