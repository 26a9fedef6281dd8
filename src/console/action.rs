//! What a key can be bound to. Names are the snake_case strings used in keymap JSON files.

use serde::{Deserialize, Serialize};

/// A direction along one jog axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum Sign {
    Plus,
    Minus,
}

impl Sign {
    pub fn value(self) -> i8 {
        match self {
            Sign::Plus => 1,
            Sign::Minus => -1,
        }
    }
}

/// The axes a held key can drive.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum JogAxis {
    X,
    Y,
    Z,
    Azimuth,
    Altitude,
    /// The selected joint (single-joint jog).
    Joint,
}

impl JogAxis {
    /// Cartesian axes combine with each other; polar axes with each other; a joint jog stands
    /// alone.
    pub fn family(self) -> JogFamily {
        match self {
            JogAxis::X | JogAxis::Y | JogAxis::Z => JogFamily::Cartesian,
            JogAxis::Azimuth | JogAxis::Altitude => JogFamily::Polar,
            JogAxis::Joint => JogFamily::Joint,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum JogFamily {
    Cartesian,
    Polar,
    Joint,
}

/// Everything a key can do.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Action {
    // Hold-to-jog.
    JogXPlus,
    JogXMinus,
    JogYPlus,
    JogYMinus,
    JogZPlus,
    JogZMinus,
    PanAzimuthPlus,
    PanAzimuthMinus,
    PanAltitudePlus,
    PanAltitudeMinus,
    JointPlus,
    JointMinus,
    // Motion control.
    Stop,
    QuickStop,
    FaultReset,
    Home,
    StepMode,
    StepBigger,
    StepSmaller,
    SpeedUp,
    SpeedDown,
    FrameCycle,
    JointNext,
    JointPrevious,
    // Named positions.
    SavePosition,
    GoToPosition,
    DeletePosition,
    RenamePosition,
    UndoDelete,
    SetPolarPosition,
    SetCartesianPosition,
    ShowPosition,
    PositionNext,
    PositionPrevious,
    // Screen.
    ToggleHex,
    Help,
    Quit,
}

impl Action {
    /// Every action, in the order the help overlay lists them.
    pub const ALL: [Action; 37] = [
        Action::JogXPlus,
        Action::JogXMinus,
        Action::JogYPlus,
        Action::JogYMinus,
        Action::JogZPlus,
        Action::JogZMinus,
        Action::PanAzimuthPlus,
        Action::PanAzimuthMinus,
        Action::PanAltitudePlus,
        Action::PanAltitudeMinus,
        Action::JointPlus,
        Action::JointMinus,
        Action::Stop,
        Action::QuickStop,
        Action::FaultReset,
        Action::Home,
        Action::StepMode,
        Action::StepBigger,
        Action::StepSmaller,
        Action::SpeedUp,
        Action::SpeedDown,
        Action::FrameCycle,
        Action::JointNext,
        Action::JointPrevious,
        Action::SavePosition,
        Action::GoToPosition,
        Action::DeletePosition,
        Action::RenamePosition,
        Action::UndoDelete,
        Action::SetPolarPosition,
        Action::SetCartesianPosition,
        Action::ShowPosition,
        Action::PositionNext,
        Action::PositionPrevious,
        Action::ToggleHex,
        Action::Help,
        Action::Quit,
    ];

    /// The axis and direction of a hold-to-jog action.
    pub fn jog(self) -> Option<(JogAxis, Sign)> {
        use Action as A;
        Some(match self {
            A::JogXPlus => (JogAxis::X, Sign::Plus),
            A::JogXMinus => (JogAxis::X, Sign::Minus),
            A::JogYPlus => (JogAxis::Y, Sign::Plus),
            A::JogYMinus => (JogAxis::Y, Sign::Minus),
            A::JogZPlus => (JogAxis::Z, Sign::Plus),
            A::JogZMinus => (JogAxis::Z, Sign::Minus),
            A::PanAzimuthPlus => (JogAxis::Azimuth, Sign::Plus),
            A::PanAzimuthMinus => (JogAxis::Azimuth, Sign::Minus),
            A::PanAltitudePlus => (JogAxis::Altitude, Sign::Plus),
            A::PanAltitudeMinus => (JogAxis::Altitude, Sign::Minus),
            A::JointPlus => (JogAxis::Joint, Sign::Plus),
            A::JointMinus => (JogAxis::Joint, Sign::Minus),
            _ => return None,
        })
    }

    /// The name used in keymap files.
    pub fn name(self) -> String {
        match serde_json::to_value(self) {
            Ok(serde_json::Value::String(s)) => s,
            _ => format!("{self:?}"),
        }
    }

    /// A short description for the help overlay.
    pub fn describe(self) -> &'static str {
        use Action as A;
        match self {
            A::JogXPlus => "jog +X (hold)",
            A::JogXMinus => "jog -X (hold)",
            A::JogYPlus => "jog +Y (hold)",
            A::JogYMinus => "jog -Y (hold)",
            A::JogZPlus => "jog +Z (hold)",
            A::JogZMinus => "jog -Z (hold)",
            A::PanAzimuthPlus => "pan azimuth + (hold)",
            A::PanAzimuthMinus => "pan azimuth - (hold)",
            A::PanAltitudePlus => "pan altitude + (hold)",
            A::PanAltitudeMinus => "pan altitude - (hold)",
            A::JointPlus => "selected joint + (hold)",
            A::JointMinus => "selected joint - (hold)",
            A::Stop => "stop all motion",
            A::QuickStop => "quick stop (arm goes to fault)",
            A::FaultReset => "reset faults",
            A::Home => "go home (asks first)",
            A::StepMode => "toggle step mode",
            A::StepBigger => "bigger step",
            A::StepSmaller => "smaller step",
            A::SpeedUp => "speed up",
            A::SpeedDown => "speed down",
            A::FrameCycle => "cycle reference frame",
            A::JointNext => "select next joint",
            A::JointPrevious => "select previous joint",
            A::SavePosition => "save current pose as...",
            A::GoToPosition => "go to selected position (asks first)",
            A::DeletePosition => "delete selected position (asks first)",
            A::RenamePosition => "rename selected position",
            A::UndoDelete => "undo the last delete",
            A::SetPolarPosition => "define a position in polar coordinates",
            A::SetCartesianPosition => "define a position in cartesian coordinates",
            A::ShowPosition => "show selected position's coordinates",
            A::PositionNext => "select next position",
            A::PositionPrevious => "select previous position",
            A::ToggleHex => "show frames in hex in the log",
            A::Help => "this help",
            A::Quit => "quit (stops the arm)",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_snake_case_and_round_trip() {
        assert_eq!(Action::JogXPlus.name(), "jog_x_plus");
        assert_eq!(Action::PanAltitudeMinus.name(), "pan_altitude_minus");
        for action in Action::ALL {
            let parsed: Action = serde_json::from_value(serde_json::json!(action.name())).unwrap();
            assert_eq!(parsed, action);
        }
    }

    #[test]
    fn all_lists_every_action_once() {
        let mut seen = std::collections::BTreeSet::new();
        for action in Action::ALL {
            assert!(seen.insert(action), "{action:?} twice");
        }
    }
}
