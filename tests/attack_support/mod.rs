//! Shared by the attack tests: hand-built Talos and Modbus requests, and readers that wait a
//! bounded time for the reply to one of them.
#![allow(dead_code)]

pub mod process;

use std::time::Duration;

use bytes::BytesMut;
use tokio::io::AsyncReadExt;
use tokio::net::TcpStream;
use tokio::time::{Instant, timeout_at};
use tokio_util::codec::Decoder;

use armjog::talos::frame::Decoded;
use armjog::talos::{Checksum, CommandValue, FrameCodec, Reply, Request, ReturnCode, TalosFrame};

/// How long a valid request may wait for its reply. Generous: a garbage header may hold the
/// Talos decoder for its 1 s per-frame deadline, and CI machines are loaded.
pub const REPLY_BOUND: Duration = Duration::from_secs(5);

/// An even request id whose bytes are none of the ICD's command values (with or without the
/// reply bit), so that if garbage before it leaves the decoder mid-header, no header read across
/// the id looks like a plausible frame start.
pub fn distinctive_id(n: u32) -> u32 {
    let high = 0x20 + ((n >> 5) & 0x3F) as u8;
    let low = 0x20 + ((n & 0x1F) << 1) as u8;
    u32::from_be_bytes([0xA7, 0x7A, high, low])
}

/// A Talos handshake request's bytes.
pub fn talos_handshake(id: u32, checksum: Checksum) -> Vec<u8> {
    Request::Handshake { oid: Some(1) }
        .to_frame(id)
        .expect("a handshake encodes")
        .to_bytes(checksum)
        .expect("a handshake fits a frame")
}

/// Reads Talos frames from `stream` until the reply to request `id` arrives; an error says what
/// came instead (a close, a timeout).
pub async fn talos_reply_to(
    stream: &mut TcpStream,
    checksum: Checksum,
    id: u32,
    bound: Duration,
) -> Result<TalosFrame, String> {
    let deadline = Instant::now() + bound;
    let mut codec = FrameCodec::new(checksum);
    let mut buf = BytesMut::new();
    loop {
        while let Some(item) = codec
            .decode(&mut buf)
            .map_err(|e| format!("client decoder: {e}"))?
        {
            if let Decoded::TalosFrame(frame) = item
                && frame.is_reply()
                && frame.id == id | 1
            {
                return Ok(frame);
            }
        }
        match timeout_at(deadline, stream.read_buf(&mut buf)).await {
            Err(_) => return Err(format!("no reply to id {id:#010x} within {bound:?}")),
            Ok(Ok(0)) => return Err(format!("connection closed before the reply to {id:#010x}")),
            Ok(Err(e)) => return Err(format!("read failed before the reply to {id:#010x}: {e}")),
            Ok(Ok(_)) => {}
        }
    }
}

/// Checks that `frame` is a successful handshake reply.
pub fn check_handshake_reply(frame: &TalosFrame) -> Result<(), String> {
    match Reply::from_frame(frame) {
        Ok(Reply::Handshake { return_code, .. }) if return_code == ReturnCode::OK => Ok(()),
        other => Err(format!(
            "expected an OK handshake reply ({:#06x}), got {other:?} from {frame:?}",
            CommandValue::Handshake.reply_value()
        )),
    }
}

/// Connects to a Talos server and has one handshake answered.
pub async fn talos_handshake_answered(
    addr: std::net::SocketAddr,
    checksum: Checksum,
    id: u32,
) -> Result<(), String> {
    use tokio::io::AsyncWriteExt;
    let mut stream = TcpStream::connect(addr)
        .await
        .map_err(|e| format!("cannot connect to the Talos server at {addr}: {e}"))?;
    stream
        .write_all(&talos_handshake(id, checksum))
        .await
        .map_err(|e| format!("cannot send a handshake: {e}"))?;
    let reply = talos_reply_to(&mut stream, checksum, id, REPLY_BOUND).await?;
    check_handshake_reply(&reply)
}

/// Modbus TCP: read input register 0 (the robot state) on unit 1.
pub fn modbus_read_state(transaction: u16) -> Vec<u8> {
    let [t0, t1] = transaction.to_be_bytes();
    vec![t0, t1, 0, 0, 0, 6, 1, 0x04, 0, 0, 0, 1]
}

/// What came back for one Modbus request.
#[derive(Debug, PartialEq, Eq)]
pub enum ModbusOutcome {
    /// The PDU (function code onwards) answering the transaction.
    Reply(Vec<u8>),
    /// The server closed the connection first.
    Closed,
    /// Neither within the bound.
    Silent,
}

/// Reads Modbus TCP replies until the one for `transaction`, a close, or the bound.
pub async fn modbus_reply_to(
    stream: &mut TcpStream,
    transaction: u16,
    bound: Duration,
) -> ModbusOutcome {
    let deadline = Instant::now() + bound;
    loop {
        let mut header = [0u8; 7];
        match timeout_at(deadline, stream.read_exact(&mut header)).await {
            Err(_) => return ModbusOutcome::Silent,
            Ok(Err(_)) => return ModbusOutcome::Closed,
            Ok(Ok(_)) => {}
        }
        let length = usize::from(u16::from_be_bytes([header[4], header[5]]));
        let mut pdu = vec![0u8; length.saturating_sub(1)];
        match timeout_at(deadline, stream.read_exact(&mut pdu)).await {
            Err(_) => return ModbusOutcome::Silent,
            Ok(Err(_)) => return ModbusOutcome::Closed,
            Ok(Ok(_)) => {}
        }
        if u16::from_be_bytes([header[0], header[1]]) == transaction {
            return ModbusOutcome::Reply(pdu);
        }
    }
}

/// Whether `pdu` is a proper answer to [`modbus_read_state`]: function 4, two bytes, one register.
pub fn is_state_reply(pdu: &[u8]) -> bool {
    pdu.len() == 4 && pdu[0] == 0x04 && pdu[1] == 2
}

/// Connects to a Modbus server and has the robot state read answered.
pub async fn modbus_state_answered(
    addr: std::net::SocketAddr,
    transaction: u16,
) -> Result<(), String> {
    use tokio::io::AsyncWriteExt;
    let mut stream = TcpStream::connect(addr)
        .await
        .map_err(|e| format!("cannot connect to the Modbus server at {addr}: {e}"))?;
    stream
        .write_all(&modbus_read_state(transaction))
        .await
        .map_err(|e| format!("cannot send a read: {e}"))?;
    match modbus_reply_to(&mut stream, transaction, REPLY_BOUND).await {
        ModbusOutcome::Reply(pdu) if is_state_reply(&pdu) => Ok(()),
        other => Err(format!(
            "robot state read on a fresh connection: expected 04 02 xx xx, got {other:?}"
        )),
    }
}
