//! The Kinova Kortex Modbus ICD (`shared/icd/kinova-modbus-icd.md`): register map, decoding of
//! telemetry and encoding of commands. Pure: no IO.
//!
//! - [`registers`]: every address, by name.
//! - [`words`]: floats and UINT32 over two registers, low word first (CDAB).
//! - [`codes`], [`flags`]: the numbered values and flag bits, with names.
//! - [`image`], [`telemetry`]: the reads of one poll and the snapshot they decode to.
//! - [`commands`]: the writes of each command, refusing values that cannot be written.
//! - [`polar`]: polar pan as a twist computed from the live tool pose.
//! - [`motion_plausibility`]: whether a snapshot is one a Gen3 can report, before motion.

pub mod cartesian;
pub mod codes;
pub mod commands;
pub mod flags;
pub mod gen3;
pub mod image;
pub mod motion_plausibility;
pub mod polar;
pub mod registers;
pub mod telemetry;
pub mod words;

pub use cartesian::{Axis, Pose, Twist, Wrench};
pub use codes::{
    ActionCommand, ActionStatus, CodeName, Coded, ControlCoil, MoveType, ReferenceFrame, RobotState,
};
pub use commands::{CommandError, StoredMotion, Write};
pub use flags::{Flag, FlagSet};
pub use image::{ImageError, PollPlan, ReadBlock, RegisterImage, SLOW_REFRESH};
pub use motion_plausibility::implausible_for_motion;
pub use polar::{PolarPanError, PolarPanSettings, check_directions, polar_twist};
pub use registers::Table;
pub use telemetry::{ActionState, ArmHealth, JointState, SpeedLimits, Telemetry, ToolState};
