//! `armjog send hw-op` as text: labelled lines with units; `--json` keeps full values.

use super::units::{arm_line, fixed, tool_lines};
use crate::talos::hardware::{ActuatorFeedback, ArmState, HwReply};

/// The lines under the reply's summary line, each indented by two spaces.
pub fn lines(reply: &HwReply) -> Vec<String> {
    let mut lines = match reply {
        HwReply::GetActuatorFeedback { actuators } if actuators.is_empty() => {
            vec!["no actuator feedback".to_string()]
        }
        HwReply::GetActuatorFeedback { actuators } => actuator_table(actuators),
        HwReply::SendActuatorCommand { feedback } => actuator_table(std::slice::from_ref(feedback)),
        HwReply::GetArmState { state } => arm_state(state),
        HwReply::StopAllJoints => vec!["all joints stopped".to_string()],
        HwReply::ClearAllFaults => vec!["all faults cleared".to_string()],
    };
    for line in &mut lines {
        line.insert_str(0, "  ");
    }
    lines
}

fn arm_state(s: &ArmState) -> Vec<String> {
    let mut lines = vec![
        format!("robot state   {}", s.robot_state),
        format!("faults        {}", s.faults),
        format!("warnings      {}", s.warnings),
        arm_line([s.current_a, s.voltage_v, s.cpu_temp_c, s.ambient_temp_c]),
    ];
    lines.extend(tool_lines(
        s.tcp_position_m.map(|m| f64::from(m * 1000.0)),
        s.tcp_orientation_deg,
        &[s.linear_velocity_m_s, s.angular_velocity_deg_s].concat(),
        &[s.force_n, s.torque_nm].concat(),
    ));
    lines
}

fn actuator_table(actuators: &[ActuatorFeedback]) -> Vec<String> {
    let f = |v: f32, d: usize| fixed(f64::from(v), d);
    let mut lines = vec![
        "joint  position deg  velocity deg/s  torque N m  current A  voltage V  motor C  core C  \
         status"
            .to_string(),
    ];
    for a in actuators {
        lines.push(format!(
            "{:>5}  {:>12}  {:>14}  {:>10}  {:>9}  {:>9}  {:>7}  {:>6}  {}",
            a.joint,
            f(a.position_deg, 3),
            f(a.velocity_deg_s, 3),
            f(a.torque_nm, 3),
            f(a.current_a, 3),
            f(a.voltage_v, 2),
            f(a.motor_temp_c, 1),
            f(a.core_temp_c, 1),
            a.status
        ));
    }
    let faulty: Vec<String> = actuators
        .iter()
        .filter(|a| {
            a.fault_bank_a != 0
                || a.fault_bank_b != 0
                || a.warning_bank_a != 0
                || a.warning_bank_b != 0
        })
        .map(|a| {
            format!(
                "joint {}: fault banks A 0x{:08X} B 0x{:08X}, warning banks A 0x{:08X} B 0x{:08X}",
                a.joint, a.fault_bank_a, a.fault_bank_b, a.warning_bank_a, a.warning_bank_b
            )
        })
        .collect();
    if faulty.is_empty() {
        lines.push("no actuator faults or warnings".to_string());
    }
    lines.extend(faulty);
    lines
}
