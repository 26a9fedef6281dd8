//! Typed requests, one variant per ICD command ("Send" tables). Names and directions are carried
//! raw so encoding can refuse a bad one naming its field; decoding applies the same rules (a server
//! answers MALFORMED_PAYLOAD).

use super::command::CommandValue;
use super::frame::TalosFrame;
use super::message::{DecodeError, EncodeError, FieldReader, framed};
use super::name::PositionName;

/// One request, as the ICD's "Send" tables define it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Request {
    /// The ICD sends a 2-byte OID; deployed clients (talos-rit/commander, the old operator's
    /// interfaces) send an empty payload, decoded as `oid: None`. armjog's client always sends
    /// `Some` (the ICD layout); `None` encodes as the empty payload it came from.
    Handshake {
        oid: Option<u16>,
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

    /// The payload bytes, validating names and directions.
    pub fn encode_payload(&self, out: &mut Vec<u8>) -> Result<(), EncodeError> {
        match self {
            Request::Handshake { oid } => {
                if let Some(oid) = oid {
                    out.extend_from_slice(&oid.to_be_bytes());
                }
            }
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
    pub fn to_frame(&self, id: u32) -> Result<TalosFrame, EncodeError> {
        let mut payload = Vec::with_capacity(self.payload_capacity());
        self.encode_payload(&mut payload)?;
        framed(id, self.command().request_value(), payload)
    }

    /// Reads a request frame. The reply bit must be clear.
    pub fn from_frame(frame: &TalosFrame) -> Result<Request, DecodeError> {
        let command = CommandValue::from_request_value(frame.command)
            .ok_or(DecodeError::UnknownCommand(frame.command))?;
        Self::decode_payload(command, &frame.payload)
    }

    pub fn decode_payload(command: CommandValue, payload: &[u8]) -> Result<Request, DecodeError> {
        use CommandValue as C;
        let mut r = FieldReader::new(command, payload);
        let request = match command {
            // Be liberal: the empty handshake of deployed clients is a handshake without an OID.
            C::Handshake => Request::Handshake {
                oid: if payload.is_empty() {
                    None
                } else {
                    Some(r.u16("oid")?)
                },
            },
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
