//! armjog's hardware companion ICD for Talos "Execute Hardware Operation" (0x0008 / 0x8008).
//!
//! The Talos ICD leaves the subcommand values and their payloads to a hardware-specific
//! companion ICD; `docs/hardware-icd.md` is armjog's, for a Kinova Gen3 7-joint arm, modelled on
//! Kinova's ActuatorCyclic service. This module is that document as code: the subcommand values,
//! the typed requests and replies, and their exact byte layouts. It is pure (no IO) and never
//! panics on input: every length and field is checked and reported as an [`HwError`].
//!
//! Only the inner `Payload` bytes live here. The Talos wrapper around them (Subcommand UINT16 and
//! RESERVED UINT32 in the request, Return Code UINT16 and Subcommand UINT16 in the reply) is the
//! frame/message layer's. All values are big-endian; physical values are IEEE-754 `f32`.

use std::fmt;
use std::ops::BitOr;

use serde::Serialize;

/// Joints of a Kinova Gen3 7-DOF arm; joints are numbered `1..=JOINT_COUNT` from the base.
pub const JOINT_COUNT: u8 = 7;
/// GET_ACTUATOR_FEEDBACK selector meaning "every joint".
pub const ALL_JOINTS: u8 = 0;
/// Bytes of one actuator feedback block (joint + 13 four-byte fields).
pub const FEEDBACK_BLOCK_LEN: usize = 53;
/// Bytes of a SEND_ACTUATOR_COMMAND request payload (joint + flags + 4 setpoints).
pub const ACTUATOR_COMMAND_LEN: usize = 21;
/// Bytes of a GET_ARM_STATE reply payload.
pub const ARM_STATE_LEN: usize = 98;

/// The subcommand values carried in the Talos "Subcommand Value" field (request and reply alike).
pub mod subcommand {
    /// Read the feedback of one actuator or of all of them.
    pub const GET_ACTUATOR_FEEDBACK: u16 = 0x0001;
    /// Send one command to one actuator; the reply carries its feedback (like ActuatorCyclic.Refresh).
    pub const SEND_ACTUATOR_COMMAND: u16 = 0x0002;
    /// Read the arm-level state, pose, twist and wrench.
    pub const GET_ARM_STATE: u16 = 0x0003;
    /// Bring every joint to velocity 0 and hold position.
    pub const STOP_ALL_JOINTS: u16 = 0x0004;
    /// Clear the major and minor fault flags of every actuator.
    pub const CLEAR_ALL_FAULTS: u16 = 0x0005;

    /// Every defined subcommand, ascending.
    pub const ALL: [u16; 5] = [
        GET_ACTUATOR_FEEDBACK,
        SEND_ACTUATOR_COMMAND,
        GET_ARM_STATE,
        STOP_ALL_JOINTS,
        CLEAR_ALL_FAULTS,
    ];

    /// snake_case name of a defined subcommand.
    pub fn name(value: u16) -> Option<&'static str> {
        match value {
            GET_ACTUATOR_FEEDBACK => Some("get_actuator_feedback"),
            SEND_ACTUATOR_COMMAND => Some("send_actuator_command"),
            GET_ARM_STATE => Some("get_arm_state"),
            STOP_ALL_JOINTS => Some("stop_all_joints"),
            CLEAR_ALL_FAULTS => Some("clear_all_faults"),
            _ => None,
        }
    }
}

/// "0x0002 (send_actuator_command)", for error messages.
fn subcommand_label(value: &u16) -> String {
    match subcommand::name(*value) {
        Some(name) => format!("0x{value:04X} ({name})"),
        None => format!("0x{value:04X}"),
    }
}

/// What was wrong with a hardware payload or with a value to be encoded.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum HwError {
    #[error("unknown hardware subcommand 0x{0:04X}")]
    UnknownSubcommand(u16),
    #[error("payload too short for subcommand {}: expected {expected} bytes, got {got}", subcommand_label(.subcommand))]
    TooShort {
        subcommand: u16,
        expected: usize,
        got: usize,
    },
    #[error("payload too long for subcommand {}: expected {expected} bytes, got {got}", subcommand_label(.subcommand))]
    TooLong {
        subcommand: u16,
        expected: usize,
        got: usize,
    },
    #[error("joint selector {0} out of range: expected 0 (all joints) or 1..=7")]
    SelectorOutOfRange(u8),
    #[error("joint {0} out of range: expected 1..=7")]
    JointOutOfRange(u8),
    #[error("actuator count {0} out of range: expected 0..=7")]
    CountOutOfRange(usize),
    #[error(
        "count mismatch for subcommand {}: count byte says {count} actuator blocks ({expected} bytes) but the payload has {got} bytes",
        subcommand_label(.subcommand)
    )]
    CountMismatch {
        subcommand: u16,
        count: u8,
        expected: usize,
        got: usize,
    },
    #[error(
        "actuator blocks out of order: joint {joint} follows joint {previous} (must be strictly ascending)"
    )]
    JointOrder { previous: u8, joint: u8 },
    #[error("non-finite value in field {field}")]
    NonFinite { field: &'static str },
    #[error("undefined bits 0x{bits:08X} set in field {field}")]
    UndefinedBits { field: &'static str, bits: u32 },
}

impl HwError {
    /// The Talos return code a server answers with when a request fails to decode:
    /// 0x0009 UNSUPPORTED_SUBCOMMAND for an unknown subcommand, 0x0002 MALFORMED_PAYLOAD otherwise.
    pub fn return_code(&self) -> u16 {
        match self {
            HwError::UnknownSubcommand(_) => 0x0009,
            _ => 0x0002,
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Flag words
// ---------------------------------------------------------------------------------------------

const BIT_LABELS: [&str; 32] = [
    "bit_0", "bit_1", "bit_2", "bit_3", "bit_4", "bit_5", "bit_6", "bit_7", "bit_8", "bit_9",
    "bit_10", "bit_11", "bit_12", "bit_13", "bit_14", "bit_15", "bit_16", "bit_17", "bit_18",
    "bit_19", "bit_20", "bit_21", "bit_22", "bit_23", "bit_24", "bit_25", "bit_26", "bit_27",
    "bit_28", "bit_29", "bit_30", "bit_31",
];

/// Names of the set bits of `word`, ascending; a bit without a name is reported as "bit_N".
fn bit_names(word: u32, name_of: impl Fn(u32) -> Option<&'static str>) -> Vec<&'static str> {
    BIT_LABELS
        .iter()
        .zip(0u32..)
        .filter(|(_, bit)| word & (1 << bit) != 0)
        .map(|(label, bit)| name_of(bit).unwrap_or(label))
        .collect()
}

/// A u32 flag word newtype: one constant per named bit, `names`, `contains`, `Display`.
macro_rules! flag_word {
    (
        $(#[$meta:meta])*
        $name:ident, zero = $zero:literal;
        $( $(#[$bit_meta:meta])* $konst:ident = bit $bit:literal, $label:literal; )*
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize)]
        #[serde(transparent)]
        pub struct $name(pub u32);

        impl $name {
            $( $(#[$bit_meta])* pub const $konst: $name = $name(1 << $bit); )*

            /// Every named bit, ascending, with its snake_case name.
            pub const NAMED: &'static [($name, &'static str)] = &[$(($name::$konst, $label),)*];
            /// Mask of every named bit.
            pub const DEFINED: u32 = 0 $(| (1 << $bit))*;
            /// What `Display` shows for a word with no bit set.
            pub const ZERO_NAME: &'static str = $zero;

            pub const fn bits(self) -> u32 {
                self.0
            }

            /// Whether every bit of `other` is set in `self`.
            pub const fn contains(self, other: $name) -> bool {
                self.0 & other.0 == other.0
            }

            /// The set bits that have no name.
            pub const fn undefined_bits(self) -> u32 {
                self.0 & !Self::DEFINED
            }

            /// snake_case names of the set bits, ascending; unnamed bits as "bit_N".
            pub fn names(&self) -> Vec<&'static str> {
                bit_names(self.0, |bit| match bit {
                    $($bit => Some($label),)*
                    _ => None,
                })
            }
        }

        impl BitOr for $name {
            type Output = $name;
            fn bitor(self, rhs: $name) -> $name {
                $name(self.0 | rhs.0)
            }
        }

        /// Names joined with '|', or the zero name when no bit is set.
        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                let names = self.names();
                if names.is_empty() {
                    f.write_str(Self::ZERO_NAME)
                } else {
                    f.write_str(&names.join("|"))
                }
            }
        }
    };
}

flag_word! {
    /// ActuatorCyclic CommandFlags (value 0 is NO_COMMAND). Bits 10-31 are undefined and SHALL be 0.
    CommandFlags, zero = "no_command";
    /// 0x1: servoing mode is enabled (the actuator tracks the setpoints).
    SERVO_ENABLE = bit 0, "servo_enable";
    /// 0x2: the brake is normally applied; 1 disables it.
    BRAKE_DISABLE = bit 1, "brake_disable";
    /// 0x4: clear the major fault flag.
    CLEAR_MAJOR_FAULT = bit 2, "clear_major_fault";
    /// 0x8: clear the minor fault flag.
    CLEAR_MINOR_FAULT = bit 3, "clear_minor_fault";
    /// 0x10: protective stop has been activated.
    PROTECTIVE_STOP = bit 4, "protective_stop";
    /// 0x20: force a brake release.
    FORCE_BRAKE_RELEASE = bit 5, "force_brake_release";
    /// 0x40: ignore the other command flag bits.
    IGNORE = bit 6, "ignore";
    /// 0x80: use the gain set of the joint admittance mode.
    LOW_GAINS = bit 7, "low_gains";
    /// 0x100: light LED 0 (interface module button 0).
    LED_0 = bit 8, "led_0";
    /// 0x200: light LED 1 (interface module button 1).
    LED_1 = bit 9, "led_1";
}

impl CommandFlags {
    /// The all-zero word.
    pub const NO_COMMAND: CommandFlags = CommandFlags(0);
}

flag_word! {
    /// ActuatorCyclic StatusFlags (value 0 is UNKNOWN_STATUS). Bits 0-3 and 28-31 are undefined;
    /// the bits Kinova documents as "Reserved" are named RESERVED_N after their bit number.
    StatusFlags, zero = "unknown_status";
    /// 0x10: the actuator is in a stable state.
    STABILIZED = bit 4, "stabilized";
    /// 0x20: the position sensor is indexed.
    MOTOR_INDEXED = bit 5, "motor_indexed";
    /// 0x40: the position sensor is indexing.
    MOTOR_INDEXING = bit 6, "motor_indexing";
    /// 0x80: reserved (Kinova enumerator JOINT_INDEXED).
    RESERVED_7 = bit 7, "reserved_7";
    /// 0x100: reserved (Kinova enumerator JOINT_INDEXING).
    RESERVED_8 = bit 8, "reserved_8";
    /// 0x200: reserved (Kinova enumerator HIGH_PRECISION).
    RESERVED_9 = bit 9, "reserved_9";
    /// 0x400: the actuator is braking.
    BRAKING = bit 10, "braking";
    /// 0x800: the actuator is in servoing mode.
    SERVOING = bit 11, "servoing";
    /// 0x1000: a major fault has occurred.
    MAJOR_FAULT = bit 12, "major_fault";
    /// 0x2000: a minor fault has occurred.
    MINOR_FAULT = bit 13, "minor_fault";
    /// 0x4000: the torque sensor is calibrated.
    CALIBRATED_TORQUE = bit 14, "calibrated_torque";
    /// 0x8000: the magnetic sensor is calibrated.
    CALIBRATED_MAG_SENSOR = bit 15, "calibrated_mag_sensor";
    /// 0x10000: the zero position calibration has been performed.
    CALIBRATED_ZERO = bit 16, "calibrated_zero";
    /// 0x20000: reserved (Kinova enumerator GPIO_0).
    RESERVED_17 = bit 17, "reserved_17";
    /// 0x40000: reserved (Kinova enumerator GPIO_1).
    RESERVED_18 = bit 18, "reserved_18";
    /// 0x80000: reserved (Kinova enumerator CS_QUASI_STATIC_CONTACT).
    RESERVED_19 = bit 19, "reserved_19";
    /// 0x100000: reserved (Kinova enumerator CS_TRANSIENT_CONTACT).
    RESERVED_20 = bit 20, "reserved_20";
    /// 0x200000: reserved (Kinova enumerator VFD_HALL_SYNC).
    RESERVED_21 = bit 21, "reserved_21";
    /// 0x400000: reserved (Kinova enumerator VFD_INDEXED).
    RESERVED_22 = bit 22, "reserved_22";
    /// 0x800000: reserved (Kinova enumerator DRIVE_BOARD_READY).
    RESERVED_23 = bit 23, "reserved_23";
    /// 0x1000000: the current sensor is calibrated.
    CALIBRATED_CURRENT = bit 24, "calibrated_current";
    /// 0x2000000: the motor is calibrated.
    CALIBRATED_MOTOR = bit 25, "calibrated_motor";
    /// 0x4000000: interface module button 0 is pressed.
    SW0_ACTIVE = bit 26, "sw0_active";
    /// 0x8000000: interface module button 1 is pressed.
    SW1_ACTIVE = bit 27, "sw1_active";
}

impl StatusFlags {
    /// The all-zero word.
    pub const UNKNOWN_STATUS: StatusFlags = StatusFlags(0);
}

flag_word! {
    /// Arm fault or warning word, same bit numbering as Kinova Modbus input registers 2-3 (faults)
    /// and 4-5 (warnings); bit N is discrete input 32+N (faults) or 64+N (warnings).
    ArmFlags, zero = "none";
    FIRMWARE_UPDATE_FAILURE = bit 0, "firmware_update_failure";
    MAX_AMBIENT_TEMPERATURE = bit 2, "max_ambient_temperature";
    MAX_CORE_TEMPERATURE = bit 3, "max_core_temperature";
    JOINT_FAULT = bit 4, "joint_fault";
    ABOVE_MAX_DOF = bit 8, "above_max_dof";
    UNABLE_TO_REACH_POSE = bit 10, "unable_to_reach_pose";
    JOINT_DETECTION_ERROR = bit 11, "joint_detection_error";
    NETWORK_INIT_ERROR = bit 12, "network_init_error";
    MAX_CURRENT = bit 13, "max_current";
    MAX_VOLTAGE = bit 14, "max_voltage";
    MIN_VOLTAGE = bit 15, "min_voltage";
    EMERGENCY_STOP = bit 23, "emergency_stop";
    EMERGENCY_LINE = bit 24, "emergency_line";
    INRUSH_CURRENT_LIMITER_FAULT = bit 25, "inrush_current_limiter_fault";
    /// Discrete input 58 only ("not implemented yet" upstream).
    NVRAM_CORRUPTED = bit 26, "nvram_corrupted";
    INCOMPATIBLE_FIRMWARE = bit 27, "incompatible_firmware";
    POWER_ON_SELF_TEST_FAILURE = bit 28, "power_on_self_test_failure";
    DISCRETE_INPUT_STUCK = bit 29, "discrete_input_stuck";
    ILLEGAL_POSITION = bit 30, "illegal_position";
}

/// Arm state, same values as Kinova Modbus input register 0. Unknown values are kept raw.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize)]
#[serde(transparent)]
pub struct RobotState(pub u16);

impl RobotState {
    pub const UNSPECIFIED: RobotState = RobotState(0);
    pub const BASE_INIT_NOT_COMPLETED: RobotState = RobotState(1);
    pub const BASE_INIT_SUCCEEDED: RobotState = RobotState(2);
    pub const INITIALISING: RobotState = RobotState(3);
    pub const IN_FAULT: RobotState = RobotState(4);
    pub const MAINTENANCE: RobotState = RobotState(5);
    pub const LOW_LEVEL_SERVOING: RobotState = RobotState(6);
    pub const READY: RobotState = RobotState(7);
    pub const CONTROLLED_BY_SEQUENCE: RobotState = RobotState(8);
    pub const CONTROLLED_MANUALLY: RobotState = RobotState(9);

    /// snake_case name of a defined state.
    pub fn name(self) -> Option<&'static str> {
        const NAMES: [&str; 10] = [
            "unspecified",
            "base_init_not_completed",
            "base_init_succeeded",
            "initialising",
            "in_fault",
            "maintenance",
            "low_level_servoing",
            "ready",
            "controlled_by_sequence",
            "controlled_manually",
        ];
        NAMES.get(usize::from(self.0)).copied()
    }
}

impl fmt::Display for RobotState {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.name() {
            Some(name) => f.write_str(name),
            None => write!(f, "state_{}", self.0),
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Payload structures
// ---------------------------------------------------------------------------------------------

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

    /// Clear both fault flags without moving: servoing off, setpoints at rest.
    pub fn clear_faults(position_deg: f32) -> Self {
        ActuatorCommand {
            flags: CommandFlags::CLEAR_MAJOR_FAULT | CommandFlags::CLEAR_MINOR_FAULT,
            position_deg,
            velocity_deg_s: 0.0,
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
        check_finite("position_deg", self.position_deg)?;
        check_finite("velocity_deg_s", self.velocity_deg_s)?;
        check_finite("torque_nm", self.torque_nm)?;
        check_finite("current_a", self.current_a)
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

    fn write(&self, out: &mut Vec<u8>) {
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

    fn read(r: &mut Reader<'_>) -> Result<Self, HwError> {
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

    fn write(&self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.robot_state.0.to_be_bytes());
        out.extend_from_slice(&self.faults.0.to_be_bytes());
        out.extend_from_slice(&self.warnings.0.to_be_bytes());
        for value in self.floats() {
            out.extend_from_slice(&value.to_be_bytes());
        }
    }

    fn read(r: &mut Reader<'_>) -> Result<Self, HwError> {
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

// ---------------------------------------------------------------------------------------------
// Requests and replies
// ---------------------------------------------------------------------------------------------

/// A hardware operation request: the Talos 0x0008 Subcommand Value and Payload.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum HwRequest {
    /// `selector`: 0 ([`ALL_JOINTS`]) or a joint 1..=7.
    GetActuatorFeedback {
        selector: u8,
    },
    /// `joint`: 1..=7.
    SendActuatorCommand {
        joint: u8,
        command: ActuatorCommand,
    },
    GetArmState,
    StopAllJoints,
    ClearAllFaults,
}

impl HwRequest {
    pub fn subcommand(&self) -> u16 {
        match self {
            HwRequest::GetActuatorFeedback { .. } => subcommand::GET_ACTUATOR_FEEDBACK,
            HwRequest::SendActuatorCommand { .. } => subcommand::SEND_ACTUATOR_COMMAND,
            HwRequest::GetArmState => subcommand::GET_ARM_STATE,
            HwRequest::StopAllJoints => subcommand::STOP_ALL_JOINTS,
            HwRequest::ClearAllFaults => subcommand::CLEAR_ALL_FAULTS,
        }
    }

    /// Every field in range: selector 0..=7, joint 1..=7, defined flag bits, finite floats.
    pub fn validate(&self) -> Result<(), HwError> {
        match self {
            HwRequest::GetActuatorFeedback { selector } => check_selector(*selector),
            HwRequest::SendActuatorCommand { joint, command } => {
                check_joint(*joint)?;
                command.validate()
            }
            HwRequest::GetArmState | HwRequest::StopAllJoints | HwRequest::ClearAllFaults => Ok(()),
        }
    }

    /// The inner Payload bytes, after [`HwRequest::validate`].
    pub fn encode_payload(&self) -> Result<Vec<u8>, HwError> {
        self.validate()?;
        let mut out = Vec::new();
        match self {
            HwRequest::GetActuatorFeedback { selector } => out.push(*selector),
            HwRequest::SendActuatorCommand { joint, command } => {
                out.push(*joint);
                out.extend_from_slice(&command.flags.0.to_be_bytes());
                for value in [
                    command.position_deg,
                    command.velocity_deg_s,
                    command.torque_nm,
                    command.current_a,
                ] {
                    out.extend_from_slice(&value.to_be_bytes());
                }
            }
            HwRequest::GetArmState | HwRequest::StopAllJoints | HwRequest::ClearAllFaults => {}
        }
        Ok(out)
    }

    /// Parses and validates the inner Payload of a request with this subcommand.
    pub fn decode(subcommand: u16, payload: &[u8]) -> Result<HwRequest, HwError> {
        use subcommand::*;
        match subcommand {
            GET_ACTUATOR_FEEDBACK => {
                let selector = Reader::exact(subcommand, payload, 1)?.u8()?;
                check_selector(selector)?;
                Ok(HwRequest::GetActuatorFeedback { selector })
            }
            SEND_ACTUATOR_COMMAND => {
                let mut r = Reader::exact(subcommand, payload, ACTUATOR_COMMAND_LEN)?;
                let joint = r.u8()?;
                check_joint(joint)?;
                let flags = CommandFlags(r.u32()?);
                let command = ActuatorCommand {
                    flags,
                    position_deg: r.f32("position_deg")?,
                    velocity_deg_s: r.f32("velocity_deg_s")?,
                    torque_nm: r.f32("torque_nm")?,
                    current_a: r.f32("current_a")?,
                };
                command.validate()?;
                Ok(HwRequest::SendActuatorCommand { joint, command })
            }
            GET_ARM_STATE => Reader::exact(subcommand, payload, 0).map(|_| HwRequest::GetArmState),
            STOP_ALL_JOINTS => {
                Reader::exact(subcommand, payload, 0).map(|_| HwRequest::StopAllJoints)
            }
            CLEAR_ALL_FAULTS => {
                Reader::exact(subcommand, payload, 0).map(|_| HwRequest::ClearAllFaults)
            }
            other => Err(HwError::UnknownSubcommand(other)),
        }
    }
}

/// A hardware operation reply payload, as sent with return code 0x0000 OK. With any other
/// return code the reply Payload is empty and is not decoded with this type.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum HwReply {
    /// 0..=7 blocks, joints strictly ascending.
    GetActuatorFeedback {
        actuators: Vec<ActuatorFeedback>,
    },
    /// The commanded actuator's feedback after the command was applied.
    SendActuatorCommand {
        feedback: ActuatorFeedback,
    },
    GetArmState {
        state: ArmState,
    },
    StopAllJoints,
    ClearAllFaults,
}

impl HwReply {
    pub fn subcommand(&self) -> u16 {
        match self {
            HwReply::GetActuatorFeedback { .. } => subcommand::GET_ACTUATOR_FEEDBACK,
            HwReply::SendActuatorCommand { .. } => subcommand::SEND_ACTUATOR_COMMAND,
            HwReply::GetArmState { .. } => subcommand::GET_ARM_STATE,
            HwReply::StopAllJoints => subcommand::STOP_ALL_JOINTS,
            HwReply::ClearAllFaults => subcommand::CLEAR_ALL_FAULTS,
        }
    }

    /// What [`HwReply::decode`] checks: at most 7 blocks, joints 1..=7 strictly ascending,
    /// finite floats. A server calls this before [`HwReply::encode_payload`].
    pub fn validate(&self) -> Result<(), HwError> {
        match self {
            HwReply::GetActuatorFeedback { actuators } => {
                if actuators.len() > usize::from(JOINT_COUNT) {
                    return Err(HwError::CountOutOfRange(actuators.len()));
                }
                let mut previous = 0;
                for feedback in actuators {
                    feedback.validate()?;
                    check_order(previous, feedback.joint)?;
                    previous = feedback.joint;
                }
                Ok(())
            }
            HwReply::SendActuatorCommand { feedback } => feedback.validate(),
            HwReply::GetArmState { state } => state.validate(),
            HwReply::StopAllJoints | HwReply::ClearAllFaults => Ok(()),
        }
    }

    /// The inner Payload bytes. Writes what it is given (at most 255 blocks); values that
    /// [`HwReply::validate`] rejects produce bytes [`HwReply::decode`] rejects.
    pub fn encode_payload(&self) -> Vec<u8> {
        let mut out = Vec::new();
        match self {
            HwReply::GetActuatorFeedback { actuators } => {
                let count = u8::try_from(actuators.len()).unwrap_or(u8::MAX);
                out.push(count);
                for feedback in actuators.iter().take(usize::from(count)) {
                    feedback.write(&mut out);
                }
            }
            HwReply::SendActuatorCommand { feedback } => feedback.write(&mut out),
            HwReply::GetArmState { state } => state.write(&mut out),
            HwReply::StopAllJoints | HwReply::ClearAllFaults => {}
        }
        out
    }

    /// Parses and validates the inner Payload of an OK reply with this subcommand.
    pub fn decode(subcommand: u16, payload: &[u8]) -> Result<HwReply, HwError> {
        use subcommand::*;
        match subcommand {
            GET_ACTUATOR_FEEDBACK => {
                let Some((&count, _)) = payload.split_first() else {
                    return Err(HwError::TooShort {
                        subcommand,
                        expected: 1,
                        got: 0,
                    });
                };
                if count > JOINT_COUNT {
                    return Err(HwError::CountOutOfRange(usize::from(count)));
                }
                let expected = 1 + usize::from(count) * FEEDBACK_BLOCK_LEN;
                if payload.len() != expected {
                    return Err(HwError::CountMismatch {
                        subcommand,
                        count,
                        expected,
                        got: payload.len(),
                    });
                }
                let mut r = Reader::exact(subcommand, payload, expected)?;
                r.u8()?;
                let mut actuators = Vec::with_capacity(usize::from(count));
                let mut previous = 0;
                for _ in 0..count {
                    let feedback = ActuatorFeedback::read(&mut r)?;
                    check_order(previous, feedback.joint)?;
                    previous = feedback.joint;
                    actuators.push(feedback);
                }
                Ok(HwReply::GetActuatorFeedback { actuators })
            }
            SEND_ACTUATOR_COMMAND => {
                let mut r = Reader::exact(subcommand, payload, FEEDBACK_BLOCK_LEN)?;
                let feedback = ActuatorFeedback::read(&mut r)?;
                Ok(HwReply::SendActuatorCommand { feedback })
            }
            GET_ARM_STATE => {
                let mut r = Reader::exact(subcommand, payload, ARM_STATE_LEN)?;
                let state = ArmState::read(&mut r)?;
                Ok(HwReply::GetArmState { state })
            }
            STOP_ALL_JOINTS => {
                Reader::exact(subcommand, payload, 0).map(|_| HwReply::StopAllJoints)
            }
            CLEAR_ALL_FAULTS => {
                Reader::exact(subcommand, payload, 0).map(|_| HwReply::ClearAllFaults)
            }
            other => Err(HwError::UnknownSubcommand(other)),
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

fn check_joint(joint: u8) -> Result<(), HwError> {
    if (1..=JOINT_COUNT).contains(&joint) {
        Ok(())
    } else {
        Err(HwError::JointOutOfRange(joint))
    }
}

fn check_selector(selector: u8) -> Result<(), HwError> {
    if selector <= JOINT_COUNT {
        Ok(())
    } else {
        Err(HwError::SelectorOutOfRange(selector))
    }
}

fn check_order(previous: u8, joint: u8) -> Result<(), HwError> {
    if joint > previous {
        Ok(())
    } else {
        Err(HwError::JointOrder { previous, joint })
    }
}

fn check_finite(field: &'static str, value: f32) -> Result<(), HwError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(HwError::NonFinite { field })
    }
}

/// Big-endian reader over a payload whose exact length was checked by [`Reader::exact`].
struct Reader<'a> {
    rest: &'a [u8],
    subcommand: u16,
    len: usize,
}

impl<'a> Reader<'a> {
    /// A reader over `payload`, or TooShort/TooLong if it is not exactly `expected` bytes.
    fn exact(subcommand: u16, payload: &'a [u8], expected: usize) -> Result<Self, HwError> {
        let got = payload.len();
        if got < expected {
            Err(HwError::TooShort {
                subcommand,
                expected,
                got,
            })
        } else if got > expected {
            Err(HwError::TooLong {
                subcommand,
                expected,
                got,
            })
        } else {
            Ok(Reader {
                rest: payload,
                subcommand,
                len: got,
            })
        }
    }

    fn take<const N: usize>(&mut self) -> Result<[u8; N], HwError> {
        match self.rest.split_first_chunk::<N>() {
            Some((head, rest)) => {
                self.rest = rest;
                Ok(*head)
            }
            // Unreachable after `exact`, but reported rather than assumed.
            None => Err(HwError::TooShort {
                subcommand: self.subcommand,
                expected: self.len - self.rest.len() + N,
                got: self.len,
            }),
        }
    }

    fn u8(&mut self) -> Result<u8, HwError> {
        self.take::<1>().map(|[b]| b)
    }

    fn u16(&mut self) -> Result<u16, HwError> {
        self.take().map(u16::from_be_bytes)
    }

    fn u32(&mut self) -> Result<u32, HwError> {
        self.take().map(u32::from_be_bytes)
    }

    /// A finite big-endian f32.
    fn f32(&mut self, field: &'static str) -> Result<f32, HwError> {
        let value = self.take().map(f32::from_be_bytes)?;
        check_finite(field, value)?;
        Ok(value)
    }

    /// `N` finite f32s, named by the next `N` entries of `names`.
    fn f32s<const N: usize>(
        &mut self,
        names: &mut impl Iterator<Item = &'static str>,
    ) -> Result<[f32; N], HwError> {
        let mut out = [0f32; N];
        for slot in &mut out {
            *slot = self.f32(names.next().unwrap_or("arm_state"))?;
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Bytes from hand-written hex ("02 00000001 ..."); whitespace is ignored.
    fn hex(text: &str) -> Vec<u8> {
        let digits: String = text.chars().filter(|c| !c.is_whitespace()).collect();
        assert!(
            digits.len().is_multiple_of(2),
            "odd hex digit count in {text:?}"
        );
        (0..digits.len())
            .step_by(2)
            .map(|i| u8::from_str_radix(&digits[i..i + 2], 16).unwrap())
            .collect()
    }

    // Hand-computed IEEE-754 big-endian values used below:
    //   0.125 3E000000   0.25 3E800000   0.5 3F000000   1.0 3F800000   1.5 3FC00000
    //   10.0 41200000   24.0 41C00000   25.0 41C80000   30.0 41F00000   40.0 42200000
    //   45.0 42340000   50.0 42480000   90.0 42B40000   180.0 43340000
    //   -0.125 BE000000 -1.0 BF800000   -2.5 C0200000   -9.5 C1180000
    //   NaN 7FC00000    +inf 7F800000   -inf FF800000

    /// Joint 2 in servoing: the doc's worked reply block.
    const BLOCK_J2: &str = "02 00000830 0000000C 42B40000 C0200000 3F800000 3F000000
                            41C00000 41F00000 42200000 00000000 00000000 00000000 00000000";
    /// Joint 7 braking with a major fault and non-zero banks.
    const BLOCK_J7: &str = "07 00001400 000001F4 43340000 00000000 BF800000 3E800000
                            41C00000 42480000 42340000 00000002 80000000 00010000 00000001";

    fn feedback_j2() -> ActuatorFeedback {
        ActuatorFeedback {
            joint: 2,
            status: StatusFlags(0x0000_0830),
            jitter_us: 12,
            position_deg: 90.0,
            velocity_deg_s: -2.5,
            torque_nm: 1.0,
            current_a: 0.5,
            voltage_v: 24.0,
            motor_temp_c: 30.0,
            core_temp_c: 40.0,
            fault_bank_a: 0,
            fault_bank_b: 0,
            warning_bank_a: 0,
            warning_bank_b: 0,
        }
    }

    fn feedback_j7() -> ActuatorFeedback {
        ActuatorFeedback {
            joint: 7,
            status: StatusFlags::MAJOR_FAULT | StatusFlags::BRAKING,
            jitter_us: 500,
            position_deg: 180.0,
            velocity_deg_s: 0.0,
            torque_nm: -1.0,
            current_a: 0.25,
            voltage_v: 24.0,
            motor_temp_c: 50.0,
            core_temp_c: 45.0,
            fault_bank_a: 2,
            fault_bank_b: 0x8000_0000,
            warning_bank_a: 0x0001_0000,
            warning_bank_b: 1,
        }
    }

    const ARM_STATE_HEX: &str = "0007 00800000 00000400
        3FC00000 41C00000 42200000 41C80000
        3F000000 00000000 3E800000  42B40000 00000000 43340000
        3E000000 BE000000 00000000  00000000 00000000 41200000
        00000000 00000000 C1180000  00000000 00000000 3F800000";

    fn arm_state() -> ArmState {
        ArmState {
            robot_state: RobotState::READY,
            faults: ArmFlags::EMERGENCY_STOP,
            warnings: ArmFlags::UNABLE_TO_REACH_POSE,
            current_a: 1.5,
            voltage_v: 24.0,
            cpu_temp_c: 40.0,
            ambient_temp_c: 25.0,
            tcp_position_m: [0.5, 0.0, 0.25],
            tcp_orientation_deg: [90.0, 0.0, 180.0],
            linear_velocity_m_s: [0.125, -0.125, 0.0],
            angular_velocity_deg_s: [0.0, 0.0, 10.0],
            force_n: [0.0, 0.0, -9.5],
            torque_nm: [0.0, 0.0, 1.0],
        }
    }

    fn jog_j2() -> HwRequest {
        HwRequest::SendActuatorCommand {
            joint: 2,
            command: ActuatorCommand::jog(90.0, -2.5),
        }
    }

    /// (subcommand, request, hand-written payload)
    fn request_vectors() -> Vec<(u16, HwRequest, Vec<u8>)> {
        vec![
            (
                0x0001,
                HwRequest::GetActuatorFeedback { selector: 0 },
                hex("00"),
            ),
            (
                0x0001,
                HwRequest::GetActuatorFeedback { selector: 7 },
                hex("07"),
            ),
            (
                0x0002,
                jog_j2(),
                hex("02 00000001 42B40000 C0200000 00000000 00000000"),
            ),
            (
                0x0002,
                HwRequest::SendActuatorCommand {
                    joint: 4,
                    command: ActuatorCommand::clear_faults(-2.5),
                },
                hex("04 0000000C C0200000 00000000 00000000 00000000"),
            ),
            (
                0x0002,
                HwRequest::SendActuatorCommand {
                    joint: 7,
                    command: ActuatorCommand {
                        flags: CommandFlags(0x0000_0301),
                        position_deg: 180.0,
                        velocity_deg_s: 10.0,
                        torque_nm: -9.5,
                        current_a: 1.5,
                    },
                },
                hex("07 00000301 43340000 41200000 C1180000 3FC00000"),
            ),
            (0x0003, HwRequest::GetArmState, vec![]),
            (0x0004, HwRequest::StopAllJoints, vec![]),
            (0x0005, HwRequest::ClearAllFaults, vec![]),
        ]
    }

    /// (subcommand, reply, hand-written payload)
    fn reply_vectors() -> Vec<(u16, HwReply, Vec<u8>)> {
        let mut j1 = feedback_j2();
        j1.joint = 1;
        vec![
            (
                0x0001,
                HwReply::GetActuatorFeedback { actuators: vec![] },
                hex("00"),
            ),
            (
                0x0001,
                HwReply::GetActuatorFeedback {
                    actuators: vec![feedback_j2()],
                },
                hex(&format!("01 {BLOCK_J2}")),
            ),
            (
                0x0001,
                HwReply::GetActuatorFeedback {
                    actuators: vec![j1, feedback_j7()],
                },
                hex(&format!("02 01{} {BLOCK_J7}", &BLOCK_J2.trim()[2..])),
            ),
            (
                0x0002,
                HwReply::SendActuatorCommand {
                    feedback: feedback_j2(),
                },
                hex(BLOCK_J2),
            ),
            (
                0x0003,
                HwReply::GetArmState { state: arm_state() },
                hex(ARM_STATE_HEX),
            ),
            (0x0004, HwReply::StopAllJoints, vec![]),
            (0x0005, HwReply::ClearAllFaults, vec![]),
        ]
    }

    #[test]
    fn subcommand_values_and_names() {
        assert_eq!(subcommand::GET_ACTUATOR_FEEDBACK, 0x0001);
        assert_eq!(subcommand::SEND_ACTUATOR_COMMAND, 0x0002);
        assert_eq!(subcommand::GET_ARM_STATE, 0x0003);
        assert_eq!(subcommand::STOP_ALL_JOINTS, 0x0004);
        assert_eq!(subcommand::CLEAR_ALL_FAULTS, 0x0005);
        assert_eq!(subcommand::name(0x0003), Some("get_arm_state"));
        assert_eq!(subcommand::name(0x0000), None);
        assert_eq!(subcommand::name(0x0006), None);
    }

    #[test]
    fn layout_lengths_match_the_doc() {
        assert_eq!(hex(BLOCK_J2).len(), FEEDBACK_BLOCK_LEN);
        assert_eq!(FEEDBACK_BLOCK_LEN, 53);
        assert_eq!(ACTUATOR_COMMAND_LEN, 21);
        assert_eq!(hex(ARM_STATE_HEX).len(), ARM_STATE_LEN);
        assert_eq!(ARM_STATE_LEN, 98);
    }

    #[test]
    fn requests_encode_and_decode_to_known_bytes() {
        for (sub, request, bytes) in request_vectors() {
            assert_eq!(request.subcommand(), sub, "{request:?}");
            assert_eq!(request.encode_payload().unwrap(), bytes, "{request:?}");
            assert_eq!(HwRequest::decode(sub, &bytes).unwrap(), request);
        }
    }

    #[test]
    fn replies_encode_and_decode_to_known_bytes() {
        for (sub, reply, bytes) in reply_vectors() {
            assert_eq!(reply.subcommand(), sub, "{reply:?}");
            reply.validate().unwrap();
            assert_eq!(reply.encode_payload(), bytes, "{reply:?}");
            assert_eq!(HwReply::decode(sub, &bytes).unwrap(), reply);
        }
    }

    fn short(subcommand: u16, expected: usize, got: usize) -> HwError {
        HwError::TooShort {
            subcommand,
            expected,
            got,
        }
    }

    fn long(subcommand: u16, expected: usize, got: usize) -> HwError {
        HwError::TooLong {
            subcommand,
            expected,
            got,
        }
    }

    fn mismatch(count: u8, expected: usize, got: usize) -> HwError {
        let subcommand = subcommand::GET_ACTUATOR_FEEDBACK;
        HwError::CountMismatch {
            subcommand,
            count,
            expected,
            got,
        }
    }

    #[test]
    fn every_payload_one_byte_short_or_long_is_rejected() {
        for (sub, _, bytes) in request_vectors() {
            let n = bytes.len();
            let longer = [bytes.as_slice(), &[0]].concat();
            assert_eq!(HwRequest::decode(sub, &longer), Err(long(sub, n, n + 1)));
            if n > 0 {
                assert_eq!(
                    HwRequest::decode(sub, &bytes[..n - 1]),
                    Err(short(sub, n, n - 1))
                );
            }
        }
        for (sub, _, bytes) in reply_vectors() {
            let n = bytes.len();
            let longer = [bytes.as_slice(), &[0]].concat();
            let shorter = &bytes[..n.saturating_sub(1)];
            if sub == subcommand::GET_ACTUATOR_FEEDBACK {
                // The count byte fixes the length: extra or missing bytes are a count mismatch.
                let count = bytes[0];
                assert_eq!(
                    HwReply::decode(sub, &longer),
                    Err(mismatch(count, n, n + 1))
                );
                let expected = if n == 1 {
                    short(sub, 1, 0)
                } else {
                    mismatch(count, n, n - 1)
                };
                assert_eq!(HwReply::decode(sub, shorter), Err(expected));
            } else {
                assert_eq!(HwReply::decode(sub, &longer), Err(long(sub, n, n + 1)));
                if n > 0 {
                    assert_eq!(HwReply::decode(sub, shorter), Err(short(sub, n, n - 1)));
                }
            }
        }
    }

    #[test]
    fn error_messages_name_the_problem() {
        let e = HwRequest::decode(0x0002, &hex("02 00000001")).unwrap_err();
        assert_eq!(
            e.to_string(),
            "payload too short for subcommand 0x0002 (send_actuator_command): expected 21 bytes, got 5"
        );
        assert_eq!(
            HwRequest::decode(0x0006, &[]).unwrap_err().to_string(),
            "unknown hardware subcommand 0x0006"
        );
        let e = HwReply::decode(0x0001, &hex("01 02")).unwrap_err();
        assert_eq!(
            e.to_string(),
            "count mismatch for subcommand 0x0001 (get_actuator_feedback): count byte says 1 actuator blocks (54 bytes) but the payload has 2 bytes"
        );
    }

    #[test]
    fn unknown_subcommands_are_rejected_both_ways() {
        for sub in [0x0000, 0x0006, 0x0008, 0x8001, 0xFFFF] {
            assert_eq!(
                HwRequest::decode(sub, &[]),
                Err(HwError::UnknownSubcommand(sub))
            );
            assert_eq!(
                HwReply::decode(sub, &[]),
                Err(HwError::UnknownSubcommand(sub))
            );
        }
        assert_eq!(HwError::UnknownSubcommand(6).return_code(), 0x0009);
        assert_eq!(HwError::JointOutOfRange(0).return_code(), 0x0002);
    }

    #[test]
    fn joints_and_selectors_out_of_range() {
        assert_eq!(
            HwRequest::decode(1, &hex("08")),
            Err(HwError::SelectorOutOfRange(8))
        );
        assert_eq!(
            HwRequest::decode(1, &hex("FF")),
            Err(HwError::SelectorOutOfRange(255))
        );
        let bad = HwRequest::GetActuatorFeedback { selector: 8 };
        assert_eq!(bad.encode_payload(), Err(HwError::SelectorOutOfRange(8)));
        for joint in [0u8, 8, 0xFF] {
            let mut bytes = hex("02 00000001 42B40000 C0200000 00000000 00000000");
            bytes[0] = joint;
            assert_eq!(
                HwRequest::decode(2, &bytes),
                Err(HwError::JointOutOfRange(joint))
            );
            let request = HwRequest::SendActuatorCommand {
                joint,
                command: ActuatorCommand::jog(0.0, 1.0),
            };
            assert_eq!(
                request.encode_payload(),
                Err(HwError::JointOutOfRange(joint))
            );
            let mut block = hex(BLOCK_J2);
            block[0] = joint;
            assert_eq!(
                HwReply::decode(2, &block),
                Err(HwError::JointOutOfRange(joint))
            );
        }
    }

    #[test]
    fn non_finite_values_are_rejected_with_their_field() {
        let cases = [
            (
                "02 00000001 7FC00000 00000000 00000000 00000000",
                "position_deg",
            ),
            (
                "02 00000001 00000000 7F800000 00000000 00000000",
                "velocity_deg_s",
            ),
            (
                "02 00000001 00000000 00000000 FF800000 00000000",
                "torque_nm",
            ),
            (
                "02 00000001 00000000 00000000 00000000 7FC00000",
                "current_a",
            ),
        ];
        for (bytes, field) in cases {
            assert_eq!(
                HwRequest::decode(2, &hex(bytes)),
                Err(HwError::NonFinite { field })
            );
        }
        let request = HwRequest::SendActuatorCommand {
            joint: 1,
            command: ActuatorCommand::jog(0.0, f32::NAN),
        };
        assert_eq!(
            request.encode_payload(),
            Err(HwError::NonFinite {
                field: "velocity_deg_s"
            })
        );
        // Ambient temperature is the 4th float of the arm state (offset 10 + 12 = 22).
        let mut arm = hex(ARM_STATE_HEX);
        arm[22..26].copy_from_slice(&hex("7F800000"));
        assert_eq!(
            HwReply::decode(3, &arm),
            Err(HwError::NonFinite {
                field: "ambient_temp_c"
            })
        );
        // Torque z is the last float.
        let mut arm = hex(ARM_STATE_HEX);
        arm[94..98].copy_from_slice(&hex("FFC00000"));
        assert_eq!(
            HwReply::decode(3, &arm),
            Err(HwError::NonFinite {
                field: "torque_nm.z"
            })
        );
        // Core temperature of a feedback block is at offset 33.
        let mut block = hex(BLOCK_J2);
        block[33..37].copy_from_slice(&hex("7FC00000"));
        assert_eq!(
            HwReply::decode(2, &block),
            Err(HwError::NonFinite {
                field: "core_temp_c"
            })
        );
        let mut state = arm_state();
        state.force_n[1] = f32::INFINITY;
        assert_eq!(
            HwReply::GetArmState { state }.validate(),
            Err(HwError::NonFinite { field: "force_n.y" })
        );
    }

    #[test]
    fn undefined_command_bits_are_rejected() {
        let bytes = hex("01 00000401 00000000 00000000 00000000 00000000");
        assert_eq!(
            HwRequest::decode(2, &bytes),
            Err(HwError::UndefinedBits {
                field: "command_flags",
                bits: 0x400
            })
        );
        let request = HwRequest::SendActuatorCommand {
            joint: 1,
            command: ActuatorCommand {
                flags: CommandFlags(0x8000_0000),
                ..ActuatorCommand::jog(0.0, 0.0)
            },
        };
        assert_eq!(
            request.encode_payload(),
            Err(HwError::UndefinedBits {
                field: "command_flags",
                bits: 0x8000_0000
            })
        );
    }

    #[test]
    fn feedback_list_count_and_order() {
        assert_eq!(HwReply::decode(1, &[]), Err(short(1, 1, 0)));
        assert_eq!(
            HwReply::decode(1, &hex("08")),
            Err(HwError::CountOutOfRange(8))
        );
        let two = hex(&format!("02 {BLOCK_J2}"));
        assert_eq!(HwReply::decode(1, &two), Err(mismatch(2, 107, 54)));
        let reversed = hex(&format!("02 {BLOCK_J7} {BLOCK_J2}"));
        assert_eq!(
            HwReply::decode(1, &reversed),
            Err(HwError::JointOrder {
                previous: 7,
                joint: 2
            })
        );
        let duplicate = hex(&format!("02 {BLOCK_J2} {BLOCK_J2}"));
        assert_eq!(
            HwReply::decode(1, &duplicate),
            Err(HwError::JointOrder {
                previous: 2,
                joint: 2
            })
        );
        let eight = HwReply::GetActuatorFeedback {
            actuators: vec![feedback_j2(); 8],
        };
        assert_eq!(eight.validate(), Err(HwError::CountOutOfRange(8)));
        let unordered = HwReply::GetActuatorFeedback {
            actuators: vec![feedback_j7(), feedback_j2()],
        };
        assert_eq!(
            unordered.validate(),
            Err(HwError::JointOrder {
                previous: 7,
                joint: 2
            })
        );
    }

    /// Every bit value of kinova-actuator-cyclic.txt, typed in by hand.
    const COMMAND_BITS: [(u32, &str); 10] = [
        (0x1, "servo_enable"),
        (0x2, "brake_disable"),
        (0x4, "clear_major_fault"),
        (0x8, "clear_minor_fault"),
        (0x10, "protective_stop"),
        (0x20, "force_brake_release"),
        (0x40, "ignore"),
        (0x80, "low_gains"),
        (0x100, "led_0"),
        (0x200, "led_1"),
    ];
    const STATUS_BITS: [(u32, &str); 24] = [
        (0x10, "stabilized"),
        (0x20, "motor_indexed"),
        (0x40, "motor_indexing"),
        (0x80, "reserved_7"),
        (0x100, "reserved_8"),
        (0x200, "reserved_9"),
        (0x400, "braking"),
        (0x800, "servoing"),
        (0x1000, "major_fault"),
        (0x2000, "minor_fault"),
        (0x4000, "calibrated_torque"),
        (0x8000, "calibrated_mag_sensor"),
        (0x10000, "calibrated_zero"),
        (0x20000, "reserved_17"),
        (0x40000, "reserved_18"),
        (0x80000, "reserved_19"),
        (0x100000, "reserved_20"),
        (0x200000, "reserved_21"),
        (0x400000, "reserved_22"),
        (0x800000, "reserved_23"),
        (0x1000000, "calibrated_current"),
        (0x2000000, "calibrated_motor"),
        (0x4000000, "sw0_active"),
        (0x8000000, "sw1_active"),
    ];

    #[test]
    fn every_command_flag_decodes_to_its_name() {
        for (value, name) in COMMAND_BITS {
            let flags = CommandFlags(value);
            assert_eq!(flags.names(), vec![name]);
            assert_eq!(flags.to_string(), name);
            assert_eq!(flags.undefined_bits(), 0);
        }
        let named: Vec<(u32, &str)> = CommandFlags::NAMED.iter().map(|(f, n)| (f.0, *n)).collect();
        assert_eq!(named, COMMAND_BITS);
        assert_eq!(CommandFlags::DEFINED, 0x3FF);
        assert_eq!(CommandFlags::SERVO_ENABLE.0, 0x1);
        assert_eq!(CommandFlags::CLEAR_MAJOR_FAULT.0, 0x4);
        assert_eq!(CommandFlags::CLEAR_MINOR_FAULT.0, 0x8);
        assert_eq!(CommandFlags::LED_1.0, 0x200);
    }

    #[test]
    fn every_status_flag_decodes_to_its_name() {
        for (value, name) in STATUS_BITS {
            assert_eq!(StatusFlags(value).names(), vec![name]);
            assert_eq!(StatusFlags(value).to_string(), name);
        }
        let named: Vec<(u32, &str)> = StatusFlags::NAMED.iter().map(|(f, n)| (f.0, *n)).collect();
        assert_eq!(named, STATUS_BITS);
        assert_eq!(StatusFlags::DEFINED, 0x0FFF_FFF0);
        assert_eq!(StatusFlags::RESERVED_7.0, 0x80);
        assert_eq!(StatusFlags::MAJOR_FAULT.0, 0x1000);
        assert_eq!(StatusFlags::SW1_ACTIVE.0, 0x800_0000);
    }

    #[test]
    fn flag_words_combine_and_show_unknown_bits() {
        assert_eq!(CommandFlags::NO_COMMAND.names(), Vec::<&str>::new());
        assert_eq!(CommandFlags::NO_COMMAND.to_string(), "no_command");
        assert_eq!(StatusFlags::UNKNOWN_STATUS.to_string(), "unknown_status");
        assert_eq!(ArmFlags(0).to_string(), "none");
        let clear = CommandFlags(0x0C);
        assert_eq!(
            clear,
            CommandFlags::CLEAR_MAJOR_FAULT | CommandFlags::CLEAR_MINOR_FAULT
        );
        assert_eq!(clear.to_string(), "clear_major_fault|clear_minor_fault");
        assert!(clear.contains(CommandFlags::CLEAR_MINOR_FAULT));
        assert!(!clear.contains(CommandFlags::SERVO_ENABLE | CommandFlags::CLEAR_MINOR_FAULT));
        assert_eq!(
            CommandFlags(0x1000_0401).names(),
            vec!["servo_enable", "bit_10", "bit_28"]
        );
        assert_eq!(CommandFlags(0x1000_0401).undefined_bits(), 0x1000_0400);
        let status = StatusFlags(0x8000_0831);
        assert_eq!(
            status.to_string(),
            "bit_0|stabilized|motor_indexed|servoing|bit_31"
        );
        assert!(status.contains(StatusFlags::SERVOING));
        assert_eq!(
            ArmFlags(0x0080_0401).names(),
            vec![
                "firmware_update_failure",
                "unable_to_reach_pose",
                "emergency_stop"
            ]
        );
        assert_eq!(ArmFlags(0x8000_0002).to_string(), "bit_1|bit_31");
        assert_eq!(ArmFlags::ILLEGAL_POSITION.0, 0x4000_0000);
    }

    #[test]
    fn robot_states_are_named() {
        let names = [
            "unspecified",
            "base_init_not_completed",
            "base_init_succeeded",
            "initialising",
            "in_fault",
            "maintenance",
            "low_level_servoing",
            "ready",
            "controlled_by_sequence",
            "controlled_manually",
        ];
        for (value, name) in (0u16..).zip(names) {
            assert_eq!(RobotState(value).to_string(), name);
        }
        assert_eq!(RobotState::IN_FAULT, RobotState(4));
        assert_eq!(RobotState::CONTROLLED_MANUALLY, RobotState(9));
        assert_eq!(RobotState(10).to_string(), "state_10");
        assert_eq!(RobotState(10).name(), None);
    }

    #[test]
    fn structures_serialize_to_json_with_raw_flag_words() {
        let json = serde_json::to_value(feedback_j2()).unwrap();
        assert_eq!(json["joint"], 2);
        assert_eq!(json["status"], 0x830);
        assert_eq!(json["position_deg"], 90.0);
        let json = serde_json::to_value(arm_state()).unwrap();
        assert_eq!(json["robot_state"], 7);
        assert_eq!(json["faults"], 0x0080_0000);
        assert_eq!(json["force_n"], serde_json::json!([0.0, 0.0, -9.5]));
    }

    fn finite() -> impl Strategy<Value = f32> {
        prop_oneof![
            -1.0e6f32..1.0e6f32,
            Just(0.0),
            Just(-0.0),
            Just(f32::MAX),
            Just(f32::MIN)
        ]
    }

    fn feedback(joint: u8) -> impl Strategy<Value = ActuatorFeedback> {
        (any::<[u32; 6]>(), proptest::array::uniform7(finite())).prop_map(move |(w, f)| {
            ActuatorFeedback {
                joint,
                status: StatusFlags(w[0]),
                jitter_us: w[1],
                position_deg: f[0],
                velocity_deg_s: f[1],
                torque_nm: f[2],
                current_a: f[3],
                voltage_v: f[4],
                motor_temp_c: f[5],
                core_temp_c: f[6],
                fault_bank_a: w[2],
                fault_bank_b: w[3],
                warning_bank_a: w[4],
                warning_bank_b: w[5],
            }
        })
    }

    fn any_request() -> impl Strategy<Value = HwRequest> {
        let command = (0u32..=0x3FF, proptest::array::uniform4(finite())).prop_map(|(b, f)| {
            ActuatorCommand {
                flags: CommandFlags(b),
                position_deg: f[0],
                velocity_deg_s: f[1],
                torque_nm: f[2],
                current_a: f[3],
            }
        });
        prop_oneof![
            (0u8..=7).prop_map(|selector| HwRequest::GetActuatorFeedback { selector }),
            (1u8..=7, command)
                .prop_map(|(joint, command)| HwRequest::SendActuatorCommand { joint, command }),
            Just(HwRequest::GetArmState),
            Just(HwRequest::StopAllJoints),
            Just(HwRequest::ClearAllFaults),
        ]
    }

    fn any_reply() -> impl Strategy<Value = HwReply> {
        let list = proptest::sample::subsequence((1u8..=7).collect::<Vec<_>>(), 0..=7)
            .prop_flat_map(|joints| joints.into_iter().map(feedback).collect::<Vec<_>>());
        let state = (
            any::<(u16, u32, u32)>(),
            proptest::collection::vec(finite(), 22),
        )
            .prop_map(|((s, f, w), v)| {
                let xyz = |i: usize| [v[i], v[i + 1], v[i + 2]];
                ArmState {
                    robot_state: RobotState(s),
                    faults: ArmFlags(f),
                    warnings: ArmFlags(w),
                    current_a: v[0],
                    voltage_v: v[1],
                    cpu_temp_c: v[2],
                    ambient_temp_c: v[3],
                    tcp_position_m: xyz(4),
                    tcp_orientation_deg: xyz(7),
                    linear_velocity_m_s: xyz(10),
                    angular_velocity_deg_s: xyz(13),
                    force_n: xyz(16),
                    torque_nm: xyz(19),
                }
            });
        prop_oneof![
            list.prop_map(|actuators| HwReply::GetActuatorFeedback { actuators }),
            (1u8..=7)
                .prop_flat_map(feedback)
                .prop_map(|feedback| HwReply::SendActuatorCommand { feedback }),
            state.prop_map(|state| HwReply::GetArmState { state }),
            Just(HwReply::StopAllJoints),
            Just(HwReply::ClearAllFaults),
        ]
    }

    proptest! {
        #[test]
        fn every_request_round_trips(request in any_request()) {
            let bytes = request.encode_payload().unwrap();
            prop_assert_eq!(HwRequest::decode(request.subcommand(), &bytes).unwrap(), request);
        }

        #[test]
        fn every_reply_round_trips(reply in any_reply()) {
            prop_assert!(reply.validate().is_ok());
            let bytes = reply.encode_payload();
            prop_assert_eq!(HwReply::decode(reply.subcommand(), &bytes).unwrap(), reply);
        }

        #[test]
        fn decoding_arbitrary_bytes_never_panics(
            sub in 0u16..=7,
            bytes in proptest::collection::vec(any::<u8>(), 0..400),
        ) {
            if let Ok(request) = HwRequest::decode(sub, &bytes) {
                prop_assert_eq!(request.encode_payload().unwrap(), bytes.clone());
            }
            if let Ok(reply) = HwReply::decode(sub, &bytes) {
                prop_assert!(reply.validate().is_ok());
                prop_assert_eq!(reply.encode_payload(), bytes);
            }
        }
    }
}
