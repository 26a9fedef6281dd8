//! Why a command failed, typed: which kind of command
//! ([`CommandKind`](super::command_kind::CommandKind)) and what went wrong ([`ArmError`]), so
//! the console decides by value what a failure means (a failed jog stops and latches the held
//! keys) and shows the text only to people.

use std::sync::Arc;

use super::guard::GuardNotRunning;
use super::modbus::ModbusError;
use super::talos::TalosError;
use crate::talos::ReturnCode;
use crate::talos::hardware::HwError;

/// What went wrong carrying out a command. The link errors are kept whole (see [`Shared`]);
/// the kinds the console or the driver act on are variants of their own.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ArmError {
    /// The operator answered with a failing return code.
    #[error("{0}")]
    ReturnCode(ReturnCode),
    /// The Talos exchange failed: not sent, no reply, a rejected or malformed reply.
    #[error("{0}")]
    Talos(Shared<TalosError>),
    /// The Modbus link refused or failed the writes.
    #[error("{0}")]
    Modbus(Shared<ModbusError>),
    #[error("no link to the Talos operator")]
    NoTalosLink,
    #[error("the Modbus link to {addr} is not up")]
    ModbusLinkDown { addr: String },
    /// No configured link can carry the command at all.
    #[error("not possible over this link")]
    NoLinkCarriesIt,
    /// The link that would carry it cannot do this: the text says why and what can.
    #[error("{0}")]
    Unsupported(&'static str),
    #[error("no joint position reported yet: wait for telemetry")]
    NoJointPosition,
    #[error("no telemetry yet: the step needs the current pose")]
    NoPose,
    #[error("speed {requested} % is outside 1-100: {in_force} % stays in force")]
    SpeedOutOfRange { requested: u8, in_force: u8 },
    /// A request could not be encoded (a value outside what the wire can carry).
    #[error("{0}")]
    Encode(HwError),
    /// Motion is refused while the stop guard is not ready.
    #[error("{0}")]
    GuardNotRunning(GuardNotRunning),
    /// The stop guard stopped the arm (the console went quiet, or its link did).
    #[error("the stop guard stopped the arm: {0}")]
    GuardStoppedArm(String),
    /// The stop guard tried to stop the arm and could not: the arm may still be moving.
    #[error("the stop guard could NOT stop the arm, it may still be moving: {0}")]
    GuardStopFailed(String),
    /// A failure read back from a recording (`armjog replay`): its words only.
    #[error("{0}")]
    Replayed(String),
    /// The Modbus link could not write a STOP: the arm may still move.
    #[error("STOP COULD NOT BE WRITTEN: {0}")]
    StopNotWritten(String),
    /// A capped move's lowered speed limits could not be put back.
    #[error("the arm keeps the lowered limits; set {linear} m/s, {angular} deg/s again: {error}")]
    SpeedLimitsNotRestored {
        linear: f32,
        angular: f32,
        error: Shared<ModbusError>,
    },
}

/// A link's error kept whole for whoever reads it. Link errors hold sockets' errors, neither
/// `Clone` nor comparable, so the error is shared, and two are equal when they read the same.
#[derive(Debug)]
pub struct Shared<E>(Arc<E>);

impl<E> From<E> for Shared<E> {
    fn from(error: E) -> Shared<E> {
        Shared(Arc::new(error))
    }
}

impl<E> Clone for Shared<E> {
    fn clone(&self) -> Shared<E> {
        Shared(self.0.clone())
    }
}

impl<E: std::fmt::Display> PartialEq for Shared<E> {
    fn eq(&self, other: &Shared<E>) -> bool {
        Arc::ptr_eq(&self.0, &other.0) || self.0.to_string() == other.0.to_string()
    }
}

impl<E: std::fmt::Display> std::fmt::Display for Shared<E> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.0.fmt(f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_text_is_what_the_status_line_showed_before_the_types() {
        assert_eq!(
            ArmError::ReturnCode(ReturnCode::UNKNOWN_POSITION).to_string(),
            ReturnCode::UNKNOWN_POSITION.to_string()
        );
        assert_eq!(
            ArmError::ModbusLinkDown {
                addr: "10.0.0.2:502".into()
            }
            .to_string(),
            "the Modbus link to 10.0.0.2:502 is not up"
        );
        assert_eq!(
            ArmError::SpeedOutOfRange {
                requested: 0,
                in_force: 40
            }
            .to_string(),
            "speed 0 % is outside 1-100: 40 % stays in force"
        );
        let lost = || TalosError::Disconnected {
            reason: "reset".into(),
        };
        assert_eq!(
            ArmError::Talos(lost().into()).to_string(),
            lost().to_string()
        );
        assert_eq!(
            ArmError::Talos(lost().into()),
            ArmError::Talos(lost().into())
        );
        let busy = ModbusError::Disconnected {
            reason: "reset".into(),
        };
        assert_eq!(
            ArmError::Modbus(busy.into()).to_string(),
            "not connected to the arm: reset"
        );
        assert_eq!(
            ArmError::Encode(HwError::UnknownSubcommand(0x99)).to_string(),
            HwError::UnknownSubcommand(0x99).to_string()
        );
    }
}
