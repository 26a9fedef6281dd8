//! What telemetry says about the arm, for the console and `armjog modbus home`: at rest or
//! not, why an action aborted, whether the arm is in fault; and ages as the screen shows them.
//! Pure.

use std::time::Duration;

use crate::kortex::gen3::JOINT_LIMITS_DEG;
use crate::kortex::{Coded, Flag, RobotState, Telemetry};

/// Below these the arm is at rest.
const REST_JOINT_DEG_S: f32 = 0.5;
const REST_LINEAR_M_S: f32 = 0.002;
const REST_ANGULAR_DEG_S: f32 = 0.5;
/// A joint this close to its limit is the one an abort stopped at.
const AT_LIMIT_DEG: f32 = 3.0;
/// Ages below this are shown in tenths of a second, above it in whole seconds.
pub(super) const AGE_TENTHS_UNTIL: Duration = Duration::from_secs(10);

/// An age for the screen: `1.8 s`, or `42 s` once past ten seconds.
pub fn age_text(age: Duration) -> String {
    if age < AGE_TENTHS_UNTIL {
        format!("{:.1} s", age.as_secs_f64())
    } else {
        format!("{} s", age.as_secs())
    }
}

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
    let at_limit = t.joints.iter().enumerate().find(|(i, j)| {
        JOINT_LIMITS_DEG
            .get(*i)
            .copied()
            .flatten()
            .is_some_and(|limit| signed(j.position).abs() >= limit as f32 - AT_LIMIT_DEG)
    });
    // A joint near its limit is named as the cause only when the arm also says a joint
    // faulted; otherwise it is only where the joint was (an abort by hand near a limit).
    let warned = t.warnings.contains(Flag::JointFault);
    match (at_limit, warned) {
        (Some((i, _)), true) => format!("aborted, J{} at its limit", i + 1),
        (Some((i, _)), false) => format!("aborted, J{} near its limit", i + 1),
        (None, true) => "aborted (joint fault warning)".into(),
        (None, false) => "aborted".into(),
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
