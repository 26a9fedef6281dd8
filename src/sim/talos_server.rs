//! The simulated Talos operator on TCP.
//!
//! Several clients may connect at once: every command goes through the one arm task, in arrival
//! order, so they cannot corrupt each other; any client's START refreshes the arm's single
//! watchdog and any client's STOP stops it. (The deployed operator takes one client at a time;
//! the simulator is more permissive so `armjog send` can be used beside a running console.)

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

use futures::SinkExt;
use tokio::io::AsyncWriteExt;
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::watch;
use tokio_util::codec::FramedWrite;

use super::operator::Operator;
use super::world::SimArm;
use crate::net::{DEFAULT_FRAME_DEADLINE, FrameReader};
use crate::talos::Dialect;
use crate::talos::ack::ACK;
use crate::talos::command::REPLY_BIT;
use crate::talos::frame::{Decoded, RejectReason};
use crate::talos::{Checksum, CommandValue, Frame, FrameCodec, Reply, Request, ReturnCode};

/// Network misbehaviour to inject, for tests and training. Changes apply at once.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct NetworkFaults {
    /// Wait this long before each reply.
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
}

impl Default for TalosServerConfig {
    fn default() -> Self {
        TalosServerConfig {
            checksum: Checksum::Crc16,
            dialect: Dialect::Icd,
            frame_deadline: DEFAULT_FRAME_DEADLINE,
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
    loop {
        match listener.accept().await {
            Ok((stream, peer)) => {
                tracing::info!("sim talos: client {peer} connected");
                let _ = stream.set_nodelay(true);
                tokio::spawn(connection(
                    stream,
                    arm.clone(),
                    config,
                    faults.clone(),
                    replies.clone(),
                ));
            }
            Err(e) => {
                tracing::warn!("sim talos: accept failed: {e}");
                tokio::time::sleep(Duration::from_millis(50)).await;
            }
        }
    }
}

async fn connection(
    stream: TcpStream,
    arm: SimArm,
    config: TalosServerConfig,
    faults: watch::Receiver<NetworkFaults>,
    replies: Arc<AtomicU64>,
) {
    let peer = stream
        .peer_addr()
        .map_or_else(|_| "an unknown peer".to_string(), |addr| addr.to_string());
    let (read_half, write_half) = stream.into_split();
    let mut frames = FrameReader::new(
        read_half,
        FrameCodec::new(config.checksum),
        config.frame_deadline,
        format!("sim talos client {peer}"),
    );
    let mut writer = FramedWrite::new(write_half, FrameCodec::new(config.checksum));
    let mut seen: u32 = 0;
    while let Some(item) = frames.next().await {
        let Ok(item) = item else { break };
        seen = seen.saturating_add(1);
        let faults_now = faults.borrow().clone();
        let answer = match config.dialect {
            Dialect::Icd => answer_icd(&arm, item).await,
            Dialect::Ack => answer_ack(&arm, item).await,
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
                Answer::Frame(frame) => writer.send(frame).await,
                Answer::Ack => writer.get_mut().write_all(&ACK).await,
            };
            if sent.is_err() {
                break;
            }
        }
        if faults_now
            .close_after_frames
            .is_some_and(|limit| seen >= limit)
        {
            tracing::info!("sim talos: closing the connection (fault injection)");
            break;
        }
    }
    tracing::info!("sim talos: client disconnected");
}

enum Answer {
    Frame(Frame),
    Ack,
}

/// A reply frame for any command value, known or not, carrying only a return code.
fn bare_reply(id: u32, command: u16, code: ReturnCode) -> Frame {
    Frame::new(id | 1, command | REPLY_BIT, code.0.to_be_bytes().to_vec())
}

async fn answer_icd(arm: &SimArm, item: Decoded) -> Option<Answer> {
    let frame = match item {
        Decoded::Frame(frame) => frame,
        Decoded::Rejected(rejection) => {
            tracing::info!("sim talos: rejected input: {rejection}");
            // A frame whose checksum failed still names its exchange: say so.
            return match (rejection.reason, rejection.header) {
                (RejectReason::BadChecksum { .. }, Some(h)) if h.command & REPLY_BIT == 0 => Some(
                    Answer::Frame(bare_reply(h.id, h.command, ReturnCode::BAD_CHECKSUM)),
                ),
                _ => None,
            };
        }
    };
    if frame.is_reply() {
        return Some(Answer::Frame(bare_reply(
            frame.id,
            frame.command,
            ReturnCode::UNKNOWN_COMMAND,
        )));
    }
    let reply = match Request::from_frame(&frame) {
        Ok(request) => arm
            .with(move |arm, operator| operator.handle(arm, request))
            .await
            .ok()?,
        Err(error) => {
            let code = Operator::reply_to_undecodable(&error);
            match CommandValue::from_request_value(frame.command) {
                Some(command) => Reply::error(command, code),
                None => return Some(Answer::Frame(bare_reply(frame.id, frame.command, code))),
            }
        }
    };
    match reply.to_frame(frame.id) {
        Ok(frame) => Some(Answer::Frame(frame)),
        Err(e) => {
            tracing::error!("sim talos: cannot encode reply: {e}");
            None
        }
    }
}

/// The deployed operator: "ACK\0" for every frame, before validating it; only commands
/// 0x0000-0x0004 do anything.
async fn answer_ack(arm: &SimArm, item: Decoded) -> Option<Answer> {
    if let Decoded::Frame(frame) = item
        && let Ok(request) = Request::from_frame(&frame)
        && Dialect::Ack.supports(request.command())
    {
        let _ = arm
            .with(move |arm, operator| operator.handle(arm, request))
            .await;
    }
    Some(Answer::Ack)
}
