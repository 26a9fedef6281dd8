//! The Kinova Kortex Modbus ICD (`shared/icd/kinova-modbus-icd.md`): register map, decoding of
//! telemetry and encoding of commands. Pure: no IO.
//!
//! - [`registers`]: every address, by name.
//! - [`words`]: floats and UINT32 over two registers, low word first (CDAB).
//! - [`codes`], [`flags`]: the numbered values and flag bits, with names.
//! - [`image`], [`telemetry`]: the reads of one poll and the snapshot they decode to.
//! - [`commands`]: the writes of each command, refusing values that cannot be written.
//! - [`polar`]: polar pan as a twist computed from the live tool pose.
//! - [`stored_run`]: how far a stored action or sequence started by id has got.
//! - [`sanity`]: whether a reported value is physically possible (the panels' `?` and the
//!   console's motion gate).

pub mod arm_state;
pub mod cartesian;
pub mod codes;
pub mod commands;
pub mod flags;
pub mod gen3;
pub mod image;
pub mod polar;
pub mod registers;
pub mod sanity;
pub mod stored_run;
pub mod telemetry;
pub mod words;

pub use arm_state::{OurMove, abort_reason, at_rest, fault_reason};
pub use cartesian::{Axis, Pose, Twist, Wrench};
pub use codes::{
    ActionCommand, ActionStatus, CodeName, Coded, ControlCoil, MoveType, ReferenceFrame, RobotState,
};
pub use commands::{CommandError, StoredMotion, Write};
pub use flags::{Flag, FlagSet};
pub use image::{ImageError, PollPlan, ReadBlock, RegisterImage, SLOW_REFRESH};
pub use polar::{PolarPanError, PolarPanSettings, check_directions, polar_twist};
pub use registers::Table;
pub use sanity::InsaneField;
pub use stored_run::{Progress, Stored, StoredRun};
pub use telemetry::{ActionState, ArmHealth, JointState, SpeedLimits, Telemetry, ToolState};
