//! A scriptable Talos operator on loopback for link and command-line tests, and the tool pose
//! the tests' arms report at home.
#![allow(dead_code)]

use std::sync::Arc;

use bytes::BytesMut;
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpListener;
use tokio::sync::mpsc;
use tokio_util::codec::Decoder;

use armjog::talos::frame::Decoded;
use armjog::talos::{Checksum, FrameCodec, TalosFrame};

/// What the operator does with one received frame.
pub enum Action {
    /// Write these bytes.
    Write(Vec<u8>),
    /// Wait this long, then go on with the next action.
    Sleep(std::time::Duration),
    /// Close the connection.
    Close,
}

pub type Script = Arc<dyn Fn(&TalosFrame) -> Vec<Action> + Send + Sync>;

/// A listening test operator. Every frame it decodes is sent on `received`, before it is
/// answered.
pub struct TestOperator {
    pub addr: String,
    pub received: mpsc::UnboundedReceiver<Decoded>,
}

impl TestOperator {
    /// Serves connections one after another with `script` answering each frame.
    pub async fn start(checksum: Checksum, script: Script) -> TestOperator {
        let listener = TcpListener::bind("127.0.0.1:0").await.expect("bind");
        let addr = listener.local_addr().expect("addr").to_string();
        let (tx, rx) = mpsc::unbounded_channel();
        tokio::spawn(async move {
            while let Ok((mut stream, _)) = listener.accept().await {
                let mut codec = FrameCodec::new(checksum);
                let mut buf = BytesMut::new();
                // A peer that closed cannot take replies, but what it wrote first is still
                // decoded and reported.
                let mut writable = true;
                'conn: loop {
                    while let Ok(Some(item)) = codec.decode(&mut buf) {
                        // Reported before the script acts on it: a test that sees what a frame
                        // did (an arm that moved) finds the frame on `received`.
                        let frame = match &item {
                            Decoded::TalosFrame(f) => Some(f.clone()),
                            Decoded::Rejected(_) => None,
                        };
                        let _ = tx.send(item);
                        let actions = frame.map(|f| script(&f)).unwrap_or_default();
                        for action in actions {
                            match action {
                                Action::Write(bytes) => {
                                    if writable && stream.write_all(&bytes).await.is_err() {
                                        writable = false;
                                    }
                                }
                                Action::Sleep(d) => tokio::time::sleep(d).await,
                                Action::Close => break 'conn,
                            }
                        }
                    }
                    match stream.read_buf(&mut buf).await {
                        Ok(0) | Err(_) => break,
                        Ok(_) => {}
                    }
                }
            }
        });
        TestOperator { addr, received: rx }
    }

    /// The next decoded frame, or panics after a second.
    pub async fn next_frame(&mut self) -> TalosFrame {
        let item = tokio::time::timeout(std::time::Duration::from_secs(1), self.received.recv())
            .await
            .expect("operator received nothing within 1 s")
            .expect("operator gone");
        match item {
            Decoded::TalosFrame(f) => f,
            Decoded::Rejected(r) => panic!("operator rejected a frame: {r}"),
        }
    }
}

impl TestOperator {
    /// Every frame received until none comes for `settle`.
    pub async fn frames_until_quiet(&mut self, settle: std::time::Duration) -> Vec<TalosFrame> {
        let mut frames = Vec::new();
        while let Ok(Some(item)) = tokio::time::timeout(settle, self.received.recv()).await {
            if let Decoded::TalosFrame(f) = item {
                frames.push(f);
            }
        }
        frames
    }
}

/// An OK reply of the ICD dialect to `frame`'s request (a version for a handshake, a speed for
/// Get Speed).
pub fn ok_reply(frame: &TalosFrame) -> armjog::talos::Reply {
    use armjog::talos::{Reply, Request, ReturnCode};
    let request = Request::from_frame(frame).expect("valid request");
    match request {
        Request::Handshake { .. } => Reply::Handshake {
            return_code: ReturnCode::OK,
            major_version: 1,
            minor_version: 2,
        },
        Request::GetSpeed => Reply::GetSpeed {
            return_code: ReturnCode::OK,
            speed: 42,
        },
        other => Reply::error(other.command(), ReturnCode::OK),
    }
}

/// A script that answers every frame OK in the ICD dialect.
pub fn answering(checksum: Checksum) -> Script {
    Arc::new(move |f: &TalosFrame| vec![Action::Write(reply_bytes(&ok_reply(f), f.id, checksum))])
}

/// A script that answers every frame with the ack dialect's "ACK\0".
pub fn acking() -> Script {
    Arc::new(|_: &TalosFrame| vec![Action::Write(b"ACK\0".to_vec())])
}

/// Command value and payload of each frame, to compare with [`stop_set`].
pub fn wire(frames: &[TalosFrame]) -> Vec<(u16, Vec<u8>)> {
    frames
        .iter()
        .map(|f| (f.command, f.payload.clone()))
        .collect()
}

/// The stop set as it must reach the operator, written by hand from the ICDs. ICD dialect:
/// Cartesian Move STOP (0x0007), Polar Pan STOP (0x0004), then Execute Hardware Operation
/// (0x0008) with subcommand STOP_ALL_JOINTS (0x0004), RESERVED 0 and no body
/// (`docs/hardware-icd.md`). Ack dialect (commands 0x0000-0x0004 only): Polar Pan STOP.
pub fn stop_set(dialect: armjog::talos::Dialect) -> Vec<(u16, Vec<u8>)> {
    match dialect {
        armjog::talos::Dialect::Icd => vec![
            (0x0007, vec![]),
            (0x0004, vec![]),
            (0x0008, vec![0x00, 0x04, 0x00, 0x00, 0x00, 0x00]),
        ],
        armjog::talos::Dialect::Ack => vec![(0x0004, vec![])],
    }
}

/// Bytes of a reply frame.
pub fn reply_bytes(reply: &armjog::talos::Reply, request_id: u32, checksum: Checksum) -> Vec<u8> {
    reply
        .to_frame(request_id)
        .expect("reply frame")
        .to_bytes(checksum)
        .expect("reply bytes")
}

// ---- known-answer helpers shared by the Talos vector and decoder tests ----

/// Hex digits to bytes; spaces and `|` are only for reading.
pub fn hex(s: &str) -> Vec<u8> {
    let digits: String = s
        .chars()
        .filter(|c| !c.is_ascii_whitespace() && *c != '|')
        .collect();
    hex::decode(&digits).unwrap_or_else(|e| panic!("bad hex in {s:?}: {e}"))
}

/// Independent CRC-16/CCITT-FALSE: poly 0x1021, init 0xFFFF, MSB first, no reflection, xorout 0.
pub fn crc16_ccitt_false(bytes: &[u8]) -> u16 {
    let mut crc: u16 = 0xFFFF;
    for &byte in bytes {
        crc ^= u16::from(byte) << 8;
        for _ in 0..8 {
            crc = if crc & 0x8000 != 0 {
                (crc << 1) ^ 0x1021
            } else {
                crc << 1
            };
        }
    }
    crc
}

/// The Gen3's tool pose at home (base frame, m and deg), as the tests' arms report it.
pub fn home_tcp() -> armjog::kortex::Pose {
    armjog::kortex::Pose {
        x: 0.4566,
        y: 0.001,
        z: 0.4338,
        theta_x: 90.0,
        theta_y: 0.0,
        theta_z: 90.0,
    }
}
