//! A scriptable Talos operator on loopback for link and command-line tests.
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

/// A listening test operator. Every frame it decodes is sent on `received`.
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
                'conn: loop {
                    while let Ok(Some(item)) = codec.decode(&mut buf) {
                        let actions = match &item {
                            Decoded::TalosFrame(f) => script(f),
                            Decoded::Rejected(_) => Vec::new(),
                        };
                        let _ = tx.send(item);
                        for action in actions {
                            match action {
                                Action::Write(bytes) => {
                                    if stream.write_all(&bytes).await.is_err() {
                                        break 'conn;
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
