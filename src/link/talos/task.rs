//! The IO task of a [`TalosLink`](super::TalosLink): owns the transport, writes requests in
//! order (each write bounded by [`WRITE_STALL`]), pairs replies, expires ACKs, re-sends STOPs,
//! and sends the stop set when its callers are gone or its read side fails. Generic over the transport so tests
//! run it over an in-memory stream on a paused clock.

use std::collections::{HashMap, VecDeque};
use std::sync::Arc;
use std::time::{Duration, Instant};

use futures::{FutureExt, StreamExt};
use tokio::io::{AsyncRead, AsyncWrite, AsyncWriteExt, ReadHalf, WriteHalf};
use tokio::sync::{Notify, mpsc};
use tokio_util::codec::FramedRead;

use super::motion::MotionSinceStop;
use super::{AnswerTx, CommandIds, Job, TalosError, TalosEvent, WRITE_STALL};
use crate::net::{Deadline, FrameReader, io_error_words};
use crate::talos::ack::{AckCodec, AckItem};
use crate::talos::frame::{Decoded, FrameCodec, TalosFrame};
use crate::talos::{Checksum, Dialect, Request};

mod ack;
mod replies;

use ack::{AckWait, ExpiredAck};

/// The most requests written together: what was queued when the task took the first, up to this.
const BATCH_MAX: usize = 16;

struct Pending {
    id: u32,
    request: Request,
    request_bytes: Vec<u8>,
    sent: Instant,
    answer: AnswerTx,
}

/// Why the link ended, on which side: after a read-side end the write side may still carry a stop.
enum End {
    Write(String),
    Read(String),
}

pub(super) struct LinkTask {
    dialect: Dialect,
    checksum: Checksum,
    ids: Arc<CommandIds>,
    pending: HashMap<u32, Pending>,
    /// Ack dialect: frames in the order sent, answered in order.
    ack_queue: VecDeque<AckWait>,
    /// Ack dialect: frames given up on, oldest first: an ACK that comes while nothing waits is
    /// theirs.
    expired_acks: VecDeque<ExpiredAck>,
    request_timeout: Duration,
    frame_deadline: Duration,
    /// The operator's address, for the log.
    addr: String,
    motion: MotionSinceStop,
    events: mpsc::UnboundedSender<TalosEvent>,
    /// Told by a caller that found the queue full.
    overflow: Arc<Notify>,
}

/// What arrives from the operator, in either dialect.
enum Incoming {
    TalosFrame(Decoded),
    Ack(AckItem),
}

/// Reads replies in the link's dialect. Both readers are cancel-safe, as `select!` needs.
enum Replies<R> {
    /// Frames with a per-frame deadline, so a reply split across reads is kept and one that
    /// never completes is given up.
    Frames(FrameReader<R>),
    Acks(FramedRead<R, AckCodec>),
}

impl<R: AsyncRead + Unpin> Replies<R> {
    async fn next(&mut self) -> Option<std::io::Result<Incoming>> {
        match self {
            Replies::Frames(reader) => reader.next().await.map(|r| r.map(Incoming::TalosFrame)),
            Replies::Acks(reader) => reader.next().await.map(|r| r.map(Incoming::Ack)),
        }
    }
}

impl LinkTask {
    pub(super) fn new(
        config: &super::TalosConfig,
        ids: Arc<CommandIds>,
        events: mpsc::UnboundedSender<TalosEvent>,
        overflow: Arc<Notify>,
    ) -> LinkTask {
        LinkTask {
            dialect: config.dialect,
            checksum: config.checksum,
            ids,
            pending: HashMap::new(),
            ack_queue: VecDeque::new(),
            expired_acks: VecDeque::new(),
            request_timeout: config.request_timeout,
            frame_deadline: config.frame_deadline,
            addr: config.addr.clone(),
            motion: MotionSinceStop::new(config.dialect),
            events,
            overflow,
        }
    }

    pub(super) async fn run<S>(mut self, stream: S, mut jobs: mpsc::Receiver<Job>)
    where
        S: AsyncRead + AsyncWrite + Send + 'static,
    {
        let (read_half, write_half): (ReadHalf<S>, WriteHalf<S>) = tokio::io::split(stream);
        // Frames are encoded once, by the task, and their bytes written as they are.
        let mut writer = write_half;
        let mut reader = match self.dialect {
            Dialect::Icd => Replies::Frames(FrameReader::new(
                read_half,
                FrameCodec::new(self.checksum),
                self.frame_deadline,
                format!("talos replies from {}", self.addr),
            )),
            Dialect::Ack => Replies::Acks(FramedRead::new(read_half, AckCodec)),
        };
        let mut sweep = tokio::time::interval(Duration::from_secs(1));
        let mut ack_expiry = Deadline::new();
        let end = loop {
            ack_expiry.set(self.next_ack_expiry());
            tokio::select! {
                // In this order, not at random: a full queue ends the link as it did; a job (a
                // STOP) is written before anything else is polled (a timer polled costs a lock
                // of the runtime's timer wheel); replies last, so an operator that floods them
                // never holds up an overdue STOP's re-send or the requests' deadlines.
                biased;
                () = self.overflow.notified() => break End::Write(super::queue_full()),
                job = jobs.recv() => match job {
                    Some(job) => {
                        // What else is queued goes in the same write: a stop set is one segment.
                        let mut batch = vec![job];
                        while batch.len() < BATCH_MAX
                            && let Ok(job) = jobs.try_recv()
                        {
                            batch.push(job);
                        }
                        if let Err(reason) = self.send(&mut writer, batch).await {
                            break End::Write(reason);
                        }
                    }
                    None => {
                        // Every caller is gone: stop what may be moving, then close.
                        let _ = self.write_stops(&mut writer).await;
                        return;
                    }
                },
                _ = ack_expiry.fired(), if ack_expiry.armed() => {
                    if let Err(reason) = self.expire_acks(&mut writer).await {
                        break End::Write(reason);
                    }
                }
                _ = sweep.tick() => self.sweep(),
                item = reader.next() => {
                    match item {
                        Some(Ok(Incoming::TalosFrame(Decoded::TalosFrame(frame)))) => self.on_frame(frame),
                        Some(Ok(Incoming::TalosFrame(Decoded::Rejected(r)))) => self.on_rejection(r),
                        Some(Ok(Incoming::Ack(AckItem::Ack))) => self.on_ack(),
                        Some(Ok(Incoming::Ack(AckItem::Garbage(n)))) => {
                            self.event(TalosEvent::UnexpectedAckBytes(n));
                        }
                        Some(Err(e)) => break End::Read(format!("read failed: {}", io_error_words(&e))),
                        None => break End::Read("the operator closed the connection".to_string()),
                    }
                }
            }
        };
        let (reason, writable) = match end {
            End::Write(reason) => (reason, false),
            End::Read(reason) => (reason, true),
        };
        tracing::warn!("talos link lost: {reason}");
        let waiting = self.pending.drain().map(|(_, p)| p);
        for p in waiting.chain(self.ack_queue.drain(..).map(|w| w.pending)) {
            let reason = reason.clone();
            let _ = p.answer.send(Err(TalosError::Disconnected { reason }));
        }
        self.event(TalosEvent::Disconnected { reason });
        // Fail later callers at once rather than letting them time out.
        jobs.close();
        // A link that failed on its read side may still carry the stop set.
        if writable && let Err(reason) = self.write_stops(&mut writer).await {
            tracing::warn!("talos: the stop set after the link was lost: {reason}");
        }
        while let Some(job) = jobs.recv().await {
            let _ = job.answer.send(Err(TalosError::Disconnected {
                reason: "the link was lost earlier".into(),
            }));
        }
    }

    /// Writes the stop set, in one write as a key's is, if anything may be moving.
    async fn write_stops<W: AsyncWrite + Unpin>(&mut self, writer: &mut W) -> Result<(), String> {
        let owed = self.motion.owed().to_vec();
        let mut bytes = Vec::new();
        for stop in &owed {
            let id = self.ids.next();
            match stop.to_frame(id) {
                Ok(frame) => bytes.extend_from_slice(&self.encode(&frame)?),
                // The stop set encodes by construction; say so if that ever changes.
                Err(e) => tracing::error!("cannot encode {}: {e}", stop.command()),
            }
        }
        if !bytes.is_empty() {
            self.write(writer, &bytes).await?;
        }
        for stop in &owed {
            self.motion.note(stop);
        }
        Ok(())
    }

    /// The frame's bytes, or why the link must end (a payload too long for its length field).
    fn encode(&self, frame: &TalosFrame) -> Result<Vec<u8>, String> {
        frame
            .to_bytes(self.checksum)
            .map_err(|e| format!("write failed: {e}"))
    }

    /// Writes one frame's bytes, or says why the link must end: a write error, a write that
    /// could not complete within [`WRITE_STALL`], or a caller that found the queue full
    /// meanwhile.
    async fn write<W: AsyncWrite + Unpin>(
        &self,
        writer: &mut W,
        bytes: &[u8],
    ) -> Result<(), String> {
        let mut written = std::pin::pin!(async {
            writer.write_all(bytes).await?;
            writer.flush().await
        });
        // Most writes complete at once: the stall's timer and the wait for an overflow are
        // set up only for one that does not (the same future goes on, where it got to).
        if let Some(done) = written.as_mut().now_or_never() {
            return done.map_err(|e| format!("write failed: {}", io_error_words(&e)));
        }
        tokio::select! {
            biased;
            written = tokio::time::timeout(WRITE_STALL, written) => match written {
                Ok(Ok(())) => Ok(()),
                Ok(Err(e)) => Err(format!("write failed: {}", io_error_words(&e))),
                Err(_) => Err(format!(
                    "the operator has not read for {} ms (write stalled)",
                    WRITE_STALL.as_millis()
                )),
            },
            () = self.overflow.notified() => Err(super::queue_full()),
        }
    }

    fn event(&self, event: TalosEvent) {
        tracing::debug!("talos event: {event:?}");
        let _ = self.events.send(event);
    }

    /// Writes the jobs' frames in one write, in their order, then makes them pending. A request
    /// that cannot be framed is answered at once; a frame that cannot be encoded ends the link
    /// (its job and those after it are made pending unsent, so their callers are answered with
    /// the link's end).
    async fn send<W: AsyncWrite + Unpin>(
        &mut self,
        writer: &mut W,
        batch: Vec<Job>,
    ) -> Result<(), String> {
        let sent = Instant::now();
        let mut encoded: Vec<(Job, Vec<u8>)> = Vec::with_capacity(batch.len());
        let mut unsent = Vec::new();
        let mut failed = None;
        for job in batch {
            if failed.is_some() {
                unsent.push(job);
                continue;
            }
            let command = job.request.command();
            let frame = match job.request.to_frame(job.id) {
                Ok(frame) => frame,
                Err(source) => {
                    let _ = job.answer.send(Err(TalosError::Encode { command, source }));
                    continue;
                }
            };
            match self.encode(&frame) {
                Ok(frame_bytes) => encoded.push((job, frame_bytes)),
                Err(reason) => {
                    failed = Some(reason);
                    unsent.push(job);
                }
            }
        }
        // The frames are written before they are made pending: the bookkeeping costs them
        // nothing, and no reply can be read before it is done (this task does both).
        let written = match encoded.as_slice() {
            [] => Ok(()),
            // One frame (a key's START or STOP): its bytes as they are, not copied.
            [(_, bytes)] => self.write(writer, bytes).await,
            frames => {
                let bytes: Vec<u8> = frames.iter().flat_map(|(_, b)| b.iter().copied()).collect();
                self.write(writer, &bytes).await
            }
        };
        for (job, request_bytes) in encoded {
            self.motion.note(&job.request);
            self.make_pending(job, request_bytes, sent);
        }
        for job in unsent {
            self.make_pending(job, Vec::new(), sent);
        }
        match failed {
            Some(reason) => Err(reason),
            None => written,
        }
    }

    fn make_pending(&mut self, job: Job, request_bytes: Vec<u8>, sent: Instant) {
        let pending = Pending {
            id: job.id,
            request: job.request,
            request_bytes,
            sent,
            answer: job.answer,
        };
        match self.dialect {
            Dialect::Icd => {
                self.pending.insert(pending.id, pending);
            }
            Dialect::Ack => self.queue_ack_wait(pending, 1, sent),
        }
    }
}
