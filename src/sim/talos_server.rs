//! The simulated Talos operator on TCP. Several clients may connect; every command goes through the
//! one arm task in order, and any client's STOP stops it. [`TalosServerConfig::one_client`] serves
//! as the deployed operator does: it accepts nothing while it serves a client.
//!
//! A closed connection stops the continuous motion it last started or refreshed
//! ([`Operator::client_gone`]); rejected frames are logged, rate-limited ([`RejectLog`]): see
//! `docs/simulator.md`.

use std::fmt;
use std::net::SocketAddr;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

use futures::SinkExt;
use tokio::io::AsyncWriteExt;
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::watch;
use tokio_util::codec::FramedWrite;

use super::operator::{ClientId, Operator};
use super::reject_log::RejectLog;
use super::world::SimArm;
use crate::net::{DEFAULT_FRAME_DEADLINE, FrameReader};
use crate::talos::Dialect;
use crate::talos::ack::ACK;
use crate::talos::command::REPLY_BIT;
use crate::talos::frame::{Decoded, RejectReason, Rejection};
use crate::talos::message::DecodeError;
use crate::talos::{Checksum, CommandValue, FrameCodec, Reply, Request, ReturnCode, TalosFrame};

/// Network misbehaviour to inject, for tests and training. Changes apply at once.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct NetworkFaults {
    pub reply_delay: Duration,
    /// Drop every Nth reply (1 drops them all; 0 drops none). Commands are still carried out.
    pub drop_every_nth_reply: u32,
    /// Close each connection after this many frames.
    pub close_after_frames: Option<u32>,
}

/// How the simulated operator speaks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TalosServerConfig {
    pub checksum: Checksum,
    pub dialect: Dialect,
    /// How long a frame may take from its first byte to its last before it is given up.
    pub frame_deadline: Duration,
    /// Serve one client at a time, as the deployed operator does (see the module docs).
    pub one_client: bool,
}

impl Default for TalosServerConfig {
    fn default() -> Self {
        TalosServerConfig {
            checksum: Checksum::Crc16,
            dialect: Dialect::Icd,
            frame_deadline: DEFAULT_FRAME_DEADLINE,
            one_client: false,
        }
    }
}

/// Accepts connections until the listener task is aborted.
pub async fn serve(
    listener: TcpListener,
    arm: SimArm,
    config: TalosServerConfig,
    faults: watch::Receiver<NetworkFaults>,
) {
    let replies = Arc::new(AtomicU64::new(0));
    let mut next_client = 0u64;
    loop {
        match listener.accept().await {
            Ok((stream, peer)) => {
                tracing::info!("sim talos: client {peer} connected");
                let _ = stream.set_nodelay(true);
                next_client += 1;
                let served = connection(
                    stream,
                    Client::new(ClientId(next_client), peer),
                    arm.clone(),
                    config,
                    faults.clone(),
                    replies.clone(),
                );
                if config.one_client {
                    // One client at a time: the next waits in the kernel's queue.
                    served.await;
                } else {
                    tokio::spawn(served);
                }
            }
            Err(e) => {
                tracing::warn!("sim talos: accept failed: {e}");
                tokio::time::sleep(Duration::from_millis(50)).await;
            }
        }
    }
}

/// One connection as the server sees it.
struct Client {
    id: ClientId,
    peer: SocketAddr,
    rejects: RejectLog,
}

impl Client {
    fn new(id: ClientId, peer: SocketAddr) -> Client {
        Client {
            id,
            peer,
            rejects: RejectLog::new(peer),
        }
    }

    fn reject(&mut self, reason: impl fmt::Display) {
        self.rejects.rejected(now(), reason);
    }
}

/// Why a connection ended (its words in the simulator's log).
#[derive(Debug, thiserror::Error)]
enum Ending {
    #[error("end of stream")]
    EndOfStream,
    #[error("read error: {0}")]
    ReadError(String),
    #[error("write error: {0}")]
    WriteError(String),
    #[error("closed by fault injection")]
    FaultInjection,
}

fn now() -> std::time::Instant {
    tokio::time::Instant::now().into_std()
}

async fn connection(
    stream: TcpStream,
    mut client: Client,
    arm: SimArm,
    config: TalosServerConfig,
    faults: watch::Receiver<NetworkFaults>,
    replies: Arc<AtomicU64>,
) {
    let (read_half, write_half) = stream.into_split();
    let mut frames = FrameReader::new(
        read_half,
        FrameCodec::new(config.checksum),
        config.frame_deadline,
        format!("sim talos client {}", client.peer),
    );
    let mut writer = FramedWrite::new(write_half, FrameCodec::new(config.checksum));
    let mut seen: u32 = 0;
    let mut ending = Ending::EndOfStream;
    while let Some(item) = frames.next().await {
        let item = match item {
            Ok(item) => item,
            Err(e) => {
                ending = Ending::ReadError(e.to_string());
                break;
            }
        };
        seen = seen.saturating_add(1);
        let faults_now = faults.borrow().clone();
        let answer = match config.dialect {
            Dialect::Icd => answer_icd(&arm, item, &mut client).await,
            Dialect::Ack => answer_ack(&arm, item, &mut client).await,
        };
        let Some(answer) = answer else { continue };
        if !faults_now.reply_delay.is_zero() {
            tokio::time::sleep(faults_now.reply_delay).await;
        }
        let n = replies.fetch_add(1, Ordering::Relaxed) + 1;
        let nth = u64::from(faults_now.drop_every_nth_reply);
        let dropped = nth != 0 && n.is_multiple_of(nth);
        if !dropped {
            let sent = match answer {
                Answer::TalosFrame(frame) => writer.send(frame).await,
                Answer::Ack => writer.get_mut().write_all(&ACK).await,
            };
            if let Err(e) = sent {
                ending = Ending::WriteError(e.to_string());
                break;
            }
        }
        if faults_now
            .close_after_frames
            .is_some_and(|limit| seen >= limit)
        {
            ending = Ending::FaultInjection;
            break;
        }
    }
    client_gone(&arm, &mut client, &ending).await;
}

/// The end of a connection: stops the continuous motion the client holds, at once.
async fn client_gone(arm: &SimArm, client: &mut Client, ending: &Ending) {
    client.rejects.finish();
    let (id, peer) = (client.id, client.peer);
    match arm
        .with(move |arm, operator| operator.client_gone(id, arm))
        .await
    {
        Ok(true) => tracing::info!(
            "sim talos: client {peer} disconnected ({ending}): stopped the continuous motion it held"
        ),
        Ok(false) => tracing::info!("sim talos: client {peer} disconnected ({ending})"),
        Err(e) => tracing::warn!("sim talos: client {peer} disconnected ({ending}); {e}"),
    }
}

enum Answer {
    TalosFrame(TalosFrame),
    Ack,
}

/// The answer to any command value, known or not: a reply frame carrying only a return code.
fn bare_reply(id: u32, command: u16, code: ReturnCode) -> Option<Answer> {
    let payload = code.0.to_be_bytes().to_vec();
    Some(Answer::TalosFrame(TalosFrame::new(
        id | 1,
        command | REPLY_BIT,
        payload,
    )))
}

/// Names a frame in the log: its id and command value.
fn label(id: u32, command: u16) -> String {
    match CommandValue::from_request_value(command) {
        Some(value) => format!("frame id {id} ({value}, 0x{command:04X})"),
        None => format!("frame id {id} (command 0x{command:04X})"),
    }
}

fn describe_rejection(rejection: &Rejection) -> String {
    match rejection.header {
        Some(h) => format!("{}: {rejection}", label(h.id, h.command)),
        None => format!("undecodable bytes: {rejection}"),
    }
}

/// Runs `request` from `client` on the operator; logs a refusal.
async fn carry_out(arm: &SimArm, client: &mut Client, id: u32, request: Request) -> Option<Reply> {
    let client_id = client.id;
    let command = request.command().request_value();
    let reply = arm
        .with(move |arm, operator| operator.handle_from(client_id, arm, request))
        .await
        .ok()?;
    let code = reply.return_code();
    if !code.is_ok() {
        client.reject(format_args!("{}: refused with {code}", label(id, command)));
    }
    Some(reply)
}

async fn answer_icd(arm: &SimArm, item: Decoded, client: &mut Client) -> Option<Answer> {
    client.rejects.poll(now());
    let frame = match item {
        Decoded::TalosFrame(frame) => frame,
        Decoded::Rejected(rejection) => {
            client.reject(describe_rejection(&rejection));
            // A frame whose checksum failed still names its exchange: say so.
            return match (rejection.reason, rejection.header) {
                (RejectReason::BadChecksum { .. }, Some(h)) if h.command & REPLY_BIT == 0 => {
                    bare_reply(h.id, h.command, ReturnCode::BAD_CHECKSUM)
                }
                _ => None,
            };
        }
    };
    if frame.is_reply() {
        client.reject(format_args!(
            "{}: a reply value; the operator takes requests",
            label(frame.id, frame.command)
        ));
        return bare_reply(frame.id, frame.command, ReturnCode::UNKNOWN_COMMAND);
    }
    let reply = match Request::from_frame(&frame) {
        Ok(request) => carry_out(arm, client, frame.id, request).await?,
        Err(error) => {
            client.reject(format_args!("{}: {error}", label(frame.id, frame.command)));
            let code = Operator::reply_to_undecodable(&error);
            match CommandValue::from_request_value(frame.command) {
                Some(command) => Reply::error(command, code),
                None => return bare_reply(frame.id, frame.command, code),
            }
        }
    };
    match reply.to_frame(frame.id) {
        Ok(frame) => Some(Answer::TalosFrame(frame)),
        Err(e) => {
            tracing::error!("sim talos: cannot encode reply: {e}");
            None
        }
    }
}

/// The deployed operator: "ACK\0" for every frame before validating; only 0x0000-0x0004 act.
async fn answer_ack(arm: &SimArm, item: Decoded, client: &mut Client) -> Option<Answer> {
    client.rejects.poll(now());
    match ack_request(item) {
        Ok((id, request)) => {
            carry_out(arm, client, id, request).await;
        }
        Err(reason) => client.reject(reason),
    }
    Some(Answer::Ack)
}

/// An ack-dialect frame's request and id, or why the deployed operator ignores it.
fn ack_request(item: Decoded) -> Result<(u32, Request), Ignored> {
    let frame = match item {
        Decoded::TalosFrame(frame) => frame,
        Decoded::Rejected(rejection) => {
            return Err(Ignored::Rejected(describe_rejection(&rejection)));
        }
    };
    let name = label(frame.id, frame.command);
    if frame.is_reply() {
        return Err(Ignored::Reply(name));
    }
    match CommandValue::from_request_value(frame.command) {
        None => return Err(Ignored::NotACommand(name)),
        Some(command) if !Dialect::Ack.supports(command) => return Err(Ignored::NotInAck(name)),
        Some(_) => {}
    }
    match Request::from_frame(&frame) {
        Ok(request) => Ok((frame.id, request)),
        Err(error) => Err(Ignored::Malformed(name, error)),
    }
}

/// Why the deployed operator does nothing with a frame, naming the frame.
#[derive(Debug, thiserror::Error)]
enum Ignored {
    #[error("{0}")]
    Rejected(String),
    #[error("{0}: a reply value; the operator takes requests")]
    Reply(String),
    #[error("{0}: not a command of the ICD")]
    NotACommand(String),
    #[error("{0}: the deployed operator implements only commands 0x0000-0x0004")]
    NotInAck(String),
    #[error("{0}: malformed payload: {1}")]
    Malformed(String, DecodeError),
}
