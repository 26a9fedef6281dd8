//! A guard in front of tokio-modbus's server decoder, which panics on some malformed writes (FC 15
//! with more coils than its bytes hold; FC 16 and 23 whose doubled quantity overflows). It also
//! closes a connection whose MBAP header no frame has (length over 254 or under 2, protocol id not
//! 0) or whose frame does not complete within [`FRAME_DEADLINE`]: MBAP has no sync marker, so
//! closing is the only way out.

use std::time::Duration;

use tokio::io::{AsyncRead, AsyncReadExt, AsyncWrite, AsyncWriteExt, DuplexStream};
use tokio::net::TcpStream;
use tokio::task::JoinHandle;

/// MBAP header: transaction, protocol, length (unit id + PDU), unit id.
const HEADER_LEN: usize = 7;
/// Largest MBAP length field: the unit id and a 253-byte PDU (Modbus application protocol).
const MAX_LENGTH: u16 = 254;
/// How long a frame may take to arrive once its first byte has.
pub const FRAME_DEADLINE: Duration = Duration::from_secs(1);

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

/// Why an MBAP header cannot start a Modbus TCP frame, if it cannot.
pub fn bad_header(header: &[u8; HEADER_LEN]) -> Option<String> {
    let protocol = u16::from_be_bytes([header[2], header[3]]);
    let length = u16::from_be_bytes([header[4], header[5]]);
    if protocol != 0 {
        Some(format!("protocol id {protocol}, not 0 (Modbus)"))
    } else if !(2..=MAX_LENGTH).contains(&length) {
        Some(format!("length {length} outside 2-{MAX_LENGTH}"))
    } else {
        None
    }
}

/// Forwards checked frames until the client leaves or sends a bad or stalled one.
async fn relay_requests(
    from_client: &mut (impl AsyncRead + Unpin),
    to_server: &mut (impl AsyncWrite + Unpin),
) {
    let mut header = [0u8; HEADER_LEN];
    loop {
        // An idle connection may wait for its next frame as long as it likes.
        if from_client.read_exact(&mut header[..1]).await.is_err() {
            return;
        }
        let pdu = match tokio::time::timeout(
            FRAME_DEADLINE,
            rest_of_frame(from_client, &mut header),
        )
        .await
        {
            Ok(Ok(pdu)) => pdu,
            Ok(Err(Ended)) => return,
            Err(_) => {
                tracing::warn!(
                    "sim modbus: a frame did not complete within {FRAME_DEADLINE:?} of its first byte; closing the connection"
                );
                return;
            }
        };
        if let Some(why) = malformed(&pdu) {
            tracing::warn!("sim modbus: malformed request ({why}); closing the connection");
            return;
        }
        if to_server.write_all(&header).await.is_err() || to_server.write_all(&pdu).await.is_err() {
            return;
        }
    }
}

/// The connection ended, or its header was refused (and logged).
struct Ended;

/// Reads the rest of a frame whose first byte is in `header[0]`; returns its PDU.
async fn rest_of_frame(
    from_client: &mut (impl AsyncRead + Unpin),
    header: &mut [u8; HEADER_LEN],
) -> Result<Vec<u8>, Ended> {
    from_client
        .read_exact(&mut header[1..])
        .await
        .map_err(|_| Ended)?;
    if let Some(why) = bad_header(header) {
        tracing::warn!("sim modbus: not a Modbus TCP header ({why}); closing the connection");
        return Err(Ended);
    }
    let length = usize::from(u16::from_be_bytes([header[4], header[5]]));
    let mut pdu = vec![0u8; length - 1];
    from_client.read_exact(&mut pdu).await.map_err(|_| Ended)?;
    Ok(pdu)
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
    fn headers_no_modbus_tcp_frame_has_are_caught() {
        let header = |protocol: u16, length: u16| {
            let [p0, p1] = protocol.to_be_bytes();
            let [l0, l1] = length.to_be_bytes();
            [0, 1, p0, p1, l0, l1, 1]
        };
        assert_eq!(bad_header(&header(0, 6)), None);
        assert_eq!(bad_header(&header(0, 2)), None);
        assert_eq!(bad_header(&header(0, 254)), None);
        assert!(bad_header(&header(0, 255)).is_some_and(|why| why.contains("length 255")));
        assert!(bad_header(&header(0, 65535)).is_some());
        assert!(bad_header(&header(0, 0)).is_some());
        assert!(bad_header(&header(0, 1)).is_some());
        assert!(bad_header(&header(1, 6)).is_some_and(|why| why.contains("protocol id 1")));
    }

    #[test]
    fn well_formed_frames_pass() {
        assert_eq!(malformed(&[0x0F, 0, 0, 0, 3, 1, 0b101]), None);
        assert_eq!(malformed(&[0x10, 0, 200, 0, 1, 2, 0, 2]), None);
        assert_eq!(malformed(&[0x04, 0xFF, 0xFF, 0, 1]), None);
        assert_eq!(malformed(&[]), None);
    }

    /// Runs the request relay over in-memory pipes; returns the client's writer, the bytes the
    /// server side receives, and the relay task.
    fn relay() -> (DuplexStream, DuplexStream, JoinHandle<()>) {
        let (client, mut from_client) = tokio::io::duplex(4096);
        let (mut to_server, server) = tokio::io::duplex(4096);
        let task = tokio::spawn(async move {
            relay_requests(&mut from_client, &mut to_server).await;
        });
        (client, server, task)
    }

    const READ_STATE: [u8; 12] = [0, 1, 0, 0, 0, 6, 1, 4, 0, 0, 0, 1];

    // Real time (the crate has no tokio test-util): the bounds only say "not before the
    // deadline" and "well before several deadlines".
    #[tokio::test]
    async fn a_frame_that_stops_arriving_ends_the_relay_at_the_deadline() {
        let (mut client, mut server, task) = relay();
        client.write_all(&READ_STATE).await.expect("write");
        let mut forwarded = [0u8; 12];
        server.read_exact(&mut forwarded).await.expect("forwarded");
        assert_eq!(forwarded, READ_STATE);
        // A header announcing 200 bytes, then a trickle of one byte per 300 ms: the trickle
        // must not extend the deadline, counted from the frame's first byte.
        let started = tokio::time::Instant::now();
        client
            .write_all(&[0, 2, 0, 0, 0, 200, 1])
            .await
            .expect("write");
        while !task.is_finished() && started.elapsed() < FRAME_DEADLINE * 3 {
            let _ = client.write_all(&[0]).await;
            tokio::time::sleep(Duration::from_millis(300)).await;
        }
        assert!(task.is_finished(), "the relay still waits");
        let waited = started.elapsed();
        assert!(
            waited >= FRAME_DEADLINE && waited < FRAME_DEADLINE * 5,
            "ended after {waited:?}"
        );
    }

    #[tokio::test]
    async fn an_idle_connection_is_not_timed_out() {
        let (mut client, mut server, task) = relay();
        tokio::time::sleep(FRAME_DEADLINE * 3 / 2).await;
        assert!(!task.is_finished(), "idle between frames is allowed");
        client.write_all(&READ_STATE).await.expect("write");
        let mut forwarded = [0u8; 12];
        server.read_exact(&mut forwarded).await.expect("forwarded");
        assert_eq!(forwarded, READ_STATE);
    }

    #[tokio::test]
    async fn an_impossible_header_ends_the_relay_without_forwarding_it() {
        let (mut client, mut server, task) = relay();
        client
            .write_all(&[0, 1, 0, 0, 0xFF, 0xFF, 1, 4])
            .await
            .expect("write");
        task.await.expect("the relay ends");
        let mut rest = Vec::new();
        server.read_to_end(&mut rest).await.expect("read");
        assert!(rest.is_empty(), "forwarded {rest:02x?}");
    }
}
