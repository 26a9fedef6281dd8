//! The simulated arm's snapshot in the shapes the hardware companion ICD reports.

use super::arm_model::ArmSnapshot;
use crate::kortex::CodeName;
use crate::talos::hardware::{ActuatorFeedback, ArmFlags, ArmState, RobotState, StatusFlags};

/// Feedback of joint `joint` (1..=7; the caller validated it, out-of-range values are clamped).
pub fn actuator_feedback(s: &ArmSnapshot, joint: u8) -> ActuatorFeedback {
    let i = usize::from(joint.clamp(1, 7) - 1);
    let moving = s.joint_velocity[i].abs() > 1e-6;
    let mut status = StatusFlags::STABILIZED
        | StatusFlags::MOTOR_INDEXED
        | StatusFlags::CALIBRATED_TORQUE
        | StatusFlags::CALIBRATED_MAG_SENSOR
        | StatusFlags::CALIBRATED_ZERO
        | StatusFlags::CALIBRATED_CURRENT
        | StatusFlags::CALIBRATED_MOTOR;
    if moving {
        status = status | StatusFlags::SERVOING;
    }
    if s.faults != 0 {
        status = status | StatusFlags::MAJOR_FAULT;
    }
    ActuatorFeedback {
        joint: joint.clamp(1, 7),
        status,
        jitter_us: 0,
        position_deg: s.joint_position[i] as f32,
        velocity_deg_s: s.joint_velocity[i] as f32,
        torque_nm: s.joint_torque[i] as f32,
        current_a: s.joint_current[i] as f32,
        voltage_v: s.arm_voltage as f32,
        motor_temp_c: s.joint_temperature[i] as f32,
        core_temp_c: (s.joint_temperature[i] + 5.0) as f32,
        fault_bank_a: 0,
        fault_bank_b: 0,
        warning_bank_a: 0,
        warning_bank_b: 0,
    }
}

/// The arm-level state (GET_ARM_STATE).
pub fn arm_state(s: &ArmSnapshot) -> ArmState {
    let f = |v: [f64; 3]| v.map(|x| x as f32);
    ArmState {
        robot_state: RobotState(s.robot_state.code()),
        faults: ArmFlags(s.faults),
        warnings: ArmFlags(s.warnings),
        current_a: s.arm_current as f32,
        voltage_v: s.arm_voltage as f32,
        cpu_temp_c: s.cpu_temperature as f32,
        ambient_temp_c: s.ambient_temperature as f32,
        tcp_position_m: f(s.tcp_position),
        tcp_orientation_deg: f(s.tcp_orientation),
        linear_velocity_m_s: f(s.tcp_linear_velocity),
        angular_velocity_deg_s: f(s.tcp_angular_velocity),
        force_n: f(s.tcp_force),
        torque_nm: f(s.tcp_torque),
    }
}
