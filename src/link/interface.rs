//! The arm interface: [`ArmCommand`]s in, [`ArmEvent`]s out, whatever the wire.

use std::time::Duration;

use crate::kortex::{Pose, ReferenceFrame, Stored, Telemetry, Write};

pub use super::command_kind::{CommandClass, CommandKind};
pub use super::failure::ArmError;

/// A continuous motion (a jog): what the held keys ask for. Directions are -1, 0 or 1.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JogMotion {
    Cartesian {
        x: i8,
        y: i8,
        z: i8,
    },
    Polar {
        azimuth: i8,
        altitude: i8,
    },
    /// Joint 1..=7.
    Joint {
        joint: u8,
        direction: i8,
    },
    /// Turn the tool about its point in the selected frame (Modbus only: no such Talos jog).
    Orientation {
        rx: i8,
        ry: i8,
        rz: i8,
    },
}

/// A discrete step move.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepMove {
    /// Tenths of millimetres.
    Cartesian { dx: i32, dy: i32, dz: i32 },
    /// Whole degrees.
    Polar { azimuth: i32, altitude: i32 },
}

impl StepMove {
    /// The pose a step moves to. Polar steps turn the position about base Z (extrinsic XYZ: a
    /// change of theta z) and change its elevation about the base origin, keeping the distance.
    pub fn target(self, pose: Pose) -> Pose {
        match self {
            StepMove::Cartesian { dx, dy, dz } => Pose {
                x: pose.x + dx as f32 / 10_000.0,
                y: pose.y + dy as f32 / 10_000.0,
                z: pose.z + dz as f32 / 10_000.0,
                ..pose
            },
            StepMove::Polar { azimuth, altitude } => {
                let (x, y, z) = (f64::from(pose.x), f64::from(pose.y), f64::from(pose.z));
                let horizontal = x.hypot(y);
                let distance = horizontal.hypot(z);
                let azimuth_now = y.atan2(x) + f64::from(azimuth).to_radians();
                let elevation = (z.atan2(horizontal) + f64::from(altitude).to_radians())
                    .clamp(-89f64.to_radians(), 89f64.to_radians());
                let h = distance * elevation.cos();
                Pose {
                    x: (h * azimuth_now.cos()) as f32,
                    y: (h * azimuth_now.sin()) as f32,
                    z: (distance * elevation.sin()) as f32,
                    theta_z: pose.theta_z + azimuth as f32,
                    ..pose
                }
            }
        }
    }
}

/// Everything the console asks of an arm.
#[derive(Debug, Clone, PartialEq)]
pub enum ArmCommand {
    /// Start, change or refresh continuous motion.
    Jog(JogMotion),
    /// Stop every motion: continuous, discrete, home, go-to.
    Stop,
    Step(StepMove),
    /// Cartesian move to a stored pose (named positions kept by the console, over Modbus).
    MoveToPose(Pose),
    Home,
    /// Percent of the maximum jog speed, 1-100.
    SetSpeed(u8),
    /// The fence's share of the speed in force, per mille (1000: none taken): motion near a face
    /// goes slower without the technician's speed changing. Kept until the next one.
    FenceSpeed(u16),
    SetFrame(ReferenceFrame),
    QuickStop,
    FaultReset,
    SavePosition {
        name: String,
        anchor: bool,
        parent: Option<String>,
    },
    DeletePosition {
        name: String,
    },
    GoToPosition {
        name: String,
    },
    /// Tenths of degrees and tenths of millimetres, as the Talos ICD has them.
    SetPolarPosition {
        name: String,
        delta: i32,
        azimuth: i32,
        radius: i32,
    },
    /// Tenths of millimetres.
    SetCartesianPosition {
        name: String,
        x: i32,
        y: i32,
        z: i32,
    },
    /// Read a position's coordinates, both ways.
    GetPosition {
        name: String,
    },
    /// Start a stored action or sequence by id (Modbus only), capped as home is.
    StartStored(Stored),
}

impl ArmCommand {
    /// What this command does to the arm ([`CommandKind::class`]).
    pub fn class(&self) -> CommandClass {
        self.kind().class()
    }

    /// `class() == Motion`: whether this command may set the arm moving.
    pub fn starts_motion(&self) -> bool {
        matches!(self.class(), CommandClass::Motion { .. })
    }

    /// `class() == Stop`. Stops are never queued behind anything.
    pub fn is_stop(&self) -> bool {
        self.class() == CommandClass::Stop
    }

    /// Which kind of command this is: what a failure of it names.
    pub fn kind(&self) -> CommandKind {
        match self {
            ArmCommand::Jog(_) => CommandKind::Jog,
            ArmCommand::Stop => CommandKind::Stop,
            ArmCommand::Step(_) => CommandKind::Step,
            ArmCommand::MoveToPose(_) => CommandKind::MoveToPose,
            ArmCommand::Home => CommandKind::Home,
            ArmCommand::SetSpeed(_) => CommandKind::SetSpeed,
            ArmCommand::FenceSpeed(_) => CommandKind::FenceSpeed,
            ArmCommand::SetFrame(_) => CommandKind::SetFrame,
            ArmCommand::QuickStop => CommandKind::QuickStop,
            ArmCommand::FaultReset => CommandKind::FaultReset,
            ArmCommand::SavePosition { .. } => CommandKind::SavePosition,
            ArmCommand::DeletePosition { .. } => CommandKind::DeletePosition,
            ArmCommand::GoToPosition { .. } => CommandKind::GoToPosition,
            ArmCommand::SetPolarPosition { .. } => CommandKind::SetPolarPosition,
            ArmCommand::SetCartesianPosition { .. } => CommandKind::SetCartesianPosition,
            ArmCommand::GetPosition { .. } => CommandKind::GetPosition,
            ArmCommand::StartStored(_) => CommandKind::StartStored,
        }
    }
}

/// A named position's coordinates, as read back.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PositionCoordinates {
    /// Tenths of millimetres.
    pub cartesian: Option<[i32; 3]>,
    /// Delta (elevation), azimuth in tenths of degrees; radius in tenths of millimetres.
    pub polar: Option<[i32; 3]>,
}

/// The state of the link(s) to the arm.
#[derive(Debug, Clone, PartialEq)]
pub enum LinkStatus {
    Connecting,
    Up {
        /// e.g. "talos 127.0.0.1:61616 (icd, crc16), operator 1.0".
        description: String,
    },
    Down {
        reason: String,
    },
}

/// Which telemetry the panels can have.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TelemetrySource {
    Modbus,
    /// The Talos hardware operation (GET_ARM_STATE and actuator feedback).
    TalosHardware,
    /// The ack dialect carries no data back.
    None,
}

/// One line of the command log: a request and its answer.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LogEntry {
    pub id: Option<u32>,
    /// A periodic telemetry poll: consecutive polls with the same outcome share one line.
    pub poll: bool,
    /// How many exchanges the line stands for (polls), at least 1.
    pub count: u32,
    pub name: String,
    /// "OK", a return code or exception name, or an error.
    pub outcome: String,
    pub ok: bool,
    pub latency: Option<Duration>,
    /// What went over the wire, raw: the log panel formats it.
    pub traffic: Traffic,
}

impl LogEntry {
    /// One exchange's line with `outcome`, not ok unless set (a failure, or a request not sent).
    pub fn new(name: &str, outcome: String) -> LogEntry {
        let (count, name) = (1, name.to_string());
        LogEntry {
            count,
            name,
            outcome,
            ..LogEntry::default()
        }
    }
}

/// The raw exchange behind a log line.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum Traffic {
    /// Nothing went out, or what did is not known (a request that was never answered).
    #[default]
    None,
    /// A Talos request frame and, if one came, the reply frame, whole.
    Talos {
        request: Vec<u8>,
        reply: Option<Vec<u8>>,
    },
    /// The Modbus writes a command made, in order.
    Modbus(Vec<Write>),
}

/// The stop guard's state ([`crate::link::guard`]); sent only when a guard is required.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum GuardStatus {
    /// Started, not yet ready (over Modbus: not yet connected): motion is refused.
    Starting,
    /// Watching the console, able to stop the arm.
    Ready { pid: u32 },
    /// Not running, or cut off from the arm: motion is refused and any is stopped.
    Down { reason: String },
}

impl GuardStatus {
    pub fn is_ready(&self) -> bool {
        matches!(self, GuardStatus::Ready { .. })
    }
}

/// What the driver tells the console.
#[derive(Debug, Clone, PartialEq)]
pub enum ArmEvent {
    Status(LinkStatus),
    Telemetry(Box<Telemetry>),
    TelemetrySource(TelemetrySource),
    /// Round trip of the latest request, for the link panel.
    Latency(Duration),
    /// The speed in force, percent.
    Speed(u8),
    /// Something the driver did on its own that the message line must say.
    Notice(String),
    Log(LogEntry),
    /// A command failed: shown on the status line.
    Failed {
        command: CommandKind,
        error: ArmError,
    },
    /// A position's coordinates, answering `GetPosition`.
    Position {
        name: String,
        coordinates: PositionCoordinates,
    },
    /// The operator does not know this name (so the console can mark it).
    UnknownPosition {
        name: String,
    },
    /// A command completed (so the console can note saved names and so on).
    Done {
        command: ArmCommand,
    },
    /// The stop guard's state changed.
    Guard(GuardStatus),
    /// Every link that carried motion acknowledged a STOP: one per STOP, after its `Done`/`Failed`.
    StopConfirmed,
    /// A STOP did not get through, or a link's own stop failed: the arm may still be moving.
    StopUnconfirmed {
        reason: String,
    },
}

impl ArmEvent {
    /// `command` failed with `error`.
    pub fn failed(command: &ArmCommand, error: ArmError) -> ArmEvent {
        let command = command.kind();
        ArmEvent::Failed { command, error }
    }
}
