//! The streaming codec: frames however TCP split them, and a report of every dropped run.

use bytes::{Buf, BytesMut};
use std::time::Duration;
use tokio_util::codec::{Decoder, Encoder};

use super::{
    ChecksumFit, DEFAULT_MAX_PAYLOAD, Decoded, FrameHeader, HEADER_LEN, Parse, RejectReason,
    Rejection, TalosFrame, checksum_that_fits, header_at, parse_frame,
};
use crate::talos::checksum::Checksum;

/// A `tokio_util` codec for Talos frames with one checksum dialect.
#[derive(Debug, Clone)]
pub struct FrameCodec {
    checksum: Checksum,
    max_payload: usize,
    /// False from a dropped byte to the next valid frame: only plausible starts count then.
    synced: bool,
    /// Bytes dropped since the last report.
    discarded: usize,
    /// The current dropped run's first reason and header, and the checksum it fits if not ours.
    first: Option<(RejectReason, Option<FrameHeader>, Option<ChecksumFit>)>,
}

impl FrameCodec {
    pub fn new(checksum: Checksum) -> Self {
        Self::with_max_payload(checksum, DEFAULT_MAX_PAYLOAD)
    }

    pub fn with_max_payload(checksum: Checksum, max_payload: usize) -> Self {
        FrameCodec {
            checksum,
            max_payload: max_payload.min(usize::from(u16::MAX)),
            synced: true,
            discarded: 0,
            first: None,
        }
    }

    /// Most bytes the decoder ever holds waiting for one frame.
    pub fn max_frame_len(&self) -> usize {
        HEADER_LEN + self.max_payload + self.checksum.len()
    }

    /// Gives up on the front frame, whose deadline passed: drops its first byte and every later one
    /// of the first `overdue` that does not start a complete frame, then resynchronises. Returns
    /// the dropped run ([`RejectReason::Stalled`]), or `None` if nothing was waiting.
    pub fn expire(
        &mut self,
        src: &mut BytesMut,
        overdue: usize,
        after: Duration,
    ) -> Option<Decoded> {
        let needed = match parse_frame(src, self.checksum, self.max_payload, !self.synced) {
            Parse::Incomplete(needed) if !src.is_empty() => needed,
            _ => return None,
        };
        let reason = RejectReason::Stalled {
            have: src.len(),
            needed,
            after,
        };
        self.drop_first_byte(src, reason, header_at(src));
        for _ in 1..overdue {
            let complete = matches!(
                parse_frame(src, self.checksum, self.max_payload, true),
                Parse::Complete(..)
            );
            if src.is_empty() || complete {
                break;
            }
            src.advance(1);
            self.discarded += 1;
        }
        self.decode_buffered(src)
    }

    /// The next buffered item, or `None` to wait: [`Decoder::decode`] without its error path.
    pub fn decode_buffered(&mut self, src: &mut BytesMut) -> Option<Decoded> {
        loop {
            match parse_frame(src, self.checksum, self.max_payload, !self.synced) {
                Parse::Complete(frame, used) => {
                    // Report the dropped run first; the frame stays buffered for the next call.
                    if let Some(rejection) = self.take_rejection() {
                        return Some(rejection);
                    }
                    self.synced = true;
                    src.advance(used);
                    return Some(Decoded::TalosFrame(frame));
                }
                Parse::Incomplete(needed) => {
                    if let Some(rejection) = self.take_rejection() {
                        return Some(rejection);
                    }
                    src.reserve(needed.saturating_sub(src.len()));
                    return None;
                }
                Parse::Invalid(reason, header) => self.drop_first_byte(src, reason, header),
            }
        }
    }

    fn take_rejection(&mut self) -> Option<Decoded> {
        let (reason, header, fits) = self.first.take()?;
        let discarded = std::mem::take(&mut self.discarded);
        Some(Decoded::Rejected(Rejection {
            reason,
            discarded,
            header,
            fits,
        }))
    }

    /// Drops `src`'s first byte, noting why if it begins a dropped run.
    fn drop_first_byte(&mut self, src: &mut BytesMut, why: RejectReason, at: Option<FrameHeader>) {
        if self.first.is_none() {
            // Only a clean frame boundary is worth a second look under the other checksums.
            let fits = self
                .synced
                .then(|| checksum_that_fits(src, self.checksum, self.max_payload));
            self.first = Some((why, at, fits.flatten()));
        }
        self.synced = false;
        src.advance(1);
        self.discarded += 1;
    }
}

impl Decoder for FrameCodec {
    type Item = Decoded;
    type Error = std::io::Error;

    fn decode(&mut self, src: &mut BytesMut) -> Result<Option<Decoded>, Self::Error> {
        Ok(self.decode_buffered(src))
    }

    fn decode_eof(&mut self, src: &mut BytesMut) -> Result<Option<Decoded>, Self::Error> {
        if let Some(item) = self.decode(src)? {
            return Ok(Some(item));
        }
        if src.is_empty() {
            return Ok(None);
        }
        let needed = match parse_frame(src, self.checksum, self.max_payload, false) {
            Parse::Incomplete(needed) => needed,
            _ => src.len(),
        };
        let have = src.len();
        // Its header may be garbage: drop up to where a frame parses.
        let discarded = (1..have)
            .find(|&at| {
                matches!(
                    parse_frame(&src[at..], self.checksum, self.max_payload, true),
                    Parse::Complete(..)
                )
            })
            .unwrap_or(have);
        src.advance(discarded);
        self.synced = false;
        Ok(Some(Decoded::Rejected(Rejection {
            reason: RejectReason::Truncated { have, needed },
            discarded,
            header: None,
            fits: None,
        })))
    }
}

impl Encoder<TalosFrame> for FrameCodec {
    type Error = std::io::Error;

    fn encode(&mut self, frame: TalosFrame, dst: &mut BytesMut) -> Result<(), Self::Error> {
        self.encode(&frame, dst)
    }
}

impl Encoder<&TalosFrame> for FrameCodec {
    type Error = std::io::Error;

    fn encode(&mut self, frame: &TalosFrame, dst: &mut BytesMut) -> Result<(), Self::Error> {
        let bytes = frame
            .to_bytes(self.checksum)
            .map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidInput, e))?;
        dst.extend_from_slice(&bytes);
        Ok(())
    }
}
