//! A guard in front of tokio-modbus's server decoder: it panics on some malformed write
//! requests (FC 15 with more coils than its data bytes hold; FC 16 and 23 with a quantity whose
//! doubling overflows a u16). Frames are checked here, and a connection that sends one is
//! closed, as the decoder does for the malformed frames it does catch.

use tokio::io::{AsyncRead, AsyncReadExt, AsyncWrite, AsyncWriteExt, DuplexStream};
use tokio::net::TcpStream;
use tokio::task::JoinHandle;

/// MBAP header: transaction, protocol, length (unit id + PDU), unit id.
const HEADER_LEN: usize = 7;

/// Aborts the relay tasks when the connection's service is dropped.
pub struct Relay {
    tasks: [JoinHandle<()>; 2],
}

impl Drop for Relay {
    fn drop(&mut self) {
        for task in &self.tasks {
            task.abort();
        }
    }
}

/// Why a request PDU would crash the decoder, if it would.
pub fn malformed(pdu: &[u8]) -> Option<&'static str> {
    let u16_at = |i: usize| pdu.get(i..i + 2).map(|b| u16::from_be_bytes([b[0], b[1]]));
    match pdu.first() {
        Some(0x0F) => match (u16_at(3), pdu.get(5)) {
            (Some(quantity), Some(&bytes)) if u32::from(quantity) > u32::from(bytes) * 8 => {
                Some("FC 15: more coils than its data bytes hold")
            }
            _ => None,
        },
        Some(0x10) => match u16_at(3) {
            Some(quantity) if quantity > 0x7F => Some("FC 16: more registers than a frame holds"),
            _ => None,
        },
        Some(0x17) => match u16_at(7) {
            Some(quantity) if quantity > 0x7F => Some("FC 23: more registers than a frame holds"),
            _ => None,
        },
        _ => None,
    }
}

/// Relays `client` through checked frames; the server talks to the returned stream.
pub fn guard(client: TcpStream) -> (DuplexStream, Relay) {
    let (server_side, relay_side) = tokio::io::duplex(64 * 1024);
    let (mut from_client, mut to_client) = client.into_split();
    let (mut from_server, mut to_server) = tokio::io::split(relay_side);
    let replies = tokio::spawn(async move {
        let _ = tokio::io::copy(&mut from_server, &mut to_client).await;
    });
    let requests = tokio::spawn(async move {
        relay_requests(&mut from_client, &mut to_server).await;
        // The server sees the end of the stream, ends the connection, and so the reply relay.
        let _ = to_server.shutdown().await;
    });
    (
        server_side,
        Relay {
            tasks: [replies, requests],
        },
    )
}

/// Forwards checked frames until the client goes away or sends a malformed one.
async fn relay_requests(
    from_client: &mut (impl AsyncRead + Unpin),
    to_server: &mut (impl AsyncWrite + Unpin),
) {
    let mut header = [0u8; HEADER_LEN];
    loop {
        if from_client.read_exact(&mut header).await.is_err() {
            return;
        }
        let length = usize::from(u16::from_be_bytes([header[4], header[5]]));
        let mut pdu = vec![0u8; length.saturating_sub(1)];
        if from_client.read_exact(&mut pdu).await.is_err() {
            return;
        }
        if let Some(why) = malformed(&pdu) {
            tracing::warn!("sim modbus: malformed request ({why}); closing the connection");
            return;
        }
        if to_server.write_all(&header).await.is_err() || to_server.write_all(&pdu).await.is_err() {
            return;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_the_decoder_would_crash_on_are_caught() {
        // 2001 coils in one data byte.
        assert!(malformed(&[0x0F, 0, 0, 0x07, 0xD1, 1, 0]).is_some());
        // 32768 registers: the decoder's quantity * 2 overflows.
        assert!(malformed(&[0x10, 0, 200, 0x80, 0x00, 0]).is_some());
        assert!(malformed(&[0x17, 0, 0, 0, 1, 0, 200, 0x80, 0x00, 0]).is_some());
    }

    #[test]
    fn well_formed_frames_pass() {
        assert_eq!(malformed(&[0x0F, 0, 0, 0, 3, 1, 0b101]), None);
        assert_eq!(malformed(&[0x10, 0, 200, 0, 1, 2, 0, 2]), None);
        assert_eq!(malformed(&[0x04, 0xFF, 0xFF, 0, 1]), None);
        assert_eq!(malformed(&[]), None);
    }
}
