//! The IO task of a [`TalosLink`](super::TalosLink): owns the transport, writes requests in
//! order (each write bounded by [`WRITE_STALL`]), pairs replies, expires ACKs, re-sends STOPs,
//! and sends the stop set when its callers are gone or its read side fails. Generic over the transport so tests
//! run it over an in-memory stream on a paused clock.

use std::collections::{HashMap, VecDeque};
use std::sync::Arc;
use std::time::{Duration, Instant};

use futures::{SinkExt, StreamExt};
use tokio::io::{AsyncRead, AsyncWrite, ReadHalf, WriteHalf};
use tokio::sync::{Notify, mpsc};
use tokio_util::codec::{FramedRead, FramedWrite};

use super::motion::MotionSinceStop;
use super::{
    Answer, AnswerTx, CommandIds, Exchange, Job, STOP_ACK_INTERVAL, STOP_ACK_TRIES, TalosError,
    TalosEvent, WRITE_STALL, ack_deadline, is_stop,
};
use crate::net::{FrameReader, io_error_words};
use crate::talos::ack::{ACK, AckCodec, AckItem};
use crate::talos::frame::{Decoded, FrameCodec, Rejection, TalosFrame};
use crate::talos::{Checksum, CommandValue, Dialect, Reply, Request};

async fn sleep_until(deadline: Option<tokio::time::Instant>) {
    match deadline {
        Some(at) => tokio::time::sleep_until(at).await,
        None => std::future::pending().await,
    }
}

struct Pending {
    id: u32,
    request: Request,
    request_bytes: Vec<u8>,
    sent: Instant,
    answer: AnswerTx,
}

/// Ack dialect: one frame on the wire waiting for its ACK.
struct AckWait {
    pending: Pending,
    /// When the frame is given up (and a STOP sent again).
    expires: tokio::time::Instant,
    /// Frames sent for this request so far.
    tries: u32,
    /// When the request's first frame went out, for the latency.
    first_sent: Instant,
}

/// Ack dialect: a frame whose ACK did not come in time and may still arrive.
struct ExpiredAck {
    id: u32,
    command: CommandValue,
    /// After this an ACK is no longer taken for this frame's.
    forget_at: tokio::time::Instant,
}

/// Why the link ended, and whether its write side may still carry a stop.
struct End {
    reason: String,
    writable: bool,
}

impl End {
    fn write(reason: String) -> End {
        End {
            reason,
            writable: false,
        }
    }

    fn read(reason: String) -> End {
        End {
            reason,
            writable: true,
        }
    }
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
        let mut writer = FramedWrite::new(write_half, FrameCodec::new(self.checksum));
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
        let end = loop {
            tokio::select! {
                job = jobs.recv() => match job {
                    Some(job) => {
                        if let Err(reason) = self.send(&mut writer, job).await {
                            break End::write(reason);
                        }
                    }
                    None => {
                        // Every caller is gone: stop what may be moving, then close.
                        let _ = self.write_stops(&mut writer).await;
                        return;
                    }
                },
                item = reader.next() => match item {
                    Some(Ok(Incoming::TalosFrame(Decoded::TalosFrame(frame)))) => self.on_frame(frame),
                    Some(Ok(Incoming::TalosFrame(Decoded::Rejected(r)))) => self.on_rejection(r),
                    Some(Ok(Incoming::Ack(AckItem::Ack))) => self.on_ack(),
                    Some(Ok(Incoming::Ack(AckItem::Garbage(n)))) => {
                        self.event(TalosEvent::UnexpectedAckBytes(n));
                    }
                    Some(Err(e)) => break End::read(format!("read failed: {}", io_error_words(&e))),
                    None => break End::read("the operator closed the connection".to_string()),
                },
                _ = sleep_until(self.next_ack_expiry()) => {
                    if let Err(reason) = self.expire_acks(&mut writer).await {
                        break End::write(reason);
                    }
                }
                () = self.overflow.notified() => break End::write(super::queue_full()),
                _ = sweep.tick() => self.sweep(),
            }
        };
        let reason = end.reason;
        tracing::warn!("talos link lost: {reason}");
        for (_, p) in self.pending.drain() {
            let _ = p.answer.send(Err(TalosError::Disconnected {
                reason: reason.clone(),
            }));
        }
        for wait in self.ack_queue.drain(..) {
            let _ = wait.pending.answer.send(Err(TalosError::Disconnected {
                reason: reason.clone(),
            }));
        }
        self.event(TalosEvent::Disconnected { reason });
        // Fail later callers at once rather than letting them time out.
        jobs.close();
        // A link that failed on its read side may still carry the stop set.
        if end.writable
            && let Err(reason) = self.write_stops(&mut writer).await
        {
            tracing::warn!("talos: the stop set after the link was lost: {reason}");
        }
        while let Some(job) = jobs.recv().await {
            let _ = job.answer.send(Err(TalosError::Disconnected {
                reason: "the link was lost earlier".into(),
            }));
        }
    }

    /// Writes the stop set if anything may be moving; the first write that fails ends it.
    async fn write_stops<W: AsyncWrite + Unpin>(
        &mut self,
        writer: &mut FramedWrite<W, FrameCodec>,
    ) -> Result<(), String> {
        for stop in self.motion.owed().to_vec() {
            let id = self.ids.next();
            match stop.to_frame(id) {
                Ok(frame) => self.write(writer, frame).await?,
                // The stop set encodes by construction; say so if that ever changes.
                Err(e) => tracing::error!("cannot encode {}: {e}", stop.command()),
            }
            self.motion.note(&stop);
        }
        Ok(())
    }

    /// Writes one frame, or says why the link must end: a write error, a write that could not
    /// complete within [`WRITE_STALL`], or a caller that found the queue full meanwhile.
    async fn write<W: AsyncWrite + Unpin>(
        &self,
        writer: &mut FramedWrite<W, FrameCodec>,
        frame: TalosFrame,
    ) -> Result<(), String> {
        tokio::select! {
            written = tokio::time::timeout(WRITE_STALL, writer.send(frame)) => match written {
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

    async fn send<W: AsyncWrite + Unpin>(
        &mut self,
        writer: &mut FramedWrite<W, FrameCodec>,
        job: Job,
    ) -> Result<(), String> {
        let id = job.id;
        let command = job.request.command();
        let frame = match job.request.to_frame(id) {
            Ok(frame) => frame,
            Err(source) => {
                let _ = job.answer.send(Err(TalosError::Encode { command, source }));
                return Ok(());
            }
        };
        let request_bytes = frame.to_bytes(self.checksum).unwrap_or_default();
        let pending = Pending {
            id,
            request: job.request,
            request_bytes,
            sent: Instant::now(),
            answer: job.answer,
        };
        self.motion.note(&pending.request);
        match self.dialect {
            Dialect::Icd => {
                self.pending.insert(id, pending);
            }
            Dialect::Ack => {
                let first_sent = pending.sent;
                self.queue_ack_wait(pending, 1, first_sent);
            }
        }
        self.write(writer, frame).await
    }

    fn queue_ack_wait(&mut self, pending: Pending, tries: u32, first_sent: Instant) {
        let wait = if is_stop(pending.request.command()) {
            STOP_ACK_INTERVAL
        } else {
            self.request_timeout
        };
        self.ack_queue.push_back(AckWait {
            pending,
            expires: tokio::time::Instant::now() + wait,
            tries,
            first_sent,
        });
    }

    fn next_ack_expiry(&self) -> Option<tokio::time::Instant> {
        self.ack_queue.iter().map(|w| w.expires).min()
    }

    /// Takes frames whose ACK is overdue out of the queue, so later ACKs pair with later
    /// frames; sends an overdue STOP again while it has tries left, and fails the rest.
    async fn expire_acks<W: AsyncWrite + Unpin>(
        &mut self,
        writer: &mut FramedWrite<W, FrameCodec>,
    ) -> Result<(), String> {
        let now = tokio::time::Instant::now();
        let (overdue, waiting): (VecDeque<AckWait>, VecDeque<AckWait>) =
            self.ack_queue.drain(..).partition(|w| w.expires <= now);
        self.ack_queue = waiting;
        let forget_after = self.request_timeout.max(Duration::from_secs(1));
        for wait in overdue {
            let AckWait {
                pending,
                tries,
                first_sent,
                ..
            } = wait;
            let command = pending.request.command();
            self.expired_acks.push_back(ExpiredAck {
                id: pending.id,
                command,
                forget_at: now + forget_after,
            });
            if is_stop(command) && tries < STOP_ACK_TRIES {
                let id = self.ids.next();
                tracing::warn!(
                    "{command} (id {}) not acknowledged within {STOP_ACK_INTERVAL:?}: sending it again as id {id}",
                    pending.id
                );
                self.event(TalosEvent::AckExpired {
                    id: pending.id,
                    command,
                    resent_as: Some(id),
                });
                let frame = match pending.request.to_frame(id) {
                    Ok(frame) => frame,
                    Err(source) => {
                        let _ = pending
                            .answer
                            .send(Err(TalosError::Encode { command, source }));
                        continue;
                    }
                };
                let request_bytes = frame.to_bytes(self.checksum).unwrap_or_default();
                let resent = Pending {
                    id,
                    request_bytes,
                    sent: Instant::now(),
                    ..pending
                };
                self.queue_ack_wait(resent, tries + 1, first_sent);
                self.write(writer, frame).await?;
            } else {
                tracing::warn!("{command} (id {}) not acknowledged in time", pending.id);
                self.event(TalosEvent::AckExpired {
                    id: pending.id,
                    command,
                    resent_as: None,
                });
                let _ = pending.answer.send(Err(TalosError::Timeout {
                    command,
                    id: pending.id,
                    after: ack_deadline(command, self.request_timeout),
                }));
            }
        }
        Ok(())
    }

    fn on_frame(&mut self, frame: TalosFrame) {
        let Some(pending) = self
            .pending
            .remove(&(frame.id & !1))
            .filter(|_| frame.id & 1 == 1)
        else {
            self.event(TalosEvent::UnpairedReply {
                id: frame.id,
                command: frame.command,
            });
            return;
        };
        let id = frame.id & !1;
        let command = pending.request.command();
        let reply_bytes = frame.to_bytes(self.checksum).unwrap_or_default();
        let result = match Reply::from_frame(&frame) {
            Ok(reply) if reply.command() == command => Ok(Exchange {
                id,
                request: pending.request,
                answer: Answer::Reply(reply),
                request_bytes: pending.request_bytes,
                reply_bytes,
                latency: pending.sent.elapsed(),
            }),
            Ok(reply) => Err(TalosError::WrongReply {
                command,
                id,
                answered: reply.command(),
            }),
            Err(source) => Err(TalosError::MalformedReply {
                command,
                id,
                source,
            }),
        };
        if pending.answer.send(result).is_err() {
            self.event(TalosEvent::LateReply { id, command });
        }
    }

    fn on_rejection(&mut self, rejection: Rejection) {
        // A corrupt reply whose header names a pending request fails that request now.
        let owner = rejection
            .header
            .filter(|h| h.id & 1 == 1)
            .and_then(|h| self.pending.remove(&(h.id & !1)));
        match owner {
            Some(pending) => {
                let command = pending.request.command();
                let id = rejection.header.map_or(0, |h| h.id & !1);
                let failed = pending.answer.send(Err(TalosError::Checksum {
                    command,
                    id,
                    rejection,
                }));
                // Its caller gave up (timed out) before the reply was given up on: the rejection
                // still tells what the operator speaks.
                if failed.is_err() {
                    self.event(TalosEvent::Rejected(rejection));
                }
            }
            None => self.event(TalosEvent::Rejected(rejection)),
        }
    }

    /// Pairs an ACK with the oldest frame still waiting. With none waiting it belongs to a
    /// frame given up on (reported late), or to nothing (reported unexpected).
    fn on_ack(&mut self) {
        let Some(wait) = self.ack_queue.pop_front() else {
            let now = tokio::time::Instant::now();
            while self
                .expired_acks
                .front()
                .is_some_and(|e| e.forget_at <= now)
            {
                self.expired_acks.pop_front();
            }
            match self.expired_acks.pop_front() {
                Some(late) => self.event(TalosEvent::LateReply {
                    id: late.id,
                    command: late.command,
                }),
                None => self.event(TalosEvent::UnexpectedAckBytes(ACK.len())),
            }
            return;
        };
        let pending = wait.pending;
        let id = pending.id;
        let exchange = Exchange {
            id,
            request: pending.request,
            answer: Answer::Ack,
            request_bytes: pending.request_bytes,
            reply_bytes: ACK.to_vec(),
            latency: wait.first_sent.elapsed(),
        };
        let command = exchange.request.command();
        if pending.answer.send(Ok(exchange)).is_err() {
            self.event(TalosEvent::LateReply { id, command });
        }
    }

    /// Forgets requests whose callers gave up, so the map stays bounded. A reply that still
    /// comes for one is reported as unpaired.
    fn sweep(&mut self) {
        let stale: Vec<u32> = self
            .pending
            .iter()
            .filter(|(_, p)| p.answer.is_closed() && p.sent.elapsed() > Duration::from_secs(5))
            .map(|(id, _)| *id)
            .collect();
        for id in stale {
            self.pending.remove(&id);
        }
    }
}
