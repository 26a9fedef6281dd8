//! Async client for a Talos operator.
//!
//! One task owns the TCP stream. Requests reach it over a channel with a oneshot for the answer;
//! it stamps each with the next even command id, writes it, and pairs the reply (id | 1) when it
//! arrives. Anything it cannot pair (an unknown id, a late reply, a corrupt frame) is reported as
//! a [`TalosEvent`], never dropped silently.
//!
//! Safety: while a continuous START is in effect, dropping the link (or the task losing its
//! callers) sends the matching STOP before closing, rather than leaving it to the operator's
//! 500 ms watchdog.
//!
//! Ack dialect: an ACK carries no id, so one lost ACK would misalign every later pairing. A
//! request whose ACK has not come within its timeout therefore leaves the in-order queue (a
//! late ACK for it is then absorbed, not paired with a newer request), and a STOP without an
//! ACK is re-sent ([`STOP_ACK_TRIES`] frames, [`STOP_ACK_INTERVAL`] apart) before it fails.

use std::collections::{HashMap, VecDeque};
use std::fmt;
use std::sync::Arc;
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::{Duration, Instant};

use futures::{SinkExt, StreamExt};
use tokio::net::TcpStream;
use tokio::net::tcp::OwnedReadHalf;
use tokio::sync::{mpsc, oneshot};
use tokio_util::codec::{FramedRead, FramedWrite};

use crate::net::{DEFAULT_FRAME_DEADLINE, FrameReader};
use crate::talos::ack::{ACK, AckCodec, AckItem};
use crate::talos::frame::{Decoded, Frame, FrameCodec, Rejection};
use crate::talos::message::{DecodeError, EncodeError};
use crate::talos::{Checksum, CommandValue, Reply, Request, ReturnCode};
// Re-exported so the link's callers keep naming it `link::Dialect`.
pub use crate::talos::Dialect;

/// Default port of the deployed operator.
pub const DEFAULT_PORT: u16 = 61616;

/// Ack dialect: how many STOP frames are sent before a STOP without an ACK fails.
pub const STOP_ACK_TRIES: u32 = 3;
/// Ack dialect: how long a STOP frame waits for its ACK before it is sent again.
pub const STOP_ACK_INTERVAL: Duration = Duration::from_millis(150);
/// Extra time a caller waits beyond the link's own ack-dialect deadline, which always answers
/// first: the caller's clock may start before the frame is written.
const ACK_CALLER_GRACE: Duration = Duration::from_millis(250);

/// Where and how to reach an operator.
#[derive(Debug, Clone)]
pub struct TalosConfig {
    pub addr: String,
    pub dialect: Dialect,
    pub checksum: Checksum,
    pub connect_timeout: Duration,
    pub request_timeout: Duration,
    /// How long a reply may take from its first byte to its last before it is given up.
    pub frame_deadline: Duration,
}

impl TalosConfig {
    pub fn new(addr: impl Into<String>) -> Self {
        TalosConfig {
            addr: addr.into(),
            dialect: Dialect::Icd,
            checksum: Checksum::Crc16,
            connect_timeout: Duration::from_secs(2),
            request_timeout: Duration::from_millis(500),
            frame_deadline: DEFAULT_FRAME_DEADLINE,
        }
    }
}

/// What came back for a request.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Answer {
    Reply(Reply),
    /// The `ack` dialect's "ACK\0": the operator received a frame, nothing more.
    Ack,
}

/// One completed request/reply exchange.
#[derive(Debug, Clone)]
pub struct Exchange {
    pub id: u32,
    pub request: Request,
    pub answer: Answer,
    pub request_bytes: Vec<u8>,
    pub reply_bytes: Vec<u8>,
    pub latency: Duration,
}

impl Exchange {
    pub fn return_code(&self) -> ReturnCode {
        match &self.answer {
            Answer::Reply(reply) => reply.return_code(),
            Answer::Ack => ReturnCode::OK,
        }
    }
}

/// Everything that can go wrong talking to an operator.
#[derive(Debug, thiserror::Error)]
pub enum TalosError {
    #[error("cannot resolve {addr}: {source}")]
    Resolve {
        addr: String,
        source: std::io::Error,
    },
    #[error("connection to {addr} refused: {source}")]
    Refused {
        addr: String,
        source: std::io::Error,
    },
    #[error("no connection to {addr} within {after:?}")]
    ConnectTimeout { addr: String, after: Duration },
    #[error("{command} (id {id}): no reply within {after:?}")]
    Timeout {
        command: CommandValue,
        id: u32,
        after: Duration,
    },
    #[error("{command} (id {id}) failed with return code {code}", command = .exchange.request.command(), id = .exchange.id, code = .exchange.return_code())]
    ReturnCode { exchange: Box<Exchange> },
    #[error("{command} (id {id}): reply rejected: {rejection}")]
    Checksum {
        command: CommandValue,
        id: u32,
        rejection: Rejection,
    },
    #[error("{command} (id {id}): malformed reply: {source}")]
    MalformedReply {
        command: CommandValue,
        id: u32,
        source: DecodeError,
    },
    #[error("{command} (id {id}): answered by a {answered} reply")]
    WrongReply {
        command: CommandValue,
        id: u32,
        answered: CommandValue,
    },
    #[error("cannot encode {command}: {source}")]
    Encode {
        command: CommandValue,
        source: EncodeError,
    },
    #[error(
        "{command} needs a typed reply, but the ack dialect's operator only acknowledges commands 0x0000-0x0004"
    )]
    NotInDialect { command: CommandValue },
    #[error("link to the operator lost: {reason}")]
    Disconnected { reason: String },
}

/// Things the link noticed that belong to no caller.
#[derive(Debug, Clone, PartialEq)]
pub enum TalosEvent {
    /// A reply whose id matches no request this link sent.
    UnpairedReply { id: u32, command: u16 },
    /// A reply that came after its request timed out.
    LateReply { id: u32, command: CommandValue },
    /// Bytes the decoder dropped that could not be tied to a pending request.
    Rejected(Rejection),
    /// Ack dialect: no ACK came for this frame in time; it left the in-order queue. A STOP is
    /// sent again as `resent_as` while it has tries left.
    AckExpired {
        id: u32,
        command: CommandValue,
        resent_as: Option<u32>,
    },
    /// An ack-dialect stream carried bytes that were not "ACK\0", or an ACK nobody waited for.
    UnexpectedAckBytes(usize),
    /// The connection ended; every pending request failed with `Disconnected`.
    Disconnected { reason: String },
}

/// The per-link command id counter: even ids from 0, wrapping after 2^31 requests. The low bit
/// is the ICD's request/reply marker.
#[derive(Debug, Default)]
struct CommandIds(AtomicU32);

impl CommandIds {
    fn next(&self) -> u32 {
        self.0.fetch_add(2, Ordering::Relaxed)
    }
}

type AnswerTx = oneshot::Sender<Result<Exchange, TalosError>>;

struct Job {
    id: u32,
    request: Request,
    answer: AnswerTx,
}

/// A connected operator link. Cheap to clone; the socket task ends when every clone is dropped.
#[derive(Clone)]
pub struct TalosLink {
    jobs: mpsc::Sender<Job>,
    ids: Arc<CommandIds>,
    config: TalosConfig,
}

impl fmt::Debug for TalosLink {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("TalosLink")
            .field("addr", &self.config.addr)
            .finish()
    }
}

impl TalosLink {
    /// Opens a TCP connection within the connect timeout. Returns the link and the receiver of
    /// its unsolicited events.
    pub async fn connect(
        config: TalosConfig,
    ) -> Result<(TalosLink, mpsc::UnboundedReceiver<TalosEvent>), TalosError> {
        let stream = open_stream(&config).await?;
        let _ = stream.set_nodelay(true);
        let (jobs_tx, jobs_rx) = mpsc::channel(64);
        let (events_tx, events_rx) = mpsc::unbounded_channel();
        let ids = Arc::new(CommandIds::default());
        let task = LinkTask {
            dialect: config.dialect,
            checksum: config.checksum,
            ids: ids.clone(),
            pending: HashMap::new(),
            ack_queue: VecDeque::new(),
            expired_acks: VecDeque::new(),
            request_timeout: config.request_timeout,
            frame_deadline: config.frame_deadline,
            addr: config.addr.clone(),
            motion: Motion::default(),
            events: events_tx,
        };
        tokio::spawn(task.run(stream, jobs_rx));
        Ok((
            TalosLink {
                jobs: jobs_tx,
                ids,
                config,
            },
            events_rx,
        ))
    }

    /// Connects, retrying with exponential backoff (100 ms doubling to 2 s) until `attempts`
    /// connection attempts have failed.
    pub async fn connect_with_backoff(
        config: TalosConfig,
        attempts: u32,
    ) -> Result<(TalosLink, mpsc::UnboundedReceiver<TalosEvent>), TalosError> {
        let mut delay = Duration::from_millis(100);
        let mut tried = 0;
        loop {
            tried += 1;
            match Self::connect(config.clone()).await {
                Ok(link) => return Ok(link),
                Err(e) if tried >= attempts.max(1) => return Err(e),
                Err(e) => tracing::info!("talos connect attempt {tried} failed: {e}"),
            }
            tokio::time::sleep(delay).await;
            delay = (delay * 2).min(Duration::from_secs(2));
        }
    }

    pub fn config(&self) -> &TalosConfig {
        &self.config
    }

    /// Sends `request` and waits for its answer within the request timeout. A reply with a
    /// non-zero return code is `Err(TalosError::ReturnCode)`, carrying the whole exchange.
    pub async fn request(&self, request: Request) -> Result<Exchange, TalosError> {
        self.submit(request).await?.wait().await
    }

    /// Queues `request` for sending and returns at once with a handle on its answer. Requests
    /// go on the wire in the order they were submitted, so a STOP submitted after a START is
    /// never overtaken by it, while the caller need not wait for the START's reply.
    pub async fn submit(&self, request: Request) -> Result<PendingReply, TalosError> {
        let command = request.command();
        if !self.config.dialect.supports(command) {
            return Err(TalosError::NotInDialect { command });
        }
        let (answer_tx, answer_rx) = oneshot::channel();
        let id = self.ids.next();
        let job = Job {
            id,
            request,
            answer: answer_tx,
        };
        let after = match self.config.dialect {
            Dialect::Icd => self.config.request_timeout,
            // The link task answers by its own deadline (re-sends included); this is a backstop.
            Dialect::Ack => ack_deadline(command, self.config.request_timeout) + ACK_CALLER_GRACE,
        };
        self.jobs.send(job).await.map_err(|_| task_gone())?;
        Ok(PendingReply {
            command,
            id,
            after,
            answer: answer_rx,
        })
    }

    /// Handshake with `oid`; returns the operator's (major, minor) version, or `None` in the
    /// ack dialect, which carries no version.
    pub async fn handshake(&self, oid: u16) -> Result<Option<(u8, u8)>, TalosError> {
        let exchange = self.request(Request::Handshake { oid }).await?;
        Ok(match exchange.answer {
            Answer::Reply(Reply::Handshake {
                major_version,
                minor_version,
                ..
            }) => Some((major_version, minor_version)),
            _ => None,
        })
    }
}

fn task_gone() -> TalosError {
    TalosError::Disconnected {
        reason: "the link task has ended".into(),
    }
}

/// The answer to a submitted request, still to come.
#[derive(Debug)]
pub struct PendingReply {
    command: CommandValue,
    id: u32,
    after: Duration,
    answer: oneshot::Receiver<Result<Exchange, TalosError>>,
}

impl PendingReply {
    /// The command id the request went out with.
    pub fn id(&self) -> u32 {
        self.id
    }

    pub fn command(&self) -> CommandValue {
        self.command
    }

    /// Waits for the answer within the request timeout, counted from now.
    pub async fn wait(self) -> Result<Exchange, TalosError> {
        let (command, id, after) = (self.command, self.id, self.after);
        let exchange = match tokio::time::timeout(after, self.answer).await {
            Ok(Ok(result)) => result?,
            Ok(Err(_)) => return Err(task_gone()),
            Err(_) => return Err(TalosError::Timeout { command, id, after }),
        };
        if exchange.return_code().is_ok() {
            Ok(exchange)
        } else {
            Err(TalosError::ReturnCode {
                exchange: Box::new(exchange),
            })
        }
    }
}

async fn sleep_until(deadline: Option<tokio::time::Instant>) {
    match deadline {
        Some(at) => tokio::time::sleep_until(at).await,
        None => std::future::pending().await,
    }
}

async fn open_stream(config: &TalosConfig) -> Result<TcpStream, TalosError> {
    let addr = config.addr.clone();
    let addrs: Vec<_> = tokio::net::lookup_host(&addr)
        .await
        .map_err(|source| TalosError::Resolve {
            addr: addr.clone(),
            source,
        })?
        .collect();
    let connect = async {
        let mut last = None;
        for a in addrs {
            match TcpStream::connect(a).await {
                Ok(s) => return Ok(s),
                Err(e) => last = Some(e),
            }
        }
        Err(last.unwrap_or_else(|| std::io::Error::other("no address")))
    };
    match tokio::time::timeout(config.connect_timeout, connect).await {
        Ok(Ok(stream)) => Ok(stream),
        Ok(Err(source)) => Err(TalosError::Refused { addr, source }),
        Err(_) => Err(TalosError::ConnectTimeout {
            addr,
            after: config.connect_timeout,
        }),
    }
}

struct Pending {
    id: u32,
    request: Request,
    request_bytes: Vec<u8>,
    sent: Instant,
    answer: AnswerTx,
}

fn is_stop(command: CommandValue) -> bool {
    matches!(
        command,
        CommandValue::PolarPanStop | CommandValue::CartesianMoveStop
    )
}

/// Ack dialect: how long the link waits for a request's ACK in all, re-sends included.
fn ack_deadline(command: CommandValue, request_timeout: Duration) -> Duration {
    if is_stop(command) {
        STOP_ACK_INTERVAL * STOP_ACK_TRIES
    } else {
        request_timeout
    }
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

/// Which continuous motions the operator was last told to run.
#[derive(Debug, Default, Clone, Copy)]
struct Motion {
    polar: bool,
    cartesian: bool,
}

impl Motion {
    fn note(&mut self, request: &Request) {
        match request {
            Request::PolarPanStart {
                moving_azimuth,
                moving_altitude,
            } => self.polar = *moving_azimuth != 0 || *moving_altitude != 0,
            Request::PolarPanStop => self.polar = false,
            Request::CartesianMoveStart {
                moving_x,
                moving_y,
                moving_z,
            } => self.cartesian = *moving_x != 0 || *moving_y != 0 || *moving_z != 0,
            Request::CartesianMoveStop => self.cartesian = false,
            _ => {}
        }
    }

    fn stops(self) -> Vec<Request> {
        let mut stops = Vec::new();
        if self.polar {
            stops.push(Request::PolarPanStop);
        }
        if self.cartesian {
            stops.push(Request::CartesianMoveStop);
        }
        stops
    }
}

struct LinkTask {
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
    motion: Motion,
    events: mpsc::UnboundedSender<TalosEvent>,
}

/// What arrives from the operator, in either dialect.
enum Incoming {
    Frame(Decoded),
    Ack(AckItem),
}

/// Reads replies in the link's dialect. Both readers are cancel-safe, as `select!` needs.
enum Replies {
    /// Frames with a per-frame deadline, so a reply split across reads is kept and one that
    /// never completes is given up.
    Frames(FrameReader<OwnedReadHalf>),
    Acks(FramedRead<OwnedReadHalf, AckCodec>),
}

impl Replies {
    async fn next(&mut self) -> Option<std::io::Result<Incoming>> {
        match self {
            Replies::Frames(reader) => reader.next().await.map(|r| r.map(Incoming::Frame)),
            Replies::Acks(reader) => reader.next().await.map(|r| r.map(Incoming::Ack)),
        }
    }
}

impl LinkTask {
    async fn run(mut self, stream: TcpStream, mut jobs: mpsc::Receiver<Job>) {
        let (read_half, write_half) = stream.into_split();
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
        let reason = loop {
            tokio::select! {
                job = jobs.recv() => match job {
                    Some(job) => {
                        if let Err(e) = self.send(&mut writer, job).await {
                            break format!("write failed: {e}");
                        }
                    }
                    None => {
                        // Every caller is gone: stop what we started, then close.
                        for stop in self.motion.stops() {
                            let frame = stop.to_frame(self.ids.next());
                            if let Ok(frame) = frame {
                                let _ = writer.send(frame).await;
                            }
                        }
                        return;
                    }
                },
                item = reader.next() => match item {
                    Some(Ok(Incoming::Frame(Decoded::Frame(frame)))) => self.on_frame(frame),
                    Some(Ok(Incoming::Frame(Decoded::Rejected(r)))) => self.on_rejection(r),
                    Some(Ok(Incoming::Ack(AckItem::Ack))) => self.on_ack(),
                    Some(Ok(Incoming::Ack(AckItem::Garbage(n)))) => {
                        self.event(TalosEvent::UnexpectedAckBytes(n));
                    }
                    Some(Err(e)) => break format!("read failed: {e}"),
                    None => break "the operator closed the connection".to_string(),
                },
                _ = sleep_until(self.next_ack_expiry()) => {
                    if let Err(e) = self.expire_acks(&mut writer).await {
                        break format!("write failed: {e}");
                    }
                }
                _ = sweep.tick() => self.sweep(),
            }
        };
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
        while let Some(job) = jobs.recv().await {
            let _ = job.answer.send(Err(TalosError::Disconnected {
                reason: "the link was lost earlier".into(),
            }));
        }
    }

    fn event(&self, event: TalosEvent) {
        tracing::debug!("talos event: {event:?}");
        let _ = self.events.send(event);
    }

    async fn send(
        &mut self,
        writer: &mut FramedWrite<tokio::net::tcp::OwnedWriteHalf, FrameCodec>,
        job: Job,
    ) -> std::io::Result<()> {
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
        writer.send(frame).await
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
    async fn expire_acks(
        &mut self,
        writer: &mut FramedWrite<tokio::net::tcp::OwnedWriteHalf, FrameCodec>,
    ) -> std::io::Result<()> {
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
                writer.send(frame).await?;
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

    fn on_frame(&mut self, frame: Frame) {
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
                let _ = pending.answer.send(Err(TalosError::Checksum {
                    command,
                    id,
                    rejection,
                }));
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
