//! What kind a command is ([`CommandKind`], named in failures) and what it does to the arm
//! ([`CommandClass`]), said once for the app, the driver, the Modbus worker and the audit. What a
//! Talos request does on the wire is the ICD's fact:
//! [`Request::class`](crate::talos::Request::class).

/// What a command does to the arm.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CommandClass {
    /// Stops every motion: never queued, always allowed; its failure may leave the arm moving.
    Stop,
    /// May set the arm moving (a jog, even all-zero, a step, a go-to, home, a stored run): only
    /// these pass the motion gate and need a ready stop guard. `runs_to_end`: the arm carries it to
    /// its end on its own, so its link's answer says only that it started.
    Motion { runs_to_end: bool },
    /// Moves nothing: speed, frame, fault reset, operator positions, limits put back.
    Setting,
    /// Reads and changes nothing.
    Query,
}

/// What kind of command failed (a command's, or the driver's own work).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CommandKind {
    Jog,
    Stop,
    Step,
    MoveToPose,
    Home,
    SetSpeed,
    /// The fence's share of the speed in force.
    FenceSpeed,
    SetFrame,
    QuickStop,
    FaultReset,
    SavePosition,
    DeletePosition,
    GoToPosition,
    SetPolarPosition,
    SetCartesianPosition,
    GetPosition,
    /// The Modbus link putting back the speed limits a capped move lowered.
    RestoreSpeedLimits,
    /// A stored action or sequence started by id.
    StartStored,
}

impl CommandKind {
    /// Every kind.
    pub const ALL: [CommandKind; 18] = [
        CommandKind::Jog,
        CommandKind::Stop,
        CommandKind::Step,
        CommandKind::MoveToPose,
        CommandKind::Home,
        CommandKind::SetSpeed,
        CommandKind::FenceSpeed,
        CommandKind::SetFrame,
        CommandKind::QuickStop,
        CommandKind::FaultReset,
        CommandKind::SavePosition,
        CommandKind::DeletePosition,
        CommandKind::GoToPosition,
        CommandKind::SetPolarPosition,
        CommandKind::SetCartesianPosition,
        CommandKind::GetPosition,
        CommandKind::RestoreSpeedLimits,
        CommandKind::StartStored,
    ];

    /// The kind a [`CommandKind::label`] names (a recording's words read back).
    pub fn from_label(label: &str) -> Option<CommandKind> {
        CommandKind::ALL.into_iter().find(|k| k.label() == label)
    }

    /// Words for the status line and the log: "jog", "go to position".
    pub fn label(self) -> &'static str {
        match self {
            CommandKind::Jog => "jog",
            CommandKind::Stop => "stop",
            CommandKind::Step => "step",
            CommandKind::MoveToPose => "move to pose",
            CommandKind::Home => "home",
            CommandKind::SetSpeed => "set speed",
            CommandKind::FenceSpeed => "fence speed",
            CommandKind::SetFrame => "set frame",
            CommandKind::QuickStop => "quick stop",
            CommandKind::FaultReset => "fault reset",
            CommandKind::SavePosition => "save position",
            CommandKind::DeletePosition => "delete position",
            CommandKind::GoToPosition => "go to position",
            CommandKind::SetPolarPosition => "set polar position",
            CommandKind::SetCartesianPosition => "set cartesian position",
            CommandKind::GetPosition => "get position",
            CommandKind::RestoreSpeedLimits => "restore speed limits",
            CommandKind::StartStored => "stored action",
        }
    }

    /// What this kind does to the arm. No `_` arm: a new kind must be classified here.
    pub fn class(self) -> CommandClass {
        match self {
            CommandKind::Stop | CommandKind::QuickStop => CommandClass::Stop,
            CommandKind::Jog => CommandClass::Motion { runs_to_end: false },
            CommandKind::Step
            | CommandKind::MoveToPose
            | CommandKind::Home
            | CommandKind::GoToPosition
            | CommandKind::StartStored => CommandClass::Motion { runs_to_end: true },
            CommandKind::SetSpeed
            | CommandKind::FenceSpeed
            | CommandKind::SetFrame
            | CommandKind::FaultReset
            | CommandKind::SavePosition
            | CommandKind::DeletePosition
            | CommandKind::SetPolarPosition
            | CommandKind::SetCartesianPosition
            | CommandKind::RestoreSpeedLimits => CommandClass::Setting,
            CommandKind::GetPosition => CommandClass::Query,
        }
    }

    /// `class() == Stop`: a failure of it may leave the arm moving.
    pub fn is_stop(self) -> bool {
        self.class() == CommandClass::Stop
    }
}

impl std::fmt::Display for CommandKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.label())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kortex::{Pose, ReferenceFrame, Stored, StoredMotion};
    use crate::link::interface::{ArmCommand, JogMotion, StepMove};

    const JOG: CommandClass = CommandClass::Motion { runs_to_end: false };
    const MOVE: CommandClass = CommandClass::Motion { runs_to_end: true };

    #[test]
    fn a_kind_names_itself_in_words() {
        assert_eq!(CommandKind::GoToPosition.to_string(), "go to position");
    }

    /// Every command, classified by hand: a command that moves the arm (while refreshed, or to
    /// its end), stops it, changes a setting or reads, whatever its fields.
    #[test]
    fn every_command_is_classified_by_what_it_does_to_the_arm() {
        let name = || "bench".to_string();
        let table = [
            (ArmCommand::Stop, CommandClass::Stop),
            (ArmCommand::QuickStop, CommandClass::Stop),
            (
                ArmCommand::Jog(JogMotion::Cartesian { x: 1, y: 0, z: 0 }),
                JOG,
            ),
            // All-zero still goes out as a start: the arm may be told to move.
            (
                ArmCommand::Jog(JogMotion::Polar {
                    azimuth: 0,
                    altitude: 0,
                }),
                JOG,
            ),
            (
                ArmCommand::Jog(JogMotion::Joint {
                    joint: 3,
                    direction: -1,
                }),
                JOG,
            ),
            (
                ArmCommand::Jog(JogMotion::Orientation {
                    rx: 0,
                    ry: 0,
                    rz: 1,
                }),
                JOG,
            ),
            (
                ArmCommand::Step(StepMove::Cartesian {
                    dx: 10,
                    dy: 0,
                    dz: 0,
                }),
                MOVE,
            ),
            (ArmCommand::MoveToPose(Pose::default()), MOVE),
            (ArmCommand::Home, MOVE),
            (ArmCommand::GoToPosition { name: name() }, MOVE),
            (
                ArmCommand::StartStored(Stored {
                    motion: StoredMotion::Action,
                    id: 7,
                }),
                MOVE,
            ),
            (ArmCommand::SetSpeed(50), CommandClass::Setting),
            (ArmCommand::FenceSpeed(550), CommandClass::Setting),
            (
                ArmCommand::SetFrame(ReferenceFrame::Base),
                CommandClass::Setting,
            ),
            (ArmCommand::FaultReset, CommandClass::Setting),
            (
                ArmCommand::SavePosition {
                    name: name(),
                    anchor: false,
                    parent: None,
                },
                CommandClass::Setting,
            ),
            (
                ArmCommand::DeletePosition { name: name() },
                CommandClass::Setting,
            ),
            (
                ArmCommand::SetPolarPosition {
                    name: name(),
                    delta: 0,
                    azimuth: 0,
                    radius: 0,
                },
                CommandClass::Setting,
            ),
            (
                ArmCommand::SetCartesianPosition {
                    name: name(),
                    x: 0,
                    y: 0,
                    z: 0,
                },
                CommandClass::Setting,
            ),
            (
                ArmCommand::GetPosition { name: name() },
                CommandClass::Query,
            ),
        ];
        for (command, class) in &table {
            assert_eq!(command.class(), *class, "{command:?}");
            assert_eq!(command.kind().class(), *class, "{command:?}");
            assert_eq!(
                command.is_stop(),
                *class == CommandClass::Stop,
                "{command:?}"
            );
            assert_eq!(
                command.starts_motion(),
                matches!(class, CommandClass::Motion { .. }),
                "{command:?}"
            );
        }
        assert_eq!(
            CommandKind::RestoreSpeedLimits.class(),
            CommandClass::Setting
        );
        assert!(CommandKind::QuickStop.is_stop() && !CommandKind::Jog.is_stop());
    }
}
