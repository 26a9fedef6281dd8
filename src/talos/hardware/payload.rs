//! The payload structures and their byte layouts.

use serde::Serialize;

use super::reader::{Reader, check_finite, check_joint};
use super::{ArmFlags, CommandFlags, HwError, RobotState, StatusFlags};

/// One actuator command (ActuatorCyclic.Command without its message id).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ActuatorCommand {
    pub flags: CommandFlags,
    pub position_deg: f32,
    pub velocity_deg_s: f32,
    pub torque_nm: f32,
    pub current_a: f32,
}

impl ActuatorCommand {
    /// Velocity jog as armjog sends it: SERVO_ENABLE, `velocity_deg_s` (0 holds), the joint's
    /// last reported position as `position_deg`, no torque or current setpoint. The server stops
    /// a jogging joint that gets no new command within 500 ms: resend while the jog is held.
    pub fn jog(position_deg: f32, velocity_deg_s: f32) -> Self {
        ActuatorCommand {
            flags: CommandFlags::SERVO_ENABLE,
            position_deg,
            velocity_deg_s,
            torque_nm: 0.0,
            current_a: 0.0,
        }
    }

    /// No undefined flag bit, every setpoint finite.
    pub fn validate(&self) -> Result<(), HwError> {
        let bits = self.flags.undefined_bits();
        if bits != 0 {
            return Err(HwError::UndefinedBits {
                field: "command_flags",
                bits,
            });
        }
        let [position, velocity, torque, current] = self.setpoints();
        check_finite("position_deg", position)?;
        check_finite("velocity_deg_s", velocity)?;
        check_finite("torque_nm", torque)?;
        check_finite("current_a", current)
    }

    /// Position, velocity, torque and current, in wire order.
    pub(super) fn setpoints(&self) -> [f32; 4] {
        [
            self.position_deg,
            self.velocity_deg_s,
            self.torque_nm,
            self.current_a,
        ]
    }
}

/// One actuator's feedback (ActuatorCyclic.Feedback with the joint index for its message id).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ActuatorFeedback {
    /// 1..=7.
    pub joint: u8,
    pub status: StatusFlags,
    pub jitter_us: u32,
    pub position_deg: f32,
    pub velocity_deg_s: f32,
    pub torque_nm: f32,
    pub current_a: f32,
    pub voltage_v: f32,
    pub motor_temp_c: f32,
    pub core_temp_c: f32,
    pub fault_bank_a: u32,
    pub fault_bank_b: u32,
    pub warning_bank_a: u32,
    pub warning_bank_b: u32,
}

impl ActuatorFeedback {
    /// Joint in 1..=7 and every float finite. Undefined status bits are allowed.
    pub fn validate(&self) -> Result<(), HwError> {
        check_joint(self.joint)?;
        for (field, value) in self.floats() {
            check_finite(field, value)?;
        }
        Ok(())
    }

    fn floats(&self) -> [(&'static str, f32); 7] {
        [
            ("position_deg", self.position_deg),
            ("velocity_deg_s", self.velocity_deg_s),
            ("torque_nm", self.torque_nm),
            ("current_a", self.current_a),
            ("voltage_v", self.voltage_v),
            ("motor_temp_c", self.motor_temp_c),
            ("core_temp_c", self.core_temp_c),
        ]
    }

    pub(super) fn write(&self, out: &mut Vec<u8>) {
        out.push(self.joint);
        out.extend_from_slice(&self.status.0.to_be_bytes());
        out.extend_from_slice(&self.jitter_us.to_be_bytes());
        for (_, value) in self.floats() {
            out.extend_from_slice(&value.to_be_bytes());
        }
        for word in [
            self.fault_bank_a,
            self.fault_bank_b,
            self.warning_bank_a,
            self.warning_bank_b,
        ] {
            out.extend_from_slice(&word.to_be_bytes());
        }
    }

    pub(super) fn read(r: &mut Reader<'_>) -> Result<Self, HwError> {
        let joint = r.u8()?;
        check_joint(joint)?;
        Ok(ActuatorFeedback {
            joint,
            status: StatusFlags(r.u32()?),
            jitter_us: r.u32()?,
            position_deg: r.f32("position_deg")?,
            velocity_deg_s: r.f32("velocity_deg_s")?,
            torque_nm: r.f32("torque_nm")?,
            current_a: r.f32("current_a")?,
            voltage_v: r.f32("voltage_v")?,
            motor_temp_c: r.f32("motor_temp_c")?,
            core_temp_c: r.f32("core_temp_c")?,
            fault_bank_a: r.u32()?,
            fault_bank_b: r.u32()?,
            warning_bank_a: r.u32()?,
            warning_bank_b: r.u32()?,
        })
    }
}

/// Arm-level telemetry; the fields follow Kinova Modbus input registers 0-13 and 104-139.
/// Pose, twist and wrench are those of the tool centre point in the base frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ArmState {
    pub robot_state: RobotState,
    pub faults: ArmFlags,
    pub warnings: ArmFlags,
    pub current_a: f32,
    pub voltage_v: f32,
    pub cpu_temp_c: f32,
    pub ambient_temp_c: f32,
    /// x, y, z.
    pub tcp_position_m: [f32; 3],
    /// theta x, y, z (extrinsic XYZ Euler angles).
    pub tcp_orientation_deg: [f32; 3],
    pub linear_velocity_m_s: [f32; 3],
    pub angular_velocity_deg_s: [f32; 3],
    pub force_n: [f32; 3],
    pub torque_nm: [f32; 3],
}

/// Names of ArmState's 22 floats in wire order.
#[rustfmt::skip]
const ARM_FLOAT_FIELDS: [&str; 22] = [
    "current_a", "voltage_v", "cpu_temp_c", "ambient_temp_c",
    "tcp_position_m.x", "tcp_position_m.y", "tcp_position_m.z",
    "tcp_orientation_deg.x", "tcp_orientation_deg.y", "tcp_orientation_deg.z",
    "linear_velocity_m_s.x", "linear_velocity_m_s.y", "linear_velocity_m_s.z",
    "angular_velocity_deg_s.x", "angular_velocity_deg_s.y", "angular_velocity_deg_s.z",
    "force_n.x", "force_n.y", "force_n.z",
    "torque_nm.x", "torque_nm.y", "torque_nm.z",
];

impl ArmState {
    /// Every float finite. Unknown robot states and undefined flag bits are allowed.
    pub fn validate(&self) -> Result<(), HwError> {
        for (field, value) in ARM_FLOAT_FIELDS.into_iter().zip(self.floats()) {
            check_finite(field, value)?;
        }
        Ok(())
    }

    /// The 22 floats in wire order.
    fn floats(&self) -> impl Iterator<Item = f32> {
        [
            self.current_a,
            self.voltage_v,
            self.cpu_temp_c,
            self.ambient_temp_c,
        ]
        .into_iter()
        .chain(self.tcp_position_m)
        .chain(self.tcp_orientation_deg)
        .chain(self.linear_velocity_m_s)
        .chain(self.angular_velocity_deg_s)
        .chain(self.force_n)
        .chain(self.torque_nm)
    }

    pub(super) fn write(&self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.robot_state.0.to_be_bytes());
        out.extend_from_slice(&self.faults.0.to_be_bytes());
        out.extend_from_slice(&self.warnings.0.to_be_bytes());
        for value in self.floats() {
            out.extend_from_slice(&value.to_be_bytes());
        }
    }

    pub(super) fn read(r: &mut Reader<'_>) -> Result<Self, HwError> {
        let robot_state = RobotState(r.u16()?);
        let faults = ArmFlags(r.u32()?);
        let warnings = ArmFlags(r.u32()?);
        let names = &mut ARM_FLOAT_FIELDS.into_iter();
        let [current_a, voltage_v, cpu_temp_c, ambient_temp_c] = r.f32s(names)?;
        Ok(ArmState {
            robot_state,
            faults,
            warnings,
            current_a,
            voltage_v,
            cpu_temp_c,
            ambient_temp_c,
            tcp_position_m: r.f32s(names)?,
            tcp_orientation_deg: r.f32s(names)?,
            linear_velocity_m_s: r.f32s(names)?,
            angular_velocity_deg_s: r.f32s(names)?,
            force_n: r.f32s(names)?,
            torque_nm: r.f32s(names)?,
        })
    }
}
