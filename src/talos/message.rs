//! Typed requests and replies, one variant per ICD command and reply (fields in snake_case). This
//! module holds what [`Request`] and [`Reply`] share: errors and the field reader that names the
//! command and field a payload fails on.

use super::command::CommandValue;
use super::frame::TalosFrame;
use super::name::{NameError, PositionName};
use super::reader::{BeReader, Short};

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
    pub(super) fn parent(&mut self) -> Result<String, DecodeError> {
        let raw = self.bytes_of_len("parent")?;
        if raw.is_empty() {
            return Ok(String::new());
        }
        self.position_name("parent", raw)
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

    pub(super) fn rest(&mut self) -> Vec<u8> {
        self.bytes.rest().to_vec()
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
