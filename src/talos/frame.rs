//! The ICD's command wrapper and a streaming codec for it.
//!
//! ```text
//! Command ID u32 | RESERVED u16 | Command Value u16 | Length u16 | Payload [Length] | Checksum
//! ```
//! All big-endian; the checksum is 2 bytes (`crc16`, `none`) or 1 (`xor8`), see [`Checksum`].
//!
//! There is no sync marker, so resynchronising is a search, counting only plausible frame starts
//! (an ICD command with an allowed length). At a clean boundary any frame within the payload bound
//! is awaited and its checksum decides, so an unknown command or a bad length reaches the server
//! however TCP split it. Timing a frame out is the reader's ([`FrameCodec::expire`]).

use std::fmt;
use std::time::Duration;

use super::checksum::Checksum;
use super::command::{CommandValue, REPLY_BIT};

/// Bytes before the payload: id (4), reserved (2), command value (2), length (2).
pub const HEADER_LEN: usize = 10;

/// Largest payload decoded by default, well above armjog's largest frame.
pub const DEFAULT_MAX_PAYLOAD: usize = 1024;

/// One frame, request or reply, as on the wire.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TalosFrame {
    pub id: u32,
    pub reserved: u16,
    pub command: u16,
    pub payload: Vec<u8>,
}

/// A header's exchange fields, kept with a rejection so a bad frame can still be answered.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FrameHeader {
    pub id: u32,
    pub command: u16,
    pub length: u16,
}

impl TalosFrame {
    pub fn new(id: u32, command: u16, payload: Vec<u8>) -> Self {
        TalosFrame {
            id,
            reserved: 0,
            command,
            payload,
        }
    }

    pub fn is_reply(&self) -> bool {
        self.command & REPLY_BIT != 0
    }

    /// The command this frame carries, if the ICD defines its value.
    pub fn command_value(&self) -> Option<CommandValue> {
        if self.is_reply() {
            CommandValue::from_reply_value(self.command)
        } else {
            CommandValue::from_request_value(self.command)
        }
    }

    /// Number of bytes [`TalosFrame::encode_into`] writes.
    pub fn encoded_len(&self, checksum: Checksum) -> usize {
        HEADER_LEN + self.payload.len() + checksum.len()
    }

    /// Appends the frame's bytes to `out`. Fails only if the payload exceeds the u16 length field.
    pub fn encode_into(&self, checksum: Checksum, out: &mut Vec<u8>) -> Result<(), FrameTooLong> {
        let length = u16::try_from(self.payload.len()).map_err(|_| FrameTooLong {
            length: self.payload.len(),
        })?;
        let start = out.len();
        out.reserve(self.encoded_len(checksum));
        out.extend_from_slice(&self.id.to_be_bytes());
        out.extend_from_slice(&self.reserved.to_be_bytes());
        out.extend_from_slice(&self.command.to_be_bytes());
        out.extend_from_slice(&length.to_be_bytes());
        out.extend_from_slice(&self.payload);
        checksum.append(out, start);
        Ok(())
    }

    pub fn to_bytes(&self, checksum: Checksum) -> Result<Vec<u8>, FrameTooLong> {
        let mut out = Vec::with_capacity(self.encoded_len(checksum));
        self.encode_into(checksum, &mut out)?;
        Ok(out)
    }
}

/// A payload longer than the ICD's u16 Length field can describe.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("payload of {length} bytes does not fit the u16 Length field")]
pub struct FrameTooLong {
    pub length: usize,
}

/// Why bytes were discarded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum RejectReason {
    /// The frame was complete but its checksum field did not match.
    #[error("bad checksum: computed 0x{expected:04X}, frame carries 0x{found:04X}")]
    BadChecksum { expected: u16, found: u16 },
    /// The Length field is above the decoder's bound.
    #[error("length {length} exceeds the {max}-byte payload bound")]
    OversizedLength { length: u16, max: usize },
    /// An undefined command cannot start a frame while resynchronising (or without a checksum).
    #[error("command value 0x{value:04X} is not in the ICD")]
    UnknownCommand { value: u16 },
    /// A length the ICD does not allow for the command: no frame start while resynchronising.
    #[error("length {length} is not one the ICD allows for command value 0x{command:04X}")]
    ImplausibleLength { command: u16, length: u16 },
    /// The stream ended inside a frame.
    #[error("stream ended inside a frame ({have} of {needed} bytes)")]
    Truncated { have: usize, needed: usize },
    /// A frame begun `after` ago was incomplete at its deadline.
    #[error("frame incomplete after {after:?} ({have} of {needed} bytes): given up")]
    Stalled {
        have: usize,
        needed: usize,
        after: Duration,
    },
}

/// Bytes the decoder dropped: the reason at the first bad position, how many were skipped, and that
/// position's header if it was a complete frame (for [`RejectReason::Stalled`], the unverified
/// header of the frame that never completed).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rejection {
    pub reason: RejectReason,
    pub discarded: usize,
    pub header: Option<FrameHeader>,
    /// Another checksum under which the dropped bytes are a frame (looked for at a clean boundary).
    pub fits: Option<ChecksumFit>,
}

impl fmt::Display for Rejection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} ({} bytes discarded)", self.reason, self.discarded)?;
        if let Some(fit) = self.fits {
            write!(f, "; {fit}")?;
        }
        Ok(())
    }
}

/// A frame that fails the link's checksum dialect but is valid under another.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("checksum fails {} but fits {}", .used.as_str(), .fits.as_str())]
pub struct ChecksumFit {
    /// The dialect the decoder was told to use.
    pub used: Checksum,
    /// The dialect the bytes fit.
    pub fits: Checksum,
}

/// The checksum other than `used` under which `bytes` start a valid frame (`none`: two zeros).
pub fn checksum_that_fits(bytes: &[u8], used: Checksum, max_payload: usize) -> Option<ChecksumFit> {
    Checksum::ALL
        .into_iter()
        .filter(|c| *c != used)
        .find(|c| match parse_frame(bytes, *c, max_payload, false) {
            Parse::Complete(_, len) => {
                *c != Checksum::None || bytes.get(len.saturating_sub(2)..len) == Some(&[0, 0])
            }
            _ => false,
        })
        .map(|fits| ChecksumFit { used, fits })
}

/// What the decoder yields: a frame, or a report of bytes it had to drop.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Decoded {
    TalosFrame(TalosFrame),
    Rejected(Rejection),
}

/// Result of parsing at the start of a buffer.
#[derive(Debug, PartialEq, Eq)]
pub enum Parse {
    /// A frame and the number of bytes it took.
    Complete(TalosFrame, usize),
    /// Not enough bytes yet; at least this many are needed in all.
    Incomplete(usize),
    /// No frame starts here.
    Invalid(RejectReason, Option<FrameHeader>),
}

fn header_at(buf: &[u8]) -> Option<FrameHeader> {
    let h: &[u8; HEADER_LEN] = buf.get(..HEADER_LEN)?.try_into().ok()?;
    Some(FrameHeader {
        id: u32::from_be_bytes([h[0], h[1], h[2], h[3]]),
        command: u16::from_be_bytes([h[6], h[7]]),
        length: u16::from_be_bytes([h[8], h[9]]),
    })
}

/// Parses one frame at the start of `buf`. `strict` (while resynchronising, and always for the
/// `none` checksum, which cannot tell a frame from noise) accepts only ICD commands with allowed
/// lengths; otherwise any length within `max_payload` is awaited and the checksum decides.
pub fn parse_frame(buf: &[u8], checksum: Checksum, max_payload: usize, strict: bool) -> Parse {
    let Some(header) = header_at(buf) else {
        return Parse::Incomplete(HEADER_LEN);
    };
    let strict = strict || checksum == Checksum::None;
    if strict && !CommandValue::is_plausible(header.command, usize::from(header.length)) {
        return Parse::Invalid(implausible(header), None);
    }
    if usize::from(header.length) > max_payload {
        let reason = RejectReason::OversizedLength {
            length: header.length,
            max: max_payload,
        };
        return Parse::Invalid(reason, Some(header));
    }
    let body_end = HEADER_LEN + usize::from(header.length);
    let total = body_end + checksum.len();
    let Some(field) = buf.get(body_end..total) else {
        return Parse::Incomplete(total);
    };
    let covered = &buf[..body_end];
    let found = checksum.read_field(field);
    if !checksum.verify(covered, found) {
        let reason = RejectReason::BadChecksum {
            expected: checksum.compute(covered),
            found,
        };
        return Parse::Invalid(reason, Some(header));
    }
    let frame = TalosFrame {
        id: header.id,
        reserved: u16::from_be_bytes([buf[4], buf[5]]),
        command: header.command,
        payload: buf[HEADER_LEN..body_end].to_vec(),
    };
    Parse::Complete(frame, total)
}

fn implausible(header: FrameHeader) -> RejectReason {
    if CommandValue::is_known_value(header.command) {
        RejectReason::ImplausibleLength {
            command: header.command,
            length: header.length,
        }
    } else {
        RejectReason::UnknownCommand {
            value: header.command,
        }
    }
}

/// Reading frames from a byte stream, resynchronising after garbage, and writing them.
mod codec;

pub use codec::FrameCodec;
