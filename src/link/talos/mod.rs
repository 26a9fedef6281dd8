//! Async client for a Talos operator. One task (`task.rs`) owns the transport, stamps each
//! request with the next even command id and pairs its reply (id | 1); what it cannot pair is
//! reported as a [`TalosEvent`], never dropped silently. [`TalosLink::submit`] never waits: a
//! full queue ([`QUEUE_DEPTH`]) or a write stalled past [`WRITE_STALL`] ends the link.
//!
//! Safety: once anything that may move the arm went out and no full stop set
//! ([`crate::talos::stop_requests`]) since, a link dropped by its callers, or failing on its read
//! side, sends the stop set before closing rather than leave it to the operator's 500 ms watchdog.
//!
//! Ack dialect: an ACK carries no id, so a request whose ACK is late leaves the in-order queue
//! (its late ACK is absorbed), and a STOP is re-sent ([`STOP_ACK_TRIES`], [`STOP_ACK_INTERVAL`]
//! apart) before it fails.

mod hint;
mod motion;
mod task;

use std::fmt;
use std::sync::Arc;
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::Duration;

use tokio::io::{AsyncRead, AsyncWrite};
use tokio::sync::{Notify, mpsc, oneshot};

use crate::net::{ConnectError, DEFAULT_FRAME_DEADLINE, connect_with_timeout};
use crate::talos::frame::Rejection;
use crate::talos::message::{DecodeError, EncodeError};
use crate::talos::{Checksum, CommandValue, Reply, Request, RequestClass, ReturnCode};
use hint::checksum_hint;
pub use hint::{first_exchange_error, wait_for_checksum_fit};
use task::LinkTask;
// Re-exported so the link's callers keep naming it `link::Dialect`.
pub use crate::talos::Dialect;

/// Default port of the deployed operator.
pub const DEFAULT_PORT: u16 = 61616;

/// Ack dialect: how many STOP frames are sent before a STOP without an ACK fails.
pub const STOP_ACK_TRIES: u32 = 3;
/// Ack dialect: how long a STOP frame waits for its ACK before it is sent again.
pub const STOP_ACK_INTERVAL: Duration = Duration::from_millis(150);
/// How many requests may wait unsent; one more is a link failure, never a wait.
pub const QUEUE_DEPTH: usize = 64;
/// A frame write that cannot complete within this ends the link: the operator is not reading.
pub const WRITE_STALL: Duration = Duration::from_millis(500);
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
    /// No connection was opened; the error names the address.
    #[error(transparent)]
    Connect(#[from] ConnectError),
    #[error("{command} (id {id}): no reply within {after:?}")]
    Timeout {
        command: CommandValue,
        id: u32,
        after: Duration,
    },
    #[error("{command} (id {id}) failed with return code {code}", command = .exchange.request.command(), id = .exchange.id, code = .exchange.return_code())]
    ReturnCode { exchange: Box<Exchange> },
    #[error("{command} (id {id}): reply rejected: {rejection}{}", checksum_hint(.rejection))]
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
    /// Told when a request found the queue full: the task then ends the link.
    overflow: Arc<Notify>,
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
    /// Opens a TCP connection within the connect timeout; returns the link and its events.
    pub async fn connect(
        config: TalosConfig,
    ) -> Result<(TalosLink, mpsc::UnboundedReceiver<TalosEvent>), TalosError> {
        let stream = connect_with_timeout(&config.addr, config.connect_timeout).await?;
        Ok(Self::over(stream, config))
    }

    /// Runs a link over a connected transport (in-memory in tests); spawns its task.
    pub fn over<S>(
        stream: S,
        config: TalosConfig,
    ) -> (TalosLink, mpsc::UnboundedReceiver<TalosEvent>)
    where
        S: AsyncRead + AsyncWrite + Send + 'static,
    {
        let (jobs_tx, jobs_rx) = mpsc::channel(QUEUE_DEPTH);
        let (events_tx, events_rx) = mpsc::unbounded_channel();
        let ids = Arc::new(CommandIds::default());
        let overflow = Arc::new(Notify::new());
        let task = LinkTask::new(&config, ids.clone(), events_tx, overflow.clone());
        // Boxed: the task is on the key path (see `Driver::spawn`).
        tokio::spawn(Box::pin(task.run(stream, jobs_rx)));
        (
            TalosLink {
                jobs: jobs_tx,
                overflow,
                ids,
                config,
            },
            events_rx,
        )
    }

    /// Sends `request` and waits for its answer within the request timeout. A reply with a
    /// non-zero return code is `Err(TalosError::ReturnCode)`, carrying the whole exchange.
    pub async fn request(&self, request: Request) -> Result<Exchange, TalosError> {
        self.submit(request)?.wait().await
    }

    /// Queues `request` and returns at once with a handle on its answer. Requests go out in the
    /// order submitted (a STOP is never overtaken by an earlier START); a full queue ends the link.
    pub fn submit(&self, request: Request) -> Result<PendingReply, TalosError> {
        let command = request.command();
        if !self.config.dialect.supports(command) {
            return Err(TalosError::NotInDialect { command });
        }
        let (answer_tx, answer_rx) = oneshot::channel();
        let id = self.ids.next();
        let after = match self.config.dialect {
            Dialect::Icd => self.config.request_timeout,
            // The link task answers by its own deadline (re-sends included); this is a backstop.
            Dialect::Ack => ack_deadline(&request, self.config.request_timeout) + ACK_CALLER_GRACE,
        };
        self.queue(Job {
            id,
            request,
            answer: answer_tx,
        })?;
        Ok(PendingReply {
            command,
            id,
            after,
            answer: answer_rx,
        })
    }

    /// Queues `job` for the link task; a full queue ends the link.
    fn queue(&self, job: Job) -> Result<(), TalosError> {
        match self.jobs.try_send(job) {
            Ok(()) => Ok(()),
            Err(mpsc::error::TrySendError::Full(_)) => {
                self.overflow.notify_one();
                Err(TalosError::Disconnected {
                    reason: queue_full(),
                })
            }
            Err(mpsc::error::TrySendError::Closed(_)) => Err(task_gone()),
        }
    }

    /// Handshake with `oid`; returns the operator's (major, minor) version, or `None` in the
    /// ack dialect, which carries no version.
    pub async fn handshake(&self, oid: u16) -> Result<Option<(u8, u8)>, TalosError> {
        let exchange = self.request(Request::Handshake { oid: Some(oid) }).await?;
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

/// Why a link whose queue filled was ended.
fn queue_full() -> String {
    format!("{QUEUE_DEPTH} requests queued unsent: the operator is not reading")
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

/// Ack dialect: how long the link waits for a request's ACK in all, re-sends included (a
/// stop is sent again while unacknowledged).
pub(super) fn ack_deadline(request: &Request, request_timeout: Duration) -> Duration {
    if request.class() == RequestClass::Stop {
        STOP_ACK_INTERVAL * STOP_ACK_TRIES
    } else {
        request_timeout
    }
}
