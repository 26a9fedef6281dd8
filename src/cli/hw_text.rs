//! `armjog send hw-op` as text: labelled lines with units; `--json` keeps full values.

use super::units::{fixed, linear_speed};
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
    let f = |v: f32, d: usize| fixed(f64::from(v), d);
    let [x, y, z] = s.tcp_position_m.map(|m| f(m * 1000.0, 1));
    let [rx, ry, rz] = s.tcp_orientation_deg.map(|d| f(d, 2));
    let [vx, vy, vz] = s.linear_velocity_m_s.map(|v| linear_speed(f64::from(v)));
    let [wx, wy, wz] = s.angular_velocity_deg_s.map(|d| f(d, 2));
    let [fx, fy, fz] = s.force_n.map(|n| f(n, 2));
    let [tx, ty, tz] = s.torque_nm.map(|n| f(n, 3));
    vec![
        format!("robot state   {}", s.robot_state),
        format!("faults        {}", s.faults),
        format!("warnings      {}", s.warnings),
        format!(
            "arm           current {} A   voltage {} V   cpu {} C   ambient {} C",
            f(s.current_a, 3),
            f(s.voltage_v, 3),
            f(s.cpu_temp_c, 1),
            f(s.ambient_temp_c, 1)
        ),
        format!(
            "tcp pose      x {x} mm   y {y} mm   z {z} mm   theta x {rx}   y {ry}   z {rz} deg"
        ),
        format!("tcp twist     x {vx}   y {vy}   z {vz}   theta x {wx}   y {wy}   z {wz} deg/s"),
        format!(
            "tcp wrench    force x {fx}   y {fy}   z {fz} N   torque x {tx}   y {ty}   z {tz} N m"
        ),
    ]
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
