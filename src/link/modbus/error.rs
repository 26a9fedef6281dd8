//! What can go wrong talking to an arm over Modbus, and the words the technician reads for it.

use std::fmt;
use std::time::Duration;

use crate::kortex::commands::{CommandError, Write};
use crate::kortex::{PolarPanError, ReadBlock};
use crate::net::ConnectError;

/// A Modbus exception response: tokio-modbus's own type, so the link and the simulator agree.
pub use tokio_modbus::ExceptionCode;

/// An exception as the console and the CLI print it: "illegal data value (0x03)".
fn exception_text(exception: &ExceptionCode) -> String {
    let name = match exception {
        ExceptionCode::Custom(_) => "unknown exception".to_owned(),
        // tokio-modbus names them in sentence case; messages here keep them lower case.
        known => known.to_string().to_lowercase(),
    };
    format!("{name} (0x{:02X})", u8::from(*exception))
}

/// One request, named for error messages.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Operation {
    Read(ReadBlock),
    Write(Write),
}

impl fmt::Display for Operation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Operation::Read(block) => block.fmt(f),
            Operation::Write(write) => write.fmt(f),
        }
    }
}

/// Everything that can go wrong talking to an arm.
#[derive(Debug, thiserror::Error)]
pub enum ModbusError {
    /// No connection was opened; the error names the address.
    #[error(transparent)]
    Connect(#[from] ConnectError),
    #[error("{operation}: the arm answered with exception {}", exception_text(.exception))]
    Exception {
        operation: Operation,
        exception: ExceptionCode,
    },
    #[error("{operation}: no reply within {after:?}")]
    Timeout {
        operation: Operation,
        after: Duration,
    },
    #[error("{operation}: connection lost: {}", crate::net::io_error_words(.source))]
    Transport {
        operation: Operation,
        source: std::io::Error,
    },
    #[error("{operation}: the reply does not match the request: {detail}")]
    Protocol {
        operation: Operation,
        detail: String,
    },
    #[error("refused before anything was sent: {0}")]
    InvalidCommand(#[from] CommandError),
    #[error("polar pan refused: {0}")]
    PolarPan(#[from] PolarPanError),
    #[error("polar pan needs background polling: the link was made without a poll rate")]
    NoPolling,
    #[error("bad link configuration: {reason}")]
    BadConfig { reason: String },
    #[error("not connected to the arm: {reason}")]
    Disconnected { reason: String },
    #[error(
        "the arm reports speed limits of {linear} m/s and {angular} deg/s: a move's speed cannot be bounded from them"
    )]
    SpeedLimitsUnknown { linear: f32, angular: f32 },
    /// Another client's capped move runs: ours would later restore its lowered limits for good.
    #[error(
        "another client's move runs on the arm ({0}): nothing is started over it (its speed \
         limits may be that client's lowered ones)"
    )]
    AnotherMoveRuns(String),
    #[error("the arm refused the stop ({stop}) and the abort coil ({abort}): it may still move")]
    StopFailed {
        stop: Box<ModbusError>,
        abort: Box<ModbusError>,
    },
}

impl ModbusError {
    /// Whether the connection can no longer be trusted and must be reopened.
    pub fn breaks_connection(&self) -> bool {
        matches!(
            self,
            ModbusError::Timeout { .. }
                | ModbusError::Transport { .. }
                | ModbusError::Protocol { .. }
        )
    }

    /// Whether nothing was sent because the command itself was refused.
    pub fn refused_before_sending(&self) -> bool {
        matches!(
            self,
            ModbusError::InvalidCommand(_)
                | ModbusError::PolarPan(
                    PolarPanError::BadSettings | PolarPanError::DirectionOutOfRange { .. }
                )
                | ModbusError::NoPolling
                | ModbusError::BadConfig { .. }
        )
    }

    /// The exception the arm answered with, if it answered with one.
    pub fn exception(&self) -> Option<ExceptionCode> {
        match self {
            ModbusError::Exception { exception, .. } => Some(*exception),
            ModbusError::StopFailed { stop, .. } => stop.exception(),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exceptions_print_lower_case_names_with_their_codes() {
        assert_eq!(
            exception_text(&ExceptionCode::IllegalDataValue),
            "illegal data value (0x03)"
        );
        assert_eq!(
            exception_text(&ExceptionCode::GatewayTargetDevice),
            "gateway target device failed to respond (0x0B)"
        );
        assert_eq!(
            exception_text(&ExceptionCode::new(0x42)),
            "unknown exception (0x42)"
        );
    }
}
