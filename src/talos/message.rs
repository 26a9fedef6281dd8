//! Typed requests and replies: one variant per ICD command and per reply.
//!
//! Field names follow the ICD in snake_case. Names and directions are carried raw so that
//! encoding can refuse a bad one with the field it came from; decoding applies the same rules,
//! so a server can answer MALFORMED_PAYLOAD.
//!
//! Error replies: armjog always sends a reply's full fixed layout, zeroing the fields after a
//! non-zero return code. When decoding, a reply whose return code is non-zero may also be just
//! the 2-byte return code (the other fields then read as zero), because an operator that failed
//! has nothing to put in them.

use serde::Serialize;

use super::command::CommandValue;
use super::frame::Frame;
use super::name::{NameError, PositionName};
use super::return_code::ReturnCode;

/// One request, as the ICD's "Send" tables define it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Request {
    Handshake {
        oid: u16,
    },
    PolarPan {
        delta_azimuth: i32,
        delta_altitude: i32,
        delay_ms: u32,
        time_ms: u32,
    },
    Home {
        delay_ms: u32,
    },
    PolarPanStart {
        moving_azimuth: i8,
        moving_altitude: i8,
    },
    PolarPanStop,
    CartesianMove {
        delta_x: i32,
        delta_y: i32,
        delta_z: i32,
        delay_ms: u32,
        time_ms: u32,
    },
    CartesianMoveStart {
        moving_x: i8,
        moving_y: i8,
        moving_z: i8,
    },
    CartesianMoveStop,
    HardwareOperation {
        subcommand: u16,
        reserved: u32,
        payload: Vec<u8>,
    },
    GetSpeed,
    SetSpeed {
        speed: u8,
    },
    /// An empty `parent` means "the operator's default reference".
    SavePosition {
        name: String,
        anchor: bool,
        parent: String,
    },
    DeletePosition {
        name: String,
    },
    GoToPosition {
        name: String,
    },
    SetPolarPosition {
        name: String,
        delta: i32,
        azimuth: i32,
        radius: i32,
    },
    GetPolarPosition {
        name: String,
    },
    SetCartesianPosition {
        name: String,
        x: i32,
        y: i32,
        z: i32,
    },
    GetCartesianPosition {
        name: String,
    },
}

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

/// A request or reply that cannot be encoded. Says which field.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum EncodeError {
    #[error("{field}: direction {value} is outside -1..=1")]
    Direction { field: &'static str, value: i8 },
    #[error("{field}: name {reason}")]
    Name {
        field: &'static str,
        reason: NameError,
    },
    #[error("payload of {0} bytes does not fit the u16 Length field")]
    TooLong(usize),
}

/// A frame whose payload does not match the ICD. Says which command and field.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DecodeError {
    #[error("command value 0x{0:04X} is not in the ICD")]
    UnknownCommand(u16),
    #[error("{command}: payload ends inside field {field}")]
    Truncated {
        command: CommandValue,
        field: &'static str,
    },
    #[error("{command}: {count} unexpected bytes after the last field")]
    TrailingBytes { command: CommandValue, count: usize },
    #[error("{command}: {field}: direction {value} is outside -1..=1")]
    Direction {
        command: CommandValue,
        field: &'static str,
        value: i8,
    },
    #[error("{command}: {field}: boolean byte 0x{value:02X} is neither 0x00 nor 0x01")]
    Boolean {
        command: CommandValue,
        field: &'static str,
        value: u8,
    },
    #[error("{command}: {field}: name {reason}")]
    Name {
        command: CommandValue,
        field: &'static str,
        reason: NameError,
    },
}

fn check_direction(field: &'static str, value: i8) -> Result<i8, EncodeError> {
    if (-1..=1).contains(&value) {
        Ok(value)
    } else {
        Err(EncodeError::Direction { field, value })
    }
}

fn put_name(out: &mut Vec<u8>, field: &'static str, name: &str) -> Result<(), EncodeError> {
    PositionName::validate(name.as_bytes())
        .map_err(|reason| EncodeError::Name { field, reason })?;
    // validate() bounds the length to 1..=255.
    out.push(name.len() as u8);
    out.extend_from_slice(name.as_bytes());
    Ok(())
}

/// Parent names may be empty (length 0): "use the operator's default".
fn put_parent(out: &mut Vec<u8>, parent: &str) -> Result<(), EncodeError> {
    if parent.is_empty() {
        out.push(0);
        Ok(())
    } else {
        put_name(out, "parent", parent)
    }
}

impl Request {
    pub fn command(&self) -> CommandValue {
        use CommandValue as C;
        match self {
            Request::Handshake { .. } => C::Handshake,
            Request::PolarPan { .. } => C::PolarPanDiscrete,
            Request::Home { .. } => C::Home,
            Request::PolarPanStart { .. } => C::PolarPanStart,
            Request::PolarPanStop => C::PolarPanStop,
            Request::CartesianMove { .. } => C::CartesianMoveDiscrete,
            Request::CartesianMoveStart { .. } => C::CartesianMoveStart,
            Request::CartesianMoveStop => C::CartesianMoveStop,
            Request::HardwareOperation { .. } => C::ExecuteHardwareOperation,
            Request::GetSpeed => C::GetSpeed,
            Request::SetSpeed { .. } => C::SetSpeed,
            Request::SavePosition { .. } => C::SavePosition,
            Request::DeletePosition { .. } => C::DeletePosition,
            Request::GoToPosition { .. } => C::GoToPosition,
            Request::SetPolarPosition { .. } => C::SetPolarPosition,
            Request::GetPolarPosition { .. } => C::GetPolarPosition,
            Request::SetCartesianPosition { .. } => C::SetCartesianPosition,
            Request::GetCartesianPosition { .. } => C::GetCartesianPosition,
        }
    }

    /// Whether this request stops motion. A link never holds such a request back.
    pub fn is_stop(&self) -> bool {
        matches!(self, Request::PolarPanStop | Request::CartesianMoveStop)
    }

    /// The payload bytes, validating names and directions.
    pub fn encode_payload(&self, out: &mut Vec<u8>) -> Result<(), EncodeError> {
        match self {
            Request::Handshake { oid } => out.extend_from_slice(&oid.to_be_bytes()),
            Request::PolarPan {
                delta_azimuth,
                delta_altitude,
                delay_ms,
                time_ms,
            } => {
                out.extend_from_slice(&delta_azimuth.to_be_bytes());
                out.extend_from_slice(&delta_altitude.to_be_bytes());
                out.extend_from_slice(&delay_ms.to_be_bytes());
                out.extend_from_slice(&time_ms.to_be_bytes());
            }
            Request::Home { delay_ms } => out.extend_from_slice(&delay_ms.to_be_bytes()),
            Request::PolarPanStart {
                moving_azimuth,
                moving_altitude,
            } => {
                out.push(check_direction("moving_azimuth", *moving_azimuth)? as u8);
                out.push(check_direction("moving_altitude", *moving_altitude)? as u8);
            }
            Request::PolarPanStop | Request::CartesianMoveStop | Request::GetSpeed => {}
            Request::CartesianMove {
                delta_x,
                delta_y,
                delta_z,
                delay_ms,
                time_ms,
            } => {
                for v in [delta_x, delta_y, delta_z] {
                    out.extend_from_slice(&v.to_be_bytes());
                }
                out.extend_from_slice(&delay_ms.to_be_bytes());
                out.extend_from_slice(&time_ms.to_be_bytes());
            }
            Request::CartesianMoveStart {
                moving_x,
                moving_y,
                moving_z,
            } => {
                out.push(check_direction("moving_x", *moving_x)? as u8);
                out.push(check_direction("moving_y", *moving_y)? as u8);
                out.push(check_direction("moving_z", *moving_z)? as u8);
            }
            Request::HardwareOperation {
                subcommand,
                reserved,
                payload,
            } => {
                out.extend_from_slice(&subcommand.to_be_bytes());
                out.extend_from_slice(&reserved.to_be_bytes());
                out.extend_from_slice(payload);
            }
            Request::SetSpeed { speed } => out.push(*speed),
            Request::SavePosition {
                name,
                anchor,
                parent,
            } => {
                put_name(out, "name", name)?;
                out.push(u8::from(*anchor));
                put_parent(out, parent)?;
            }
            Request::DeletePosition { name }
            | Request::GoToPosition { name }
            | Request::GetPolarPosition { name }
            | Request::GetCartesianPosition { name } => put_name(out, "name", name)?,
            Request::SetPolarPosition {
                name,
                delta,
                azimuth,
                radius,
            } => {
                put_name(out, "name", name)?;
                for v in [delta, azimuth, radius] {
                    out.extend_from_slice(&v.to_be_bytes());
                }
            }
            Request::SetCartesianPosition { name, x, y, z } => {
                put_name(out, "name", name)?;
                for v in [x, y, z] {
                    out.extend_from_slice(&v.to_be_bytes());
                }
            }
        }
        Ok(())
    }

    /// The payload's length, or an upper bound for the fixed layouts (to allocate once).
    fn payload_capacity(&self) -> usize {
        match self {
            Request::HardwareOperation { payload, .. } => 6 + payload.len(),
            Request::SavePosition { name, parent, .. } => 3 + name.len() + parent.len(),
            Request::DeletePosition { name }
            | Request::GoToPosition { name }
            | Request::GetPolarPosition { name }
            | Request::GetCartesianPosition { name } => 1 + name.len(),
            Request::SetPolarPosition { name, .. } | Request::SetCartesianPosition { name, .. } => {
                13 + name.len()
            }
            _ => 20,
        }
    }

    /// The request as a frame with command id `id`.
    pub fn to_frame(&self, id: u32) -> Result<Frame, EncodeError> {
        let mut payload = Vec::with_capacity(self.payload_capacity());
        self.encode_payload(&mut payload)?;
        if payload.len() > usize::from(u16::MAX) {
            return Err(EncodeError::TooLong(payload.len()));
        }
        Ok(Frame::new(id, self.command().request_value(), payload))
    }

    /// Reads a request frame. The reply bit must be clear.
    pub fn from_frame(frame: &Frame) -> Result<Request, DecodeError> {
        let command = CommandValue::from_request_value(frame.command)
            .ok_or(DecodeError::UnknownCommand(frame.command))?;
        Self::decode_payload(command, &frame.payload)
    }

    pub fn decode_payload(command: CommandValue, payload: &[u8]) -> Result<Request, DecodeError> {
        use CommandValue as C;
        let mut r = Reader::new(command, payload);
        let request = match command {
            C::Handshake => Request::Handshake { oid: r.u16("oid")? },
            C::PolarPanDiscrete => Request::PolarPan {
                delta_azimuth: r.i32("delta_azimuth")?,
                delta_altitude: r.i32("delta_altitude")?,
                delay_ms: r.u32("delay_ms")?,
                time_ms: r.u32("time_ms")?,
            },
            C::Home => Request::Home {
                delay_ms: r.u32("delay_ms")?,
            },
            C::PolarPanStart => Request::PolarPanStart {
                moving_azimuth: r.direction("moving_azimuth")?,
                moving_altitude: r.direction("moving_altitude")?,
            },
            C::PolarPanStop => Request::PolarPanStop,
            C::CartesianMoveDiscrete => Request::CartesianMove {
                delta_x: r.i32("delta_x")?,
                delta_y: r.i32("delta_y")?,
                delta_z: r.i32("delta_z")?,
                delay_ms: r.u32("delay_ms")?,
                time_ms: r.u32("time_ms")?,
            },
            C::CartesianMoveStart => Request::CartesianMoveStart {
                moving_x: r.direction("moving_x")?,
                moving_y: r.direction("moving_y")?,
                moving_z: r.direction("moving_z")?,
            },
            C::CartesianMoveStop => Request::CartesianMoveStop,
            C::ExecuteHardwareOperation => Request::HardwareOperation {
                subcommand: r.u16("subcommand")?,
                reserved: r.u32("reserved")?,
                payload: r.rest(),
            },
            C::GetSpeed => Request::GetSpeed,
            C::SetSpeed => Request::SetSpeed {
                speed: r.u8("speed")?,
            },
            C::SavePosition => Request::SavePosition {
                name: r.name("name")?,
                anchor: r.boolean("anchor")?,
                parent: r.parent()?,
            },
            C::DeletePosition => Request::DeletePosition {
                name: r.name("name")?,
            },
            C::GoToPosition => Request::GoToPosition {
                name: r.name("name")?,
            },
            C::SetPolarPosition => Request::SetPolarPosition {
                name: r.name("name")?,
                delta: r.i32("delta")?,
                azimuth: r.i32("azimuth")?,
                radius: r.i32("radius")?,
            },
            C::GetPolarPosition => Request::GetPolarPosition {
                name: r.name("name")?,
            },
            C::SetCartesianPosition => Request::SetCartesianPosition {
                name: r.name("name")?,
                x: r.i32("x")?,
                y: r.i32("y")?,
                z: r.i32("z")?,
            },
            C::GetCartesianPosition => Request::GetCartesianPosition {
                name: r.name("name")?,
            },
        };
        r.finish()?;
        Ok(request)
    }
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

    /// The reply to `command` carrying only a return code, every other field zero. This is how
    /// a server answers with an error.
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
    pub fn to_frame(&self, request_id: u32) -> Result<Frame, EncodeError> {
        let capacity = match self {
            Reply::HardwareOperation { payload, .. } => 4 + payload.len(),
            _ => 14,
        };
        let mut payload = Vec::with_capacity(capacity);
        self.encode_payload(&mut payload);
        if payload.len() > usize::from(u16::MAX) {
            return Err(EncodeError::TooLong(payload.len()));
        }
        Ok(Frame::new(
            request_id | 1,
            self.command().reply_value(),
            payload,
        ))
    }

    /// Reads a reply frame. The reply bit must be set.
    pub fn from_frame(frame: &Frame) -> Result<Reply, DecodeError> {
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
        let mut r = Reader::new(command, payload);
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

/// Big-endian field reader that names the field it failed on.
struct Reader<'a> {
    command: CommandValue,
    bytes: &'a [u8],
    /// Read missing fields as zero (bare error replies).
    zero_fill: bool,
}

impl<'a> Reader<'a> {
    fn new(command: CommandValue, bytes: &'a [u8]) -> Self {
        Reader {
            command,
            bytes,
            zero_fill: false,
        }
    }

    fn is_empty(&self) -> bool {
        self.bytes.is_empty()
    }

    fn take<const N: usize>(&mut self, field: &'static str) -> Result<[u8; N], DecodeError> {
        if self.zero_fill && self.bytes.is_empty() {
            return Ok([0; N]);
        }
        let (head, tail) = self
            .bytes
            .split_first_chunk::<N>()
            .ok_or(DecodeError::Truncated {
                command: self.command,
                field,
            })?;
        self.bytes = tail;
        Ok(*head)
    }

    fn u8(&mut self, field: &'static str) -> Result<u8, DecodeError> {
        Ok(self.take::<1>(field)?[0])
    }

    fn u16(&mut self, field: &'static str) -> Result<u16, DecodeError> {
        Ok(u16::from_be_bytes(self.take(field)?))
    }

    fn u32(&mut self, field: &'static str) -> Result<u32, DecodeError> {
        Ok(u32::from_be_bytes(self.take(field)?))
    }

    fn i32(&mut self, field: &'static str) -> Result<i32, DecodeError> {
        Ok(i32::from_be_bytes(self.take(field)?))
    }

    fn direction(&mut self, field: &'static str) -> Result<i8, DecodeError> {
        let value = self.take::<1>(field)?[0] as i8;
        if (-1..=1).contains(&value) {
            Ok(value)
        } else {
            Err(DecodeError::Direction {
                command: self.command,
                field,
                value,
            })
        }
    }

    fn boolean(&mut self, field: &'static str) -> Result<bool, DecodeError> {
        match self.u8(field)? {
            0 => Ok(false),
            1 => Ok(true),
            value => Err(DecodeError::Boolean {
                command: self.command,
                field,
                value,
            }),
        }
    }

    fn bytes_of_len(&mut self, field: &'static str) -> Result<&'a [u8], DecodeError> {
        let len = usize::from(self.u8(field)?);
        if self.bytes.len() < len {
            return Err(DecodeError::Truncated {
                command: self.command,
                field,
            });
        }
        let (head, tail) = self.bytes.split_at(len);
        self.bytes = tail;
        Ok(head)
    }

    fn name(&mut self, field: &'static str) -> Result<String, DecodeError> {
        let raw = self.bytes_of_len(field)?;
        PositionName::from_bytes(raw)
            .map(PositionName::into_string)
            .map_err(|reason| DecodeError::Name {
                command: self.command,
                field,
                reason,
            })
    }

    fn parent(&mut self) -> Result<String, DecodeError> {
        let raw = self.bytes_of_len("parent")?;
        if raw.is_empty() {
            return Ok(String::new());
        }
        PositionName::from_bytes(raw)
            .map(PositionName::into_string)
            .map_err(|reason| DecodeError::Name {
                command: self.command,
                field: "parent",
                reason,
            })
    }

    fn rest(&mut self) -> Vec<u8> {
        std::mem::take(&mut self.bytes).to_vec()
    }

    fn finish(self) -> Result<(), DecodeError> {
        if self.bytes.is_empty() {
            Ok(())
        } else {
            Err(DecodeError::TrailingBytes {
                command: self.command,
                count: self.bytes.len(),
            })
        }
    }
}
