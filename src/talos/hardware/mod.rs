//! armjog's hardware companion ICD for Talos "Execute Hardware Operation" (0x0008 / 0x8008):
//! `docs/hardware-icd.md` as code, for a Kinova Gen3 7-joint arm (modelled on Kinova's
//! ActuatorCyclic). Only the inner `Payload` bytes live here; the wrapper is the frame layer's.
//! Big-endian, physical values `f32`; pure, and every length and field is checked ([`HwError`]).
//! `flags`, `payload`, `message` and `reader` are re-exported here.

mod flags;
mod message;
mod payload;
mod reader;

pub use flags::{ArmFlags, CommandFlags, RobotState, StatusFlags};
pub use message::{HwReply, HwRequest};
pub use payload::{ActuatorCommand, ActuatorFeedback, ArmState};

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
    macro_rules! subcommands {
        ($($(#[$doc:meta])* $konst:ident = $value:literal, $name:literal;)*) => {
            $($(#[$doc])* pub const $konst: u16 = $value;)*

            /// Every defined subcommand, ascending.
            pub const ALL: [u16; 5] = [$($konst,)*];

            /// snake_case name of a defined subcommand.
            pub fn name(value: u16) -> Option<&'static str> {
                match value {
                    $($konst => Some($name),)*
                    _ => None,
                }
            }
        };
    }

    subcommands! {
        /// Read the feedback of one actuator or of all of them.
        GET_ACTUATOR_FEEDBACK = 0x0001, "get_actuator_feedback";
        /// Send one command to one actuator; the reply carries its feedback (like ActuatorCyclic.Refresh).
        SEND_ACTUATOR_COMMAND = 0x0002, "send_actuator_command";
        /// Read the arm-level state, pose, twist and wrench.
        GET_ARM_STATE = 0x0003, "get_arm_state";
        /// Bring every joint to velocity 0 and hold position.
        STOP_ALL_JOINTS = 0x0004, "stop_all_joints";
        /// Clear the major and minor fault flags of every actuator.
        CLEAR_ALL_FAULTS = 0x0005, "clear_all_faults";
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
