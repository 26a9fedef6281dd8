//! Typed requests, one variant per ICD command ("Send" tables). Names and directions are carried
//! raw so encoding can refuse a bad one naming its field; decoding applies the same rules (a server
//! answers MALFORMED_PAYLOAD).

use super::command::CommandValue;
use super::frame::TalosFrame;
use super::message::{DecodeError, EncodeError, FieldReader, framed, talos_message};

talos_message! {
    /// One request, as the ICD's "Send" tables define it.
    #[derive(Debug, Clone, PartialEq, Eq)]
    pub enum Request {
        /// The ICD sends a 2-byte OID; deployed clients (talos-rit/commander, the old operator's
        /// interfaces) send an empty payload, decoded as `oid: None`. armjog's client always sends
        /// `Some` (the ICD layout); `None` encodes as the empty payload it came from.
        Handshake = Handshake { oid: Option<u16> = oid, },
        PolarPan = PolarPanDiscrete {
            delta_azimuth: i32 = i32,
            delta_altitude: i32 = i32,
            delay_ms: u32 = u32,
            time_ms: u32 = u32,
        },
        Home = Home { delay_ms: u32 = u32, },
        PolarPanStart = PolarPanStart {
            moving_azimuth: i8 = direction,
            moving_altitude: i8 = direction,
        },
        PolarPanStop = PolarPanStop,
        CartesianMove = CartesianMoveDiscrete {
            delta_x: i32 = i32,
            delta_y: i32 = i32,
            delta_z: i32 = i32,
            delay_ms: u32 = u32,
            time_ms: u32 = u32,
        },
        CartesianMoveStart = CartesianMoveStart {
            moving_x: i8 = direction,
            moving_y: i8 = direction,
            moving_z: i8 = direction,
        },
        CartesianMoveStop = CartesianMoveStop,
        HardwareOperation = ExecuteHardwareOperation {
            subcommand: u16 = u16,
            reserved: u32 = u32,
            payload: Vec<u8> = rest,
        },
        GetSpeed = GetSpeed,
        SetSpeed = SetSpeed { speed: u8 = u8, },
        /// An empty `parent` means "the operator's default reference".
        SavePosition = SavePosition {
            name: String = name,
            anchor: bool = boolean,
            parent: String = parent,
        },
        DeletePosition = DeletePosition { name: String = name, },
        GoToPosition = GoToPosition { name: String = name, },
        SetPolarPosition = SetPolarPosition {
            name: String = name,
            delta: i32 = i32,
            azimuth: i32 = i32,
            radius: i32 = i32,
        },
        GetPolarPosition = GetPolarPosition { name: String = name, },
        SetCartesianPosition = SetCartesianPosition {
            name: String = name,
            x: i32 = i32,
            y: i32 = i32,
            z: i32 = i32,
        },
        GetCartesianPosition = GetCartesianPosition { name: String = name, },
    }
}

impl Request {
    /// The request as a frame with command id `id`.
    pub fn to_frame(&self, id: u32) -> Result<TalosFrame, EncodeError> {
        // One allocation for every jog's START and STOP (at most 27 bytes); a long name grows it.
        let mut payload = Vec::with_capacity(32);
        self.encode_payload(&mut payload)?;
        framed(id, self.command().request_value(), payload)
    }

    /// Reads a request frame. The reply bit must be clear.
    pub fn from_frame(frame: &TalosFrame) -> Result<Request, DecodeError> {
        let command = CommandValue::from_request_value(frame.command)
            .ok_or(DecodeError::UnknownCommand(frame.command))?;
        Self::decode_payload(command, &frame.payload)
    }
}
