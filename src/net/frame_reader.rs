//! Reads Talos frames from a byte stream, each with a deadline from its first byte's arrival (so
//! trickling does not extend it). A header may announce more than ever comes, and the codec waits
//! for split frames, so past the deadline the frame is given up ([`FrameCodec::expire`]), logged as
//! `RejectReason::Stalled`, and the frames buffered behind it come out at once. `FramedRead` cannot
//! do this: it decodes only when bytes arrive.

use std::collections::VecDeque;
use std::io;
use std::time::Duration;

use bytes::BytesMut;
use futures::FutureExt;
use tokio::io::{AsyncRead, AsyncReadExt};
use tokio::time::Instant;
use tokio_util::codec::Decoder;

use crate::talos::FrameCodec;
use crate::talos::frame::Decoded;

/// How long a frame may take from its first byte to its last, by default.
pub const DEFAULT_FRAME_DEADLINE: Duration = Duration::from_secs(1);

/// Room made in the buffer before each read.
const READ_CHUNK: usize = 8 * 1024;

/// Decoded frames over `R`, a deadline per frame; cancel-safe.
#[derive(Debug)]
pub struct FrameReader<R> {
    inner: R,
    codec: FrameCodec,
    buf: BytesMut,
    deadline: Duration,
    /// Who is at the other end, as the log names it.
    peer: String,
    /// Per buffered read: the offset past its last byte and its arrival (bounded by the buffer).
    arrivals: VecDeque<(u64, Instant)>,
    /// Bytes read from `inner` since the start.
    received: u64,
    eof: bool,
}

impl<R: AsyncRead + Unpin> FrameReader<R> {
    pub fn new(inner: R, codec: FrameCodec, deadline: Duration, peer: impl Into<String>) -> Self {
        FrameReader {
            inner,
            codec,
            buf: BytesMut::new(),
            deadline,
            peer: peer.into(),
            arrivals: VecDeque::new(),
            received: 0,
            eof: false,
        }
    }

    /// The next frame or rejection; `None` once ended and all is reported.
    pub async fn next(&mut self) -> Option<io::Result<Decoded>> {
        loop {
            if let Some(item) = self.codec.decode_buffered(&mut self.buf) {
                self.forget_consumed();
                return Some(Ok(item));
            }
            self.forget_consumed();
            if self.eof {
                let item = match self.codec.decode_eof(&mut self.buf) {
                    Ok(item) => item,
                    Err(e) => return Some(Err(e)),
                };
                self.forget_consumed();
                return item.map(Ok);
            }
            if self.buf.capacity() - self.buf.len() < READ_CHUNK {
                self.buf.reserve(READ_CHUNK);
            }
            let deadline = self.front_deadline();
            let read = self.inner.read_buf(&mut self.buf);
            // The read is polled first: bytes already here never expire for being read late.
            let outcome = match deadline {
                Some(at) => tokio::time::timeout_at(at, read).await,
                None => Ok(read.await),
            };
            match outcome {
                Ok(Ok(0)) => self.eof = true,
                Ok(Ok(n)) => self.note_arrival(n),
                Ok(Err(e)) => return Some(Err(e)),
                Err(_elapsed) => {
                    // A yield may be the coop budget: take bytes here first.
                    let read = tokio::task::unconstrained(self.inner.read_buf(&mut self.buf));
                    match read.now_or_never() {
                        Some(Ok(0)) => self.eof = true,
                        Some(Ok(n)) => self.note_arrival(n),
                        Some(Err(e)) => return Some(Err(e)),
                        None => match self.expire() {
                            Some(item) => return Some(Ok(item)),
                            // Nothing was waiting after all: restart the clock, not spin.
                            None => {
                                if let Some(front) = self.arrivals.front_mut() {
                                    front.1 = Instant::now();
                                }
                            }
                        },
                    }
                }
            }
        }
    }

    fn note_arrival(&mut self, n: usize) {
        self.received += n as u64;
        self.arrivals.push_back((self.received, Instant::now()));
    }

    /// Gives up on the overdue frame at the front of the buffer.
    fn expire(&mut self) -> Option<Decoded> {
        let now = Instant::now();
        let consumed = self.consumed();
        let overdue_end = self
            .arrivals
            .iter()
            .take_while(|(_, at)| *at + self.deadline <= now)
            .map(|(end, _)| *end)
            .last()?;
        let overdue = usize::try_from(overdue_end - consumed).unwrap_or(usize::MAX);
        let item = self.codec.expire(&mut self.buf, overdue, self.deadline);
        self.forget_consumed();
        if let Some(Decoded::Rejected(rejection)) = &item {
            tracing::info!("{}: {rejection}", self.peer);
        }
        item
    }

    /// Stream offset of the first buffered byte.
    fn consumed(&self) -> u64 {
        self.received - self.buf.len() as u64
    }

    /// Drops the arrival records of reads whose bytes have all left the buffer.
    fn forget_consumed(&mut self) {
        let consumed = self.consumed();
        while self
            .arrivals
            .front()
            .is_some_and(|(end, _)| *end <= consumed)
        {
            self.arrivals.pop_front();
        }
    }

    /// When the frame at the front of the buffer must be complete, if one has begun.
    fn front_deadline(&self) -> Option<Instant> {
        if self.buf.is_empty() {
            return None;
        }
        self.arrivals.front().map(|(_, at)| *at + self.deadline)
    }
}
