//! Typed replies, one variant per ICD reply ("Receive" tables). armjog sends a reply's full layout,
//! zeroed after a non-zero return code; decoding also takes a bare 2-byte return code there, as a
//! failed operator has nothing to put in the fields.

use serde::Serialize;

use super::command::CommandValue;
use super::frame::TalosFrame;
use super::message::{DecodeError, EncodeError, FieldReader, framed, talos_message};
use super::return_code::ReturnCode;

talos_message! {
    /// One reply, as the ICD's "Receive" tables define it.
    #[derive(Debug, Clone, PartialEq, Eq, Serialize)]
    #[serde(untagged)]
    pub enum Reply {
        Handshake = Handshake {
            return_code: ReturnCode = return_code,
            major_version: u8 = u8,
            minor_version: u8 = u8,
        },
        PolarPan = PolarPanDiscrete { return_code: ReturnCode = return_code, },
        Home = Home { return_code: ReturnCode = return_code, },
        PolarPanStart = PolarPanStart { return_code: ReturnCode = return_code, },
        PolarPanStop = PolarPanStop { return_code: ReturnCode = return_code, },
        CartesianMove = CartesianMoveDiscrete { return_code: ReturnCode = return_code, },
        CartesianMoveStart = CartesianMoveStart { return_code: ReturnCode = return_code, },
        CartesianMoveStop = CartesianMoveStop { return_code: ReturnCode = return_code, },
        HardwareOperation = ExecuteHardwareOperation {
            return_code: ReturnCode = return_code,
            subcommand: u16 = u16,
            #[serde(serialize_with = "as_hex")]
            payload: Vec<u8> = rest,
        },
        GetSpeed = GetSpeed {
            return_code: ReturnCode = return_code,
            speed: u8 = u8,
        },
        SetSpeed = SetSpeed { return_code: ReturnCode = return_code, },
        SavePosition = SavePosition { return_code: ReturnCode = return_code, },
        DeletePosition = DeletePosition { return_code: ReturnCode = return_code, },
        GoToPosition = GoToPosition { return_code: ReturnCode = return_code, },
        SetPolarPosition = SetPolarPosition { return_code: ReturnCode = return_code, },
        GetPolarPosition = GetPolarPosition {
            return_code: ReturnCode = return_code,
            delta: i32 = i32,
            azimuth: i32 = i32,
            radius: i32 = i32,
        },
        SetCartesianPosition = SetCartesianPosition { return_code: ReturnCode = return_code, },
        GetCartesianPosition = GetCartesianPosition {
            return_code: ReturnCode = return_code,
            x: i32 = i32,
            y: i32 = i32,
            z: i32 = i32,
        },
    }
}

fn as_hex<S: serde::Serializer>(bytes: &[u8], s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(&hex::encode_upper(bytes))
}

impl Reply {
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
        match Self::decode_fields(command, &return_code.0.to_be_bytes(), true) {
            Ok(reply) => reply,
            // Unreachable: with zero fill every reply decodes from a bare return code.
            Err(_) => Reply::PolarPan { return_code },
        }
    }

    /// The reply as a frame answering request id `request_id` (its id | 1).
    pub fn to_frame(&self, request_id: u32) -> Result<TalosFrame, EncodeError> {
        let capacity = match self {
            Reply::HardwareOperation { payload, .. } => 4 + payload.len(),
            _ => 14,
        };
        let mut payload = Vec::with_capacity(capacity);
        self.encode_payload(&mut payload)?;
        framed(request_id | 1, self.command().reply_value(), payload)
    }

    /// Reads a reply frame. The reply bit must be set.
    pub fn from_frame(frame: &TalosFrame) -> Result<Reply, DecodeError> {
        let command = CommandValue::from_reply_value(frame.command)
            .ok_or(DecodeError::UnknownCommand(frame.command))?;
        Self::decode_payload(command, &frame.payload)
    }
}
