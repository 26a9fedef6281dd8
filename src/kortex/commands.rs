//! The register and coil writes of every command, as pure functions; values that cannot be written
//! are refused here. Register writes are FC16, coil writes FC05, sent in order, each awaiting its
//! reply.

use std::fmt;

use super::cartesian::{Pose, Twist};
use super::codes::{ActionCommand, CodeName, ControlCoil, MoveType, ReferenceFrame};
use super::registers::holding_register as hr;
use super::two_registers;

/// Twist hard limit of the arm, linear: m/s (Gen3 user guide).
pub const MAX_LINEAR_SPEED: f32 = 0.5;
/// Twist hard limit of the arm, angular: deg/s.
pub const MAX_ANGULAR_SPEED: f32 = 100.0;
/// No Kinova arm reaches beyond this (a Gen3: 0.902 m): a larger coordinate is likely mm.
pub const MAX_REACH: f32 = 1.5;
/// Orientation targets beyond a full turn are refused as typos.
pub const MAX_ANGLE: f32 = 360.0;
/// Stored action or sequence ids: register 201 is a uint16 and 0 means none. The one range for the
/// form, the command line, the profiles and [`start_stored`].
pub const STORED_IDS: std::ops::RangeInclusive<u16> = 1..=u16::MAX;

/// One write request.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Write {
    /// Write Multiple Registers (FC16) from `addr`.
    Registers { addr: u16, values: Vec<u16> },
    /// Write Single Coil (FC05).
    Coil { addr: u16, value: bool },
}

impl Write {
    fn register(addr: u16, value: u16) -> Write {
        Write::Registers {
            addr,
            values: vec![value],
        }
    }

    fn command(command: ActionCommand) -> Write {
        Write::register(hr::COMMAND, command.code())
    }

    pub fn function_code(&self) -> u8 {
        match self {
            Write::Registers { .. } => 0x10,
            Write::Coil { .. } => 0x05,
        }
    }
}

impl fmt::Display for Write {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Write::Registers { addr, values } => {
                let last = usize::from(*addr) + values.len().saturating_sub(1);
                let shown: Vec<String> = values.iter().map(|v| format!("0x{v:04X}")).collect();
                write!(
                    f,
                    "write holding registers {addr}-{last} = [{}] (FC16)",
                    shown.join(", ")
                )
            }
            Write::Coil { addr, value } => {
                let state = if *value { "on" } else { "off" };
                write!(f, "write coil {addr} {state} (FC05)")
            }
        }
    }
}

/// Why a command was refused before anything was sent.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CommandError {
    #[error("{what} is {value}: only finite numbers can be written")]
    NotFinite { what: &'static str, value: f32 },
    #[error("linear speed {speed} m/s is over the arm's twist limit of {limit} m/s")]
    LinearTooFast { speed: f32, limit: f32 },
    #[error("angular speed {speed} deg/s is over the arm's twist limit of {limit} deg/s")]
    AngularTooFast { speed: f32, limit: f32 },
    #[error("{what} {value} must be above 0 and at most {limit}")]
    SpeedLimitOutOfRange {
        what: &'static str,
        value: f32,
        limit: f32,
    },
    #[error("{what} {value} m is farther than any Kinova arm reaches ({limit} m); metres expected")]
    OutOfReach {
        what: &'static str,
        value: f32,
        limit: f32,
    },
    #[error("{what} {value} deg is more than a full turn")]
    AngleOutOfRange { what: &'static str, value: f32 },
    #[error("reference frame {0} is not one of 1 (mixed), 2 (tool), 3 (base)")]
    UnknownReferenceFrame(u16),
    #[error("{0} is outside {first} to {last}", first = STORED_IDS.start(), last = STORED_IDS.end())]
    StoredIdOutOfRange(i128),
}

/// `number` as a stored action's or sequence's id, if it is in [`STORED_IDS`].
pub fn stored_id(number: i128) -> Result<u16, CommandError> {
    u16::try_from(number)
        .ok()
        .filter(|id| STORED_IDS.contains(id))
        .ok_or(CommandError::StoredIdOutOfRange(number))
}

/// The reference frame numbered `code` in register 203, or a refusal.
pub fn reference_frame(code: u16) -> Result<ReferenceFrame, CommandError> {
    ReferenceFrame::from_code(code).ok_or(CommandError::UnknownReferenceFrame(code))
}

const AXES: [&str; 6] = ["x", "y", "z", "theta_x", "theta_y", "theta_z"];

fn finite(values: [f32; 6]) -> Result<(), CommandError> {
    match values.iter().zip(AXES).find(|(v, _)| !v.is_finite()) {
        Some((value, what)) => Err(CommandError::NotFinite {
            what,
            value: *value,
        }),
        None => Ok(()),
    }
}

/// Checks a twist against the arm's hard limits (on the speed, not per axis).
pub fn check_twist(twist: Twist) -> Result<(), CommandError> {
    finite(twist.to_array())?;
    let (linear, angular) = (twist.linear_speed(), twist.angular_speed());
    if linear > MAX_LINEAR_SPEED {
        return Err(CommandError::LinearTooFast {
            speed: linear,
            limit: MAX_LINEAR_SPEED,
        });
    }
    if angular > MAX_ANGULAR_SPEED {
        return Err(CommandError::AngularTooFast {
            speed: angular,
            limit: MAX_ANGULAR_SPEED,
        });
    }
    Ok(())
}

/// The shared start sequence of a cartesian trajectory or a twist: Kinova's own example.
fn start_cartesian(move_type: MoveType, frame: ReferenceFrame, target: [f32; 6]) -> Vec<Write> {
    let mut block = vec![move_type.code(), frame.code()];
    block.extend(two_registers::f32s_to_words(&target));
    vec![
        Write::command(ActionCommand::NoAction),
        Write::Registers {
            addr: hr::COMMAND_MOVE_TYPE,
            values: block,
        },
        Write::command(ActionCommand::Start),
    ]
}

/// Starts a twist, or replaces the running one (the ICD does not say whether 204-215 are read
/// while a twist runs, so an update is a full restart with the new values):
///
/// 1. FC16 200 <- `[0]` (no action: the start below is then a fresh command)
/// 2. FC16 202-215 <- `[3 (twist), frame, x, y, z m/s, theta x, y, z deg/s]`, floats CDAB
/// 3. FC16 200 <- `[1]` (start)
pub fn twist(frame: ReferenceFrame, twist: Twist) -> Result<Vec<Write>, CommandError> {
    check_twist(twist)?;
    Ok(start_cartesian(MoveType::Twist, frame, twist.to_array()))
}

/// Stops the running twist, action or trajectory:
///
/// 1. FC16 200 <- `[2]` (action stop)
pub fn stop() -> Vec<Write> {
    vec![Write::command(ActionCommand::Stop)]
}

/// Moves the tool to a pose (move type 2, cartesian trajectory):
///
/// 1. FC16 200 <- `[0]` (no action)
/// 2. FC16 202-215 <- `[2 (cartesian trajectory), frame, x, y, z m, theta x, y, z deg]`, CDAB
/// 3. FC16 200 <- `[1]` (start)
pub fn go_to_pose(frame: ReferenceFrame, pose: Pose) -> Result<Vec<Write>, CommandError> {
    let values = pose.to_array();
    finite(values)?;
    for (value, what) in values.iter().zip(AXES) {
        let angle = what.starts_with("theta");
        if angle && value.abs() > MAX_ANGLE {
            return Err(CommandError::AngleOutOfRange {
                what,
                value: *value,
            });
        }
        if !angle && value.abs() > MAX_REACH {
            return Err(CommandError::OutOfReach {
                what,
                value: *value,
                limit: MAX_REACH,
            });
        }
    }
    Ok(start_cartesian(
        MoveType::CartesianTrajectory,
        frame,
        values,
    ))
}

/// What a stored motion started by id is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StoredMotion {
    Action,
    Sequence,
}

/// Starts a stored action (Home, Retract, ...) or sequence by id:
///
/// 1. FC16 200 <- `[0]` (no action)
/// 2. FC16 201-202 <- `[id, 0 (action) or 1 (sequence)]`
/// 3. FC16 200 <- `[1]` (start)
///
/// An id outside [`STORED_IDS`] is refused.
pub fn start_stored(id: u16, motion: StoredMotion) -> Result<Vec<Write>, CommandError> {
    let id = stored_id(id.into())?;
    Ok(vec![
        Write::command(ActionCommand::NoAction),
        Write::Registers {
            addr: hr::COMMAND_ID,
            values: vec![id, motion.move_type().code()],
        },
        Write::command(ActionCommand::Start),
    ])
}

/// Sets the desired cartesian speed limits (linear m/s, angular deg/s), each above zero and at
/// most the twist hard limit:
///
/// 1. FC16 216-219 <- `[linear, angular]`, CDAB
pub fn speed_limits(linear: f32, angular: f32) -> Result<Vec<Write>, CommandError> {
    for (what, value, limit) in [
        ("linear speed limit", linear, MAX_LINEAR_SPEED),
        ("angular speed limit", angular, MAX_ANGULAR_SPEED),
    ] {
        if !value.is_finite() {
            return Err(CommandError::NotFinite { what, value });
        }
        if value <= 0.0 || value > limit {
            return Err(CommandError::SpeedLimitOutOfRange { what, value, limit });
        }
    }
    Ok(vec![Write::Registers {
        addr: hr::DESIRED_LINEAR_SPEED_LIMIT,
        values: two_registers::f32s_to_words(&[linear, angular]),
    }])
}

/// Quick stop, abort or fault reset. The ICD does not say whether a coil acts on its rising
/// edge or while on, so it is pulsed: each command is then a fresh edge and nothing stays
/// latched.
///
/// 1. FC05 coil N <- on
/// 2. FC05 coil N <- off
pub fn pulse(coil: ControlCoil) -> Vec<Write> {
    let addr = coil.code();
    vec![
        Write::Coil { addr, value: true },
        Write::Coil { addr, value: false },
    ]
}
