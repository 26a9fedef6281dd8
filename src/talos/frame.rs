//! The ICD's command wrapper and a streaming codec for it.
//!
//! ```text
//! Command ID u32 | RESERVED u16 | Command Value u16 | Length u16 | Payload [Length] | Checksum
//! ```
//! All big-endian. The checksum field is 2 bytes (`crc16`, `none`) or 1 byte (`xor8`), see
//! [`Checksum`].
//!
//! The wrapper has no sync marker, so resynchronisation after garbage or a corrupt frame is a
//! search: drop one byte and try to parse again. While searching, only plausible positions count
//! as frame starts: a command value in the ICD with a length the ICD allows for it. At a clean
//! frame boundary the decoder keeps any frame whose Length is within the payload bound, whatever
//! its command value, until it is complete and its checksum decides; so a frame with an unknown
//! command or a wrong payload length reaches the server (which answers "unknown command" or
//! "malformed payload") however TCP split it into reads. A header that announces more than ever
//! comes is not the codec's to time out: the reader gives each frame a deadline and calls
//! [`FrameCodec::expire`] (see `FrameReader` in `src/net/`).

use std::fmt;
use std::time::Duration;

use super::checksum::Checksum;
use super::command::{CommandValue, REPLY_BIT};

/// Bytes before the payload: id (4), reserved (2), command value (2), length (2).
pub const HEADER_LEN: usize = 10;

/// Largest payload the decoder accepts by default. The largest frame armjog defines (Save
/// Position with two 255-byte names, or all-joint hardware feedback) is well below it.
pub const DEFAULT_MAX_PAYLOAD: usize = 1024;

/// One frame, request or reply, as on the wire.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TalosFrame {
    pub id: u32,
    pub reserved: u16,
    pub command: u16,
    pub payload: Vec<u8>,
}

/// The parts of a header that identify an exchange, kept with a rejection so a server can still
/// answer a frame whose checksum failed.
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
        let sum = checksum.compute(&out[start..]);
        match checksum.len() {
            1 => out.push(sum as u8),
            _ => out.extend_from_slice(&sum.to_be_bytes()),
        }
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
    /// A command value the ICD does not define cannot start a frame while resynchronising (or
    /// with no checksum to trust).
    #[error("command value 0x{value:04X} is not in the ICD")]
    UnknownCommand { value: u16 },
    /// The Length field is not one the ICD allows for the command value: not a frame start
    /// while resynchronising (or with no checksum to trust).
    #[error("length {length} is not one the ICD allows for command value 0x{command:04X}")]
    ImplausibleLength { command: u16, length: u16 },
    /// The stream ended inside a frame.
    #[error("stream ended inside a frame ({have} of {needed} bytes)")]
    Truncated { have: usize, needed: usize },
    /// A frame begun `after` ago was still incomplete at its deadline: the peer announced more
    /// bytes than it sent (or sends them too slowly).
    #[error("frame incomplete after {after:?} ({have} of {needed} bytes): given up")]
    Stalled {
        have: usize,
        needed: usize,
        after: Duration,
    },
}

/// Bytes the decoder dropped: the reason found at the first bad position, how many bytes were
/// skipped before the next valid frame (or the end of what was buffered), and the header found at
/// the first bad position if it was a complete frame (or, for [`RejectReason::Stalled`], the
/// unverified header of the frame that never completed).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rejection {
    pub reason: RejectReason,
    pub discarded: usize,
    pub header: Option<FrameHeader>,
    /// Another checksum dialect under which the first dropped bytes are one valid frame: what
    /// the peer most likely speaks. Looked for only at a clean frame boundary.
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
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ChecksumFit {
    /// The dialect the decoder was told to use.
    pub used: Checksum,
    /// The dialect the bytes fit.
    pub fits: Checksum,
}

impl fmt::Display for ChecksumFit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "checksum fails {} but fits {}",
            self.used.as_str(),
            self.fits.as_str()
        )
    }
}

/// Which checksum dialect other than `used` makes `bytes` start with one complete frame whose
/// checksum field checks out. `none` fits only a field of two zero bytes (it verifies nothing).
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

/// Parses one frame at the start of `buf`.
///
/// `strict` (set while resynchronising, and always for the `none` checksum, which cannot tell a
/// frame from noise) only accepts command values the ICD defines, with a payload length the ICD
/// allows for them. Otherwise any header whose Length is within `max_payload` is waited for and
/// the checksum decides, so the server can answer "unknown command" or "malformed payload" for a
/// frame whichever way it was split into reads.
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
