//! Typed requests and replies, one variant per ICD command and reply (fields in snake_case). This
//! module holds what [`Request`] and [`Reply`] share: the `talos_message!` that declares each,
//! errors, and each wire type's writer (`put`) and reader (`FieldReader`, which names the
//! command and field a payload fails on).

use super::command::CommandValue;
use super::frame::TalosFrame;
use super::name::{NameError, PositionName};
use super::reader::{BeReader, Short};
use super::return_code::ReturnCode;

pub use super::reply::Reply;
pub use super::request::Request;

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

/// `payload` as a frame, unless it is longer than the u16 Length field can say.
pub(super) fn framed(id: u32, command: u16, payload: Vec<u8>) -> Result<TalosFrame, EncodeError> {
    match payload.len() > usize::from(u16::MAX) {
        true => Err(EncodeError::TooLong(payload.len())),
        false => Ok(TalosFrame::new(id, command, payload)),
    }
}

/// Defines a request or reply enum, one variant per ICD command (`Variant = Command { fields }`),
/// with its `command()` and its fields written and read in wire order. Each field names its wire
/// type: the [`put`] function that writes it and the [`FieldReader`] method that reads it.
macro_rules! talos_message {
    (
        $(#[$meta:meta])*
        pub enum $name:ident {
            $(
                $(#[$variant_meta:meta])*
                $variant:ident = $command:ident $({
                    $($(#[$field_meta:meta])* $field:ident: $ty:ty = $wire:ident,)*
                })?,
            )*
        }
    ) => {
        $(#[$meta])*
        pub enum $name {
            $($(#[$variant_meta])* $variant $({ $($(#[$field_meta])* $field: $ty,)* })?,)*
        }

        impl $name {
            pub fn command(&self) -> CommandValue {
                match self {
                    $($name::$variant { .. } => CommandValue::$command,)*
                }
            }

            /// The payload bytes in wire order, each field checked as its wire type requires.
            pub fn encode_payload(&self, out: &mut Vec<u8>) -> Result<(), EncodeError> {
                match self {
                    $($name::$variant $({ $($field,)* })? => {
                        $($($crate::talos::message::put::$wire(out, stringify!($field), $field)?;)*)?
                    })*
                }
                Ok(())
            }

            /// `command`'s message from its payload, every byte used.
            pub fn decode_payload(command: CommandValue, payload: &[u8]) -> Result<Self, DecodeError> {
                Self::decode_fields(command, payload, false)
            }

            /// As `decode_payload`; `zero_fill` reads fields past the end as zero.
            fn decode_fields(
                command: CommandValue,
                payload: &[u8],
                zero_fill: bool,
            ) -> Result<Self, DecodeError> {
                let mut r = FieldReader::new(command, payload);
                r.zero_fill = zero_fill;
                let message = match command {
                    $(CommandValue::$command => $name::$variant $({
                        $($field: r.$wire(stringify!($field))?,)*
                    })?,)*
                };
                r.finish()?;
                Ok(message)
            }
        }
    };
}
pub(super) use talos_message;

/// The writers of the wire types [`talos_message`] names, each the twin of a [`FieldReader`] method.
pub(super) mod put {
    use super::EncodeError;
    use crate::talos::name::PositionName;
    use crate::talos::return_code::ReturnCode;

    type Put = Result<(), EncodeError>;

    pub fn u8(out: &mut Vec<u8>, _: &str, value: &u8) -> Put {
        out.push(*value);
        Ok(())
    }

    pub fn u16(out: &mut Vec<u8>, _: &str, value: &u16) -> Put {
        out.extend_from_slice(&value.to_be_bytes());
        Ok(())
    }

    pub fn u32(out: &mut Vec<u8>, _: &str, value: &u32) -> Put {
        out.extend_from_slice(&value.to_be_bytes());
        Ok(())
    }

    pub fn i32(out: &mut Vec<u8>, _: &str, value: &i32) -> Put {
        out.extend_from_slice(&value.to_be_bytes());
        Ok(())
    }

    pub fn return_code(out: &mut Vec<u8>, field: &str, value: &ReturnCode) -> Put {
        u16(out, field, &value.0)
    }

    /// The ICD's OID, or nothing for a handshake that came without one.
    pub fn oid(out: &mut Vec<u8>, field: &str, value: &Option<u16>) -> Put {
        value.as_ref().map_or(Ok(()), |oid| u16(out, field, oid))
    }

    pub fn direction(out: &mut Vec<u8>, field: &'static str, value: &i8) -> Put {
        if !(-1..=1).contains(value) {
            return Err(EncodeError::Direction {
                field,
                value: *value,
            });
        }
        out.push(*value as u8);
        Ok(())
    }

    pub fn boolean(out: &mut Vec<u8>, _: &str, value: &bool) -> Put {
        out.push(u8::from(*value));
        Ok(())
    }

    pub fn name(out: &mut Vec<u8>, field: &'static str, name: &str) -> Put {
        PositionName::validate(name.as_bytes())
            .map_err(|reason| EncodeError::Name { field, reason })?;
        // validate() bounds the length to 1..=255.
        out.push(name.len() as u8);
        out.extend_from_slice(name.as_bytes());
        Ok(())
    }

    /// Parent names may be empty (length 0): "use the operator's default".
    pub fn parent(out: &mut Vec<u8>, field: &'static str, parent: &str) -> Put {
        match parent.is_empty() {
            true => u8(out, field, &0),
            false => name(out, field, parent),
        }
    }

    pub fn rest(out: &mut Vec<u8>, _: &str, bytes: &[u8]) -> Put {
        out.extend_from_slice(bytes);
        Ok(())
    }
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

/// The shared reader, with the command for errors ([`DecodeError::Truncated`] names the field).
pub(super) struct FieldReader<'a> {
    command: CommandValue,
    bytes: BeReader<'a>,
    /// Read missing fields as zero (bare error replies).
    pub(super) zero_fill: bool,
}

impl<'a> FieldReader<'a> {
    pub(super) fn new(command: CommandValue, bytes: &'a [u8]) -> Self {
        FieldReader {
            command,
            bytes: BeReader::new(bytes),
            zero_fill: false,
        }
    }

    pub(super) fn is_empty(&self) -> bool {
        self.bytes.is_empty()
    }

    /// `read` from the payload, or zero once a bare error reply has run out.
    fn field<T: Default>(
        &mut self,
        read: impl FnOnce(&mut BeReader<'a>) -> Result<T, Short>,
    ) -> Result<T, DecodeError> {
        if self.zero_fill && self.bytes.is_empty() {
            return Ok(T::default());
        }
        read(&mut self.bytes).map_err(|short| self.truncated(short))
    }

    fn truncated(&self, short: Short) -> DecodeError {
        DecodeError::Truncated {
            command: self.command,
            field: short.field,
        }
    }

    /// A reply's return code. A failed operator may send it bare: the other fields read as zero.
    pub(super) fn return_code(&mut self, field: &'static str) -> Result<ReturnCode, DecodeError> {
        let code = ReturnCode(self.u16(field)?);
        self.zero_fill |= !code.is_ok() && self.is_empty();
        Ok(code)
    }

    /// Be liberal: the empty handshake of deployed clients is a handshake without an OID.
    pub(super) fn oid(&mut self, field: &'static str) -> Result<Option<u16>, DecodeError> {
        match self.is_empty() {
            true => Ok(None),
            false => self.u16(field).map(Some),
        }
    }

    pub(super) fn u8(&mut self, field: &'static str) -> Result<u8, DecodeError> {
        self.field(|r| r.u8(field))
    }

    pub(super) fn u16(&mut self, field: &'static str) -> Result<u16, DecodeError> {
        self.field(|r| r.u16(field))
    }

    pub(super) fn u32(&mut self, field: &'static str) -> Result<u32, DecodeError> {
        self.field(|r| r.u32(field))
    }

    pub(super) fn i32(&mut self, field: &'static str) -> Result<i32, DecodeError> {
        self.field(|r| r.i32(field))
    }

    pub(super) fn direction(&mut self, field: &'static str) -> Result<i8, DecodeError> {
        let value = self.field(|r| r.i8(field))?;
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

    pub(super) fn boolean(&mut self, field: &'static str) -> Result<bool, DecodeError> {
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

    /// A length byte, then that many bytes; both count as `field`.
    fn bytes_of_len(&mut self, field: &'static str) -> Result<&'a [u8], DecodeError> {
        let len = usize::from(self.u8(field)?);
        self.bytes
            .slice(field, len)
            .map_err(|short| self.truncated(short))
    }

    pub(super) fn name(&mut self, field: &'static str) -> Result<String, DecodeError> {
        let raw = self.bytes_of_len(field)?;
        self.position_name(field, raw)
    }

    /// Like `name`, but empty is allowed: "the operator's default reference".
    pub(super) fn parent(&mut self, field: &'static str) -> Result<String, DecodeError> {
        let raw = self.bytes_of_len(field)?;
        if raw.is_empty() {
            return Ok(String::new());
        }
        self.position_name(field, raw)
    }

    fn position_name(&self, field: &'static str, raw: &[u8]) -> Result<String, DecodeError> {
        PositionName::from_bytes(raw)
            .map(PositionName::into_string)
            .map_err(|reason| DecodeError::Name {
                command: self.command,
                field,
                reason,
            })
    }

    /// The bytes left; never fails (a `Result` as every field's read is).
    pub(super) fn rest(&mut self, _: &'static str) -> Result<Vec<u8>, DecodeError> {
        Ok(self.bytes.rest().to_vec())
    }

    /// Ok when every byte was read; otherwise the count left over.
    pub(super) fn finish(self) -> Result<(), DecodeError> {
        match self.bytes.remaining() {
            0 => Ok(()),
            count => Err(DecodeError::TrailingBytes {
                command: self.command,
                count,
            }),
        }
    }
}
