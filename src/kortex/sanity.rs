//! Whether a reported value is physically possible: the one place that decides it, for the panels
//! (`?` and a warning) and the motion gate. Bounds are about five times the Gen3's own limits
//! (`shared/field-notes.md`: 0-360 deg, 80/70 deg/s, 39/9 N m, 0.5 m/s and 100 deg/s, 1.2 m reach),
//! so only nonsense (1e9, NaN, infinity) is refused, never a reading near a limit.

use std::fmt;

use super::registers::input_register as ir;
use super::telemetry::Telemetry;

/// The closed range a value must be in, finite.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    pub min: f32,
    pub max: f32,
}

impl Bounds {
    const fn symmetric(max: f32) -> Bounds {
        Bounds { min: -max, max }
    }

    /// `value` if it is finite and within the bounds.
    pub fn sane(self, value: f32) -> Option<f32> {
        (value.is_finite() && value >= self.min && value <= self.max).then_some(value)
    }
}

/// Joint angle, deg: reported 0-360; one turn either side of that is still an angle.
pub const JOINT_ANGLE_DEG: Bounds = Bounds {
    min: -360.0,
    max: 720.0,
};
/// Joint speed, deg/s: five times the 80 deg/s maximum.
pub const JOINT_SPEED_DEG_S: Bounds = Bounds::symmetric(400.0);
/// Joint torque, N m: five times the 39 N m maximum.
pub const JOINT_TORQUE_NM: Bounds = Bounds::symmetric(200.0);
/// Joint or arm current, A.
pub const CURRENT_A: Bounds = Bounds::symmetric(50.0);
/// A temperature, deg C.
pub const TEMPERATURE_C: Bounds = Bounds {
    min: -60.0,
    max: 250.0,
};
/// The arm's supply voltage, V (24 V nominal).
pub const VOLTAGE_V: Bounds = Bounds {
    min: -5.0,
    max: 100.0,
};
/// Tool position, m: four times the reach.
pub const TOOL_POSITION_M: Bounds = Bounds::symmetric(5.0);
/// Tool orientation, deg.
pub const TOOL_ORIENTATION_DEG: Bounds = Bounds::symmetric(720.0);
/// Tool linear speed, m/s (each axis): five times the 0.5 m/s hard limit.
pub const TOOL_LINEAR_SPEED_M_S: Bounds = Bounds::symmetric(2.5);
/// Tool angular speed, deg/s (each axis): five times the 100 deg/s hard limit.
pub const TOOL_ANGULAR_SPEED_DEG_S: Bounds = Bounds::symmetric(500.0);
/// Force at the tool, N.
pub const TOOL_FORCE_N: Bounds = Bounds::symmetric(2000.0);
/// Torque at the tool, N m.
pub const TOOL_TORQUE_NM: Bounds = Bounds::symmetric(500.0);

/// A reported value out of its bounds: what it is, where the ICD puts it, what it was.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InsaneField {
    /// What the value is: `position`, `tool twist x`, `arm voltage`.
    pub field: &'static str,
    /// The joint (1-7), for a joint's value.
    pub joint: Option<u8>,
    /// The first of the two input registers the ICD gives it.
    pub register: u16,
    pub value: f32,
}

impl fmt::Display for InsaneField {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(joint) = self.joint {
            write!(f, "J{joint} ")?;
        }
        let v = self.value;
        // 1e30 reads as itself, not as 31 digits.
        let value = if v.is_finite() && v.abs() < 1e6 {
            v.to_string()
        } else {
            format!("{v:e}")
        };
        write!(
            f,
            "{} {value} (input registers {}-{})",
            self.field,
            self.register,
            self.register + 1
        )
    }
}

const JOINT_FIELDS: [(&str, u16, Bounds); 5] = [
    ("position", ir::JOINT_POSITIONS, JOINT_ANGLE_DEG),
    ("speed", ir::JOINT_VELOCITIES, JOINT_SPEED_DEG_S),
    ("torque", ir::JOINT_TORQUES, JOINT_TORQUE_NM),
    ("current", ir::JOINT_CURRENTS, CURRENT_A),
    ("temperature", ir::JOINT_MOTOR_TEMPERATURES, TEMPERATURE_C),
];

const TOOL_POSE: [&str; 6] = [
    "tool x", "tool y", "tool z", "tool θx", "tool θy", "tool θz",
];
const TOOL_TWIST: [&str; 6] = [
    "tool twist x",
    "tool twist y",
    "tool twist z",
    "tool twist θx",
    "tool twist θy",
    "tool twist θz",
];
const TOOL_WRENCH: [&str; 6] = [
    "tool force x",
    "tool force y",
    "tool force z",
    "tool torque x",
    "tool torque y",
    "tool torque z",
];

/// The bounds of a six-float tool block, in the ICD's order.
fn six(linear: Bounds, angular: Bounds) -> [Bounds; 6] {
    [linear, linear, linear, angular, angular, angular]
}

impl Telemetry {
    /// Every value out of its physical range (or not finite), in register order.
    pub fn insane_fields(&self) -> Vec<InsaneField> {
        let mut out = Vec::new();
        let mut check = |field, joint, register, value, bounds: Bounds| {
            if bounds.sane(value).is_none() {
                out.push(InsaneField {
                    field,
                    joint,
                    register,
                    value,
                });
            }
        };
        let arm = [
            ("arm current", ir::ARM_CURRENT, self.arm.current, CURRENT_A),
            ("arm voltage", ir::ARM_VOLTAGE, self.arm.voltage, VOLTAGE_V),
            (
                "CPU temperature",
                ir::ARM_CPU_TEMPERATURE,
                self.arm.cpu_temperature,
                TEMPERATURE_C,
            ),
            (
                "ambient temperature",
                ir::ARM_AMBIENT_TEMPERATURE,
                self.arm.ambient_temperature,
                TEMPERATURE_C,
            ),
        ];
        for (field, register, value, bounds) in arm {
            check(field, None, register, value, bounds);
        }
        for (field, block, bounds) in JOINT_FIELDS {
            for (j, joint) in self.joints.iter().enumerate() {
                let value = match field {
                    "position" => joint.position,
                    "speed" => joint.velocity,
                    "torque" => joint.torque,
                    "current" => joint.current,
                    _ => joint.temperature,
                };
                let number = j as u16 + 1;
                check(
                    field,
                    Some(number as u8),
                    ir::joint(block, number),
                    value,
                    bounds,
                );
            }
        }
        let blocks = [
            (
                TOOL_POSE,
                ir::TCP_POSE,
                self.tcp.pose.to_array(),
                six(TOOL_POSITION_M, TOOL_ORIENTATION_DEG),
            ),
            (
                TOOL_TWIST,
                ir::TCP_TWIST,
                self.tcp.twist.to_array(),
                six(TOOL_LINEAR_SPEED_M_S, TOOL_ANGULAR_SPEED_DEG_S),
            ),
            (
                TOOL_WRENCH,
                ir::TCP_WRENCH,
                self.tcp.wrench.to_array(),
                six(TOOL_FORCE_N, TOOL_TORQUE_NM),
            ),
        ];
        for (names, block, values, bounds) in blocks {
            for i in 0..6 {
                check(names[i], None, block + 2 * i as u16, values[i], bounds[i]);
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kortex::{Coded, RegisterImage, RobotState, Telemetry};

    fn sane() -> Telemetry {
        let mut t = Telemetry::decode(&RegisterImage::default());
        t.robot_state = Coded::Known(RobotState::Ready);
        t.arm.voltage = 24.0;
        for j in &mut t.joints {
            j.position = 180.0;
            j.temperature = 30.0;
        }
        t.tcp.pose.x = 0.45;
        t
    }

    #[test]
    fn a_sane_snapshot_has_no_insane_fields_and_values_near_the_limits_pass() {
        let mut t = sane();
        assert!(t.insane_fields().is_empty(), "{:?}", t.insane_fields());
        t.joints[0].position = 359.99;
        t.joints[1].velocity = 80.0;
        t.joints[6].torque = -39.0;
        t.tcp.twist.x = 0.5;
        t.tcp.twist.theta_z = -100.0;
        assert!(t.insane_fields().is_empty(), "{:?}", t.insane_fields());
    }

    #[test]
    fn nonsense_is_named_with_its_register() {
        let mut t = sane();
        t.joints[2].position = 1e9;
        t.joints[0].velocity = f32::NAN;
        t.tcp.twist.y = f32::INFINITY;
        t.arm.voltage = -1e30;
        let fields = t.insane_fields();
        let shown: Vec<String> = fields.iter().map(|f| f.to_string()).collect();
        assert_eq!(
            shown,
            [
                "arm voltage -1e30 (input registers 8-9)",
                "J3 position 1e9 (input registers 38-39)",
                "J1 speed NaN (input registers 48-49)",
                "tool twist y inf (input registers 118-119)",
            ]
        );
        assert_eq!(JOINT_ANGLE_DEG.sane(1e30), None);
        assert_eq!(JOINT_ANGLE_DEG.sane(-0.5), Some(-0.5));
        assert_eq!(TOOL_LINEAR_SPEED_M_S.sane(f32::NAN), None);
    }
}
