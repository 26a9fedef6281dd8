//! What a key can be bound to. Names are the snake_case strings used in keymap JSON files.

use serde::{Deserialize, Serialize};

use self::Action as A;

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
    /// Turns of the tool about its point, about X, Y, Z of the selected frame.
    Rx,
    Ry,
    Rz,
}

impl JogAxis {
    /// Cartesian, polar and turn axes each combine within their kind; a joint jog stands alone.
    pub fn family(self) -> JogFamily {
        match self {
            JogAxis::X | JogAxis::Y | JogAxis::Z => JogFamily::Cartesian,
            JogAxis::Azimuth | JogAxis::Altitude => JogFamily::Polar,
            JogAxis::Joint => JogFamily::Joint,
            JogAxis::Rx | JogAxis::Ry | JogAxis::Rz => JogFamily::Orientation,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum JogFamily {
    Cartesian,
    Polar,
    Joint,
    Orientation,
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
    JogRxPlus,
    JogRxMinus,
    JogRyPlus,
    JogRyMinus,
    JogRzPlus,
    JogRzMinus,
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
    HistoryCycle,
    Help,
    Quit,
    // Tours of named positions.
    MakeTour,
    PlayTour,
    TourLeg,
    // Motion (listed after home in `ALL`).
    StoredAction,
    // The fence screen (listed with the screen's keys).
    Fence,
}

/// Every action in the order the help overlay lists them, with what it does in one line.
const DESCRIBED: [(Action, &str); 49] = [
    (A::JogXPlus, "hold: move the tool +X"),
    (A::JogXMinus, "hold: move the tool -X"),
    (A::JogYPlus, "hold: move the tool +Y"),
    (A::JogYMinus, "hold: move the tool -Y"),
    (A::JogZPlus, "hold: move the tool +Z"),
    (A::JogZMinus, "hold: move the tool -Z"),
    (A::PanAzimuthPlus, "hold: turn about the base, azimuth +"),
    (A::PanAzimuthMinus, "hold: turn about the base, azimuth -"),
    (A::PanAltitudePlus, "hold: raise the tool, altitude +"),
    (A::PanAltitudeMinus, "hold: lower the tool, altitude -"),
    (A::JointPlus, "hold: turn the selected joint +"),
    (A::JointMinus, "hold: turn the selected joint -"),
    (A::JogRxPlus, "hold: turn the tool about its point, +Rx"),
    (A::JogRxMinus, "hold: turn the tool about its point, -Rx"),
    (A::JogRyPlus, "hold: turn the tool about its point, +Ry"),
    (A::JogRyMinus, "hold: turn the tool about its point, -Ry"),
    (A::JogRzPlus, "hold: turn the tool about its point, +Rz"),
    (A::JogRzMinus, "hold: turn the tool about its point, -Rz"),
    (A::Stop, "stop all motion"),
    (A::QuickStop, "quick stop: the arm faults until reset"),
    (A::FaultReset, "reset the arm's faults"),
    (A::Home, "go to the home pose (asks first)"),
    (
        A::StoredAction,
        "run a stored action or sequence by id (Modbus)",
    ),
    (A::StepMode, "step mode on/off: one step per press"),
    (A::StepBigger, "bigger step (step mode)"),
    (A::StepSmaller, "smaller step (step mode)"),
    (A::SpeedUp, "faster: next speed step (% of the cap)"),
    (A::SpeedDown, "slower: previous speed step"),
    (A::FrameCycle, "jog frame: base, tool, mixed (Modbus)"),
    (A::JointNext, "select the next joint"),
    (A::JointPrevious, "select the previous joint"),
    (A::SavePosition, "save the current pose under a name"),
    (A::GoToPosition, "go to the selected position (asks first)"),
    (
        A::DeletePosition,
        "delete the selected position (asks first)",
    ),
    (A::RenamePosition, "rename the selected position"),
    (A::UndoDelete, "bring back the last deleted position"),
    (
        A::SetPolarPosition,
        "define a position by elevation, azimuth, radius",
    ),
    (A::SetCartesianPosition, "define a position by x, y, z"),
    (A::ShowPosition, "show the selected position's coordinates"),
    (A::PositionNext, "select the next position"),
    (A::PositionPrevious, "select the previous position"),
    (A::ToggleHex, "show the log's frames in hex"),
    (A::HistoryCycle, "history: plot joint torque or current"),
    (A::Fence, "the fence: its faces and zones, taught here"),
    (A::Help, "this help: every key of the keymap"),
    (A::Quit, "stop the arm and quit"),
    (A::MakeTour, "make a tour of the positions (a form)"),
    (A::PlayTour, "play a tour straight through (asks first)"),
    (A::TourLeg, "play a tour one leg at a time; next leg"),
];

impl Action {
    /// Every action, in the order the help overlay lists them.
    pub const ALL: [Action; 49] = {
        let mut all = [Action::Stop; 49];
        let mut i = 0;
        while i < all.len() {
            all[i] = DESCRIBED[i].0;
            i += 1;
        }
        all
    };

    /// The axis and direction of a hold-to-jog action.
    pub fn jog(self) -> Option<(JogAxis, Sign)> {
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
            A::JogRxPlus => (JogAxis::Rx, Sign::Plus),
            A::JogRxMinus => (JogAxis::Rx, Sign::Minus),
            A::JogRyPlus => (JogAxis::Ry, Sign::Plus),
            A::JogRyMinus => (JogAxis::Ry, Sign::Minus),
            A::JogRzPlus => (JogAxis::Rz, Sign::Plus),
            A::JogRzMinus => (JogAxis::Rz, Sign::Minus),
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

    /// What the action does, in one line (the help overlay and the key table of docs/user-guide.md).
    pub fn describe(self) -> &'static str {
        let described = DESCRIBED.iter().find(|(action, _)| *action == self);
        described.map_or("", |(_, text)| text)
    }

    /// The help overlay's section for this action.
    pub fn section(self) -> &'static str {
        match self {
            _ if self.jog().is_some() => "Hold to move",
            A::Stop
            | A::QuickStop
            | A::FaultReset
            | A::Home
            | A::StepMode
            | A::StepBigger
            | A::StepSmaller
            | A::SpeedUp
            | A::SpeedDown
            | A::FrameCycle
            | A::JointNext
            | A::JointPrevious
            | A::StoredAction => "Motion",
            A::SavePosition
            | A::GoToPosition
            | A::DeletePosition
            | A::RenamePosition
            | A::UndoDelete
            | A::SetPolarPosition
            | A::SetCartesianPosition
            | A::ShowPosition
            | A::PositionNext
            | A::PositionPrevious => "Named positions",
            A::MakeTour | A::PlayTour | A::TourLeg => "Tours",
            _ => "Screen",
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
        assert_eq!(Action::JogRxPlus.name(), "jog_rx_plus");
        assert_eq!(Action::JogRzMinus.name(), "jog_rz_minus");
        for action in Action::ALL {
            let parsed: Action = serde_json::from_value(serde_json::json!(action.name())).unwrap();
            assert_eq!(parsed, action);
        }
    }

    #[test]
    fn every_description_is_one_short_line() {
        for action in Action::ALL {
            let text = action.describe();
            assert!(!text.is_empty() && !text.contains('\n'), "{action:?}");
            assert!(
                text.len() <= 48,
                "{action:?}: {text} is too long for 80 columns"
            );
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
