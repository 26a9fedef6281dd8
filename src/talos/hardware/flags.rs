//! The u32 flag-word newtypes, their macro, and [`RobotState`].

use std::fmt;
use std::ops::BitOr;

use serde::Serialize;

use crate::kortex::{CodeName, Flag, FlagSet};

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

        /// Names joined with '|', or the zero name (`zero`) when no bit is set.
        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                let names = self.names();
                if names.is_empty() {
                    f.write_str($zero)
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

/// Arm fault or warning word, same bit numbering as Kinova Modbus input registers 2-3 (faults)
/// and 4-5 (warnings); bit N is discrete input 32+N (faults) or 64+N (warnings). Its names are
/// the Modbus register map's ([`crate::kortex::Flag`]), so both links name a flag alike.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize)]
#[serde(transparent)]
pub struct ArmFlags(pub u32);

impl ArmFlags {
    /// snake_case names of the set bits, ascending; unnamed bits as `unknown_bit_N`.
    pub fn names(&self) -> Vec<String> {
        FlagSet::from_bits(self.0).names()
    }
}

impl From<Flag> for ArmFlags {
    fn from(flag: Flag) -> ArmFlags {
        ArmFlags(flag.bit())
    }
}

impl fmt::Display for ArmFlags {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names = self.names();
        if names.is_empty() {
            f.write_str("none")
        } else {
            f.write_str(&names.join("|"))
        }
    }
}

/// Arm state, same values as Kinova Modbus input register 0 (named by
/// [`crate::kortex::RobotState`]). Unknown values are kept raw.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize)]
#[serde(transparent)]
pub struct RobotState(pub u16);

impl RobotState {
    pub const IN_FAULT: RobotState = RobotState(4);
    pub const READY: RobotState = RobotState(7);
    pub const CONTROLLED_MANUALLY: RobotState = RobotState(9);

    /// snake_case name of a defined state, as the Modbus register map names it.
    pub fn name(self) -> Option<&'static str> {
        crate::kortex::RobotState::from_code(self.0).map(CodeName::key)
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
