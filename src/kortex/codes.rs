//! The ICD's numbered values, each with a snake_case key and the ICD's description.

use std::borrow::Cow;
use std::fmt;

use serde::{Serialize, Serializer};

/// A value the ICD numbers: robot states, move types, reference frames, flags (by bit).
pub trait CodeName: Sized + Copy + 'static {
    /// Every value, in code order.
    const ALL: &'static [Self];
    fn from_code(code: u16) -> Option<Self>;
    fn code(self) -> u16;
    /// snake_case name, as printed by `--json`.
    fn key(self) -> &'static str;
    /// What the ICD says it means.
    fn description(self) -> &'static str;
}

/// Declares a `CodeName` enum: `Variant = code, "key", "description";`.
macro_rules! coded_enum {
    (
        $(#[$meta:meta])*
        $name:ident { $( $(#[$vmeta:meta])* $variant:ident = $code:literal, $key:literal, $desc:literal; )+ }
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum $name { $( $(#[$vmeta])* $variant = $code, )+ }

        impl $crate::kortex::codes::CodeName for $name {
            const ALL: &'static [Self] = &[$($name::$variant),+];
            fn from_code(code: u16) -> Option<Self> {
                match code { $( $code => Some($name::$variant), )+ _ => None }
            }
            fn code(self) -> u16 {
                self as u16
            }
            fn key(self) -> &'static str {
                match self { $( $name::$variant => $key, )+ }
            }
            fn description(self) -> &'static str {
                match self { $( $name::$variant => $desc, )+ }
            }
        }

        impl std::fmt::Display for $name {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str($crate::kortex::codes::CodeName::key(*self))
            }
        }
    };
}
pub(crate) use coded_enum;

coded_enum! {
    /// Arm state: input register 0 holds its number; discrete inputs 0-9 hold it one-hot.
    RobotState {
        Unspecified = 0, "unspecified", "Unspecified arm state";
        /// Never seen by a client: the base must finish initialising before it accepts one.
        BaseInitialization = 1, "base_initialization", "Base initialisation in progress";
        BaseInitialized = 2, "base_initialized", "Base initialisation succeeded";
        ArmInitialization = 3, "arm_initialization", "Arm is being initialised";
        InFault = 4, "in_fault", "Arm is in fault";
        InMaintenance = 5, "in_maintenance", "Arm is in maintenance";
        LowLevelServoing = 6, "low_level_servoing", "Arm is in low-level servoing mode";
        Ready = 7, "ready", "Arm is ready to be controlled";
        ControlledBySequence = 8, "controlled_by_sequence", "Arm is being controlled via a sequence";
        ControlledManually = 9, "controlled_manually", "Arm is being controlled manually";
    }
}

coded_enum! {
    /// Status of the executed action or sequence (holding register 100).
    ActionStatus {
        Started = 0, "started", "Started";
        Completed = 1, "completed", "Completed";
        Paused = 2, "paused", "Paused";
        Aborted = 3, "aborted", "Aborted";
    }
}

coded_enum! {
    /// Move type: active (holding register 102) or commanded (holding register 202).
    MoveType {
        Action = 0, "action", "Action";
        Sequence = 1, "sequence", "Sequence";
        CartesianTrajectory = 2, "cartesian_trajectory", "Cartesian trajectory";
        Twist = 3, "twist", "Twist";
    }
}

coded_enum! {
    /// Cartesian reference frame of a commanded pose or twist (holding register 203).
    ReferenceFrame {
        Mixed = 1, "mixed", "Mixed";
        Tool = 2, "tool", "Tool";
        Base = 3, "base", "Base";
    }
}

coded_enum! {
    /// What a write to holding register 200 asks for (the ICD calls it "Status").
    ActionCommand {
        NoAction = 0, "no_action", "No action";
        Start = 1, "start", "Action start";
        Stop = 2, "stop", "Action stop";
    }
}

coded_enum! {
    /// Control coils 0-2; holding register 0 lists the same actions by the same numbers.
    ControlCoil {
        QuickStop = 0, "quick_stop", "Quick stop";
        Abort = 1, "abort", "Abort / manual stop";
        FaultReset = 2, "fault_reset", "Fault reset";
    }
}

impl std::str::FromStr for ReferenceFrame {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        ReferenceFrame::ALL
            .iter()
            .copied()
            .find(|frame| frame.key() == s)
            .ok_or_else(|| format!("unknown reference frame '{s}': expected mixed, tool or base"))
    }
}

/// A decoded number: one the ICD names, or one it does not (kept, never dropped).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Coded<T> {
    Known(T),
    Unknown(u16),
}

impl<T: CodeName> Coded<T> {
    pub fn from_code(code: u16) -> Self {
        T::from_code(code).map_or(Coded::Unknown(code), Coded::Known)
    }

    pub fn code(&self) -> u16 {
        match self {
            Coded::Known(value) => value.code(),
            Coded::Unknown(code) => *code,
        }
    }

    pub fn known(&self) -> Option<T> {
        match self {
            Coded::Known(value) => Some(*value),
            Coded::Unknown(_) => None,
        }
    }

    /// The value of a [`Coded::key`] (`ready`, `unknown_65535`): how it reads back from JSON.
    pub fn from_key(key: &str) -> Option<Coded<T>> {
        if let Some(code) = key.strip_prefix("unknown_") {
            return code.parse().ok().map(Coded::Unknown);
        }
        T::ALL
            .iter()
            .find(|v| v.key() == key)
            .map(|v| Coded::Known(*v))
    }

    /// The value's key, or `unknown_N` for a number the ICD does not list.
    pub fn key(&self) -> Cow<'static, str> {
        match self {
            Coded::Known(value) => Cow::Borrowed(value.key()),
            Coded::Unknown(code) => Cow::Owned(format!("unknown_{code}")),
        }
    }
}

impl<T: CodeName> fmt::Display for Coded<T> {
    /// `ready (7)`; a number the ICD does not list shows as itself: `unknown (65535)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Coded::Known(value) => write!(f, "{} ({})", value.key(), value.code()),
            Coded::Unknown(code) => write!(f, "unknown ({code})"),
        }
    }
}

impl<T: CodeName> Serialize for Coded<T> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(&self.key())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_round_trip_and_unknowns_are_kept() {
        for state in RobotState::ALL {
            assert_eq!(RobotState::from_code(state.code()), Some(*state));
        }
        assert_eq!(RobotState::ALL.len(), 10);
        assert_eq!(Coded::<MoveType>::from_code(3).key(), "twist");
        assert_eq!(Coded::<MoveType>::from_code(9).key(), "unknown_9");
        assert_eq!(
            Coded::<RobotState>::from_code(65535).to_string(),
            "unknown (65535)"
        );
        assert_eq!(Coded::<RobotState>::from_code(7).to_string(), "ready (7)");
        assert_eq!("tool".parse::<ReferenceFrame>(), Ok(ReferenceFrame::Tool));
        assert!("world".parse::<ReferenceFrame>().is_err());
    }
}
