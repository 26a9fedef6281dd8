//! The Kinova Kortex Modbus ICD (`shared/icd/kinova-modbus-icd.md`), pure: [`registers`]
//! (addresses), [`two_registers`] (CDAB floats), [`codes`] and [`flags`] (named values), [`image`] and
//! [`telemetry`] (a poll's reads and snapshot), [`commands`] (writes), [`polar`] (pan as a twist),
//! [`stored_run`] (a stored run's progress), [`sanity`] (physically possible values).

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
pub mod two_registers;

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
