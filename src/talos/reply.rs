//! Typed replies, one variant per ICD reply ("Receive" tables). armjog sends a reply's full layout,
//! zeroed after a non-zero return code; decoding also takes a bare 2-byte return code there, as a
//! failed operator has nothing to put in the fields.

use serde::Serialize;

use super::command::CommandValue;
use super::frame::TalosFrame;
use super::message::{DecodeError, EncodeError, FieldReader, framed};
use super::return_code::ReturnCode;

/// One reply, as the ICD's "Receive" tables define it.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
#[serde(untagged)]
pub enum Reply {
    Handshake {
        return_code: ReturnCode,
        major_version: u8,
        minor_version: u8,
    },
    PolarPan {
        return_code: ReturnCode,
    },
    Home {
        return_code: ReturnCode,
    },
    PolarPanStart {
        return_code: ReturnCode,
    },
    PolarPanStop {
        return_code: ReturnCode,
    },
    CartesianMove {
        return_code: ReturnCode,
    },
    CartesianMoveStart {
        return_code: ReturnCode,
    },
    CartesianMoveStop {
        return_code: ReturnCode,
    },
    HardwareOperation {
        return_code: ReturnCode,
        subcommand: u16,
        #[serde(serialize_with = "as_hex")]
        payload: Vec<u8>,
    },
    GetSpeed {
        return_code: ReturnCode,
        speed: u8,
    },
    SetSpeed {
        return_code: ReturnCode,
    },
    SavePosition {
        return_code: ReturnCode,
    },
    DeletePosition {
        return_code: ReturnCode,
    },
    GoToPosition {
        return_code: ReturnCode,
    },
    SetPolarPosition {
        return_code: ReturnCode,
    },
    GetPolarPosition {
        return_code: ReturnCode,
        delta: i32,
        azimuth: i32,
        radius: i32,
    },
    SetCartesianPosition {
        return_code: ReturnCode,
    },
    GetCartesianPosition {
        return_code: ReturnCode,
        x: i32,
        y: i32,
        z: i32,
    },
}

fn as_hex<S: serde::Serializer>(bytes: &[u8], s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(&hex::encode_upper(bytes))
}

impl Reply {
    pub fn command(&self) -> CommandValue {
        use CommandValue as C;
        match self {
            Reply::Handshake { .. } => C::Handshake,
            Reply::PolarPan { .. } => C::PolarPanDiscrete,
            Reply::Home { .. } => C::Home,
            Reply::PolarPanStart { .. } => C::PolarPanStart,
            Reply::PolarPanStop { .. } => C::PolarPanStop,
            Reply::CartesianMove { .. } => C::CartesianMoveDiscrete,
            Reply::CartesianMoveStart { .. } => C::CartesianMoveStart,
            Reply::CartesianMoveStop { .. } => C::CartesianMoveStop,
            Reply::HardwareOperation { .. } => C::ExecuteHardwareOperation,
            Reply::GetSpeed { .. } => C::GetSpeed,
            Reply::SetSpeed { .. } => C::SetSpeed,
            Reply::SavePosition { .. } => C::SavePosition,
            Reply::DeletePosition { .. } => C::DeletePosition,
            Reply::GoToPosition { .. } => C::GoToPosition,
            Reply::SetPolarPosition { .. } => C::SetPolarPosition,
            Reply::GetPolarPosition { .. } => C::GetPolarPosition,
            Reply::SetCartesianPosition { .. } => C::SetCartesianPosition,
            Reply::GetCartesianPosition { .. } => C::GetCartesianPosition,
        }
    }

    pub fn return_code(&self) -> ReturnCode {
        match self {
            Reply::Handshake { return_code, .. }
            | Reply::PolarPan { return_code }
            | Reply::Home { return_code }
            | Reply::PolarPanStart { return_code }
            | Reply::PolarPanStop { return_code }
            | Reply::CartesianMove { return_code }
            | Reply::CartesianMoveStart { return_code }
            | Reply::CartesianMoveStop { return_code }
            | Reply::HardwareOperation { return_code, .. }
            | Reply::GetSpeed { return_code, .. }
            | Reply::SetSpeed { return_code }
            | Reply::SavePosition { return_code }
            | Reply::DeletePosition { return_code }
            | Reply::GoToPosition { return_code }
            | Reply::SetPolarPosition { return_code }
            | Reply::GetPolarPosition { return_code, .. }
            | Reply::SetCartesianPosition { return_code }
            | Reply::GetCartesianPosition { return_code, .. } => *return_code,
        }
    }

    /// The error reply to `command`: only a return code, every other field zero.
    pub fn error(command: CommandValue, return_code: ReturnCode) -> Reply {
        match Self::decode_inner(command, &return_code.0.to_be_bytes(), true) {
            Ok(reply) => reply,
            // Unreachable: with zero fill every reply decodes from a bare return code.
            Err(_) => Reply::PolarPan { return_code },
        }
    }

    pub fn encode_payload(&self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.return_code().0.to_be_bytes());
        match self {
            Reply::Handshake {
                major_version,
                minor_version,
                ..
            } => out.extend_from_slice(&[*major_version, *minor_version]),
            Reply::HardwareOperation {
                subcommand,
                payload,
                ..
            } => {
                out.extend_from_slice(&subcommand.to_be_bytes());
                out.extend_from_slice(payload);
            }
            Reply::GetSpeed { speed, .. } => out.push(*speed),
            Reply::GetPolarPosition {
                delta,
                azimuth,
                radius,
                ..
            } => {
                for v in [delta, azimuth, radius] {
                    out.extend_from_slice(&v.to_be_bytes());
                }
            }
            Reply::GetCartesianPosition { x, y, z, .. } => {
                for v in [x, y, z] {
                    out.extend_from_slice(&v.to_be_bytes());
                }
            }
            _ => {}
        }
    }

    /// The reply as a frame answering request id `request_id` (its id | 1).
    pub fn to_frame(&self, request_id: u32) -> Result<TalosFrame, EncodeError> {
        let capacity = match self {
            Reply::HardwareOperation { payload, .. } => 4 + payload.len(),
            _ => 14,
        };
        let mut payload = Vec::with_capacity(capacity);
        self.encode_payload(&mut payload);
        framed(request_id | 1, self.command().reply_value(), payload)
    }

    /// Reads a reply frame. The reply bit must be set.
    pub fn from_frame(frame: &TalosFrame) -> Result<Reply, DecodeError> {
        let command = CommandValue::from_reply_value(frame.command)
            .ok_or(DecodeError::UnknownCommand(frame.command))?;
        Self::decode_payload(command, &frame.payload)
    }

    pub fn decode_payload(command: CommandValue, payload: &[u8]) -> Result<Reply, DecodeError> {
        Self::decode_inner(command, payload, false)
    }

    fn decode_inner(
        command: CommandValue,
        payload: &[u8],
        zero_fill: bool,
    ) -> Result<Reply, DecodeError> {
        use CommandValue as C;
        let mut r = FieldReader::new(command, payload);
        let return_code = ReturnCode(r.u16("return_code")?);
        // A failed operator may send the bare return code: the other fields read as zero.
        r.zero_fill = zero_fill || (!return_code.is_ok() && r.is_empty());
        let reply = match command {
            C::Handshake => Reply::Handshake {
                return_code,
                major_version: r.u8("major_version")?,
                minor_version: r.u8("minor_version")?,
            },
            C::PolarPanDiscrete => Reply::PolarPan { return_code },
            C::Home => Reply::Home { return_code },
            C::PolarPanStart => Reply::PolarPanStart { return_code },
            C::PolarPanStop => Reply::PolarPanStop { return_code },
            C::CartesianMoveDiscrete => Reply::CartesianMove { return_code },
            C::CartesianMoveStart => Reply::CartesianMoveStart { return_code },
            C::CartesianMoveStop => Reply::CartesianMoveStop { return_code },
            C::ExecuteHardwareOperation => Reply::HardwareOperation {
                return_code,
                subcommand: r.u16("subcommand")?,
                payload: r.rest(),
            },
            C::GetSpeed => Reply::GetSpeed {
                return_code,
                speed: r.u8("speed")?,
            },
            C::SetSpeed => Reply::SetSpeed { return_code },
            C::SavePosition => Reply::SavePosition { return_code },
            C::DeletePosition => Reply::DeletePosition { return_code },
            C::GoToPosition => Reply::GoToPosition { return_code },
            C::SetPolarPosition => Reply::SetPolarPosition { return_code },
            C::GetPolarPosition => Reply::GetPolarPosition {
                return_code,
                delta: r.i32("delta")?,
                azimuth: r.i32("azimuth")?,
                radius: r.i32("radius")?,
            },
            C::SetCartesianPosition => Reply::SetCartesianPosition { return_code },
            C::GetCartesianPosition => Reply::GetCartesianPosition {
                return_code,
                x: r.i32("x")?,
                y: r.i32("y")?,
                z: r.i32("z")?,
            },
        };
        r.finish()?;
        Ok(reply)
    }
}
