//! Talos-only telemetry from the hardware ICD's GET_ARM_STATE and GET_ACTUATOR_FEEDBACK.

use crate::kortex::{
    ActionState, ArmHealth, Coded, FlagSet, JointState, Pose, SpeedLimits, Telemetry, ToolState,
    Twist, Wrench,
};
use crate::talos::hardware::{ActuatorFeedback, ArmState};

/// A snapshot; joints without feedback read zero, action status and limits unknown (not on Talos).
pub fn telemetry(state: &ArmState, actuators: &[ActuatorFeedback]) -> Telemetry {
    let mut joints = [JointState::default(); 7];
    for a in actuators {
        if let Some(j) = joints.get_mut(usize::from(a.joint).wrapping_sub(1)) {
            *j = JointState {
                position: a.position_deg,
                velocity: a.velocity_deg_s,
                torque: a.torque_nm,
                current: a.current_a,
                temperature: a.motor_temp_c,
            };
        }
    }
    let six = |a: [f32; 3], b: [f32; 3]| [a[0], a[1], a[2], b[0], b[1], b[2]];
    Telemetry {
        robot_state: Coded::from_code(state.robot_state.0),
        faults: FlagSet::from_bits(state.faults.0),
        warnings: FlagSet::from_bits(state.warnings.0),
        arm: ArmHealth {
            current: state.current_a,
            voltage: state.voltage_v,
            cpu_temperature: state.cpu_temp_c,
            ambient_temperature: state.ambient_temp_c,
        },
        joints,
        tcp: ToolState {
            pose: Pose::from_array(six(state.tcp_position_m, state.tcp_orientation_deg)),
            twist: Twist::from_array(six(state.linear_velocity_m_s, state.angular_velocity_deg_s)),
            wrench: Wrench::from_array(six(state.force_n, state.torque_nm)),
        },
        action: ActionState {
            status: Coded::Unknown(u16::MAX),
            id: 0,
            move_type: Coded::Unknown(u16::MAX),
        },
        speed_limits: SpeedLimits::default(),
        control: Coded::Unknown(u16::MAX),
        state_from_inputs: None,
    }
}
