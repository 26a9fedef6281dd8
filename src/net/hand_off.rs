//! A link's TCP stream that gives the CPU to its reader after each write, when that reader is a
//! process on this machine (the built-in simulator, `armjog sim`, an operator run beside the
//! console).
//!
//! Why: a loopback write wakes its reader on the writer's core (the kernel's wake-up is a sync
//! one: it expects the writer to sleep soon), and the reader then runs only once the console's
//! thread sleeps: after everything else a key's burst does (`perf sched timehist` shows the
//! operator stand-in running right after the console's burst, on its core). Measured on the
//! 2-core VM with `benches/pty_latency.py --compare`, 300 cycles, without and with it:
//! release->STOP p50 0.331 -> 0.297 ms at rest (p99 0.660 -> 0.615), and under
//! `stress --cpu 2` p50 0.129 both, p90 0.292 -> 0.260, p99 4.06 -> 2.17 ms; press->START p50
//! 0.374 -> 0.356 ms at rest and 0.220 -> 0.215 under stress (p99 4.69 -> 3.53 ms).
//! A reader on another machine gains nothing from it, so the stream yields only for one on this
//! machine. The Modbus link does not use it: in a stop set the driver hands the Modbus worker its
//! STOP first, and its write must not wait for the operator's turn.

use std::io;
use std::net::SocketAddr;
use std::pin::Pin;
use std::task::{Context, Poll};

use tokio::io::{AsyncRead, AsyncWrite, ReadBuf};
use tokio::net::TcpStream;

/// A connected stream; writes yield the thread once they are with the kernel, when the peer is
/// on this machine (see the module's comment).
#[derive(Debug)]
pub struct HandOffStream {
    stream: TcpStream,
    peer_on_this_host: bool,
}

impl HandOffStream {
    /// Wraps a connected stream. A stream whose addresses cannot be read (one already reset)
    /// does not yield: its writes fail anyway.
    pub fn new(stream: TcpStream) -> HandOffStream {
        let peer_on_this_host = match (stream.local_addr(), stream.peer_addr()) {
            (Ok(local), Ok(peer)) => on_this_host(local, peer),
            _ => false,
        };
        HandOffStream {
            stream,
            peer_on_this_host,
        }
    }

    /// Whether the stream's writes give the CPU to the peer.
    pub fn peer_on_this_host(&self) -> bool {
        self.peer_on_this_host
    }

    /// After a write that reached the kernel: the reader on this machine runs now, not after
    /// the rest of this thread's burst. With nothing else runnable here it costs one syscall.
    fn hand_off(&self, written: &Poll<io::Result<usize>>) {
        if self.peer_on_this_host && matches!(written, Poll::Ready(Ok(n)) if *n > 0) {
            std::thread::yield_now();
        }
    }
}

/// Whether a connection from `local` to `peer` stays on this machine: a loopback address, or
/// this machine's own address on both ends.
pub fn on_this_host(local: SocketAddr, peer: SocketAddr) -> bool {
    let peer_ip = peer.ip().to_canonical();
    peer_ip.is_loopback() || peer_ip == local.ip().to_canonical()
}

impl AsyncRead for HandOffStream {
    fn poll_read(
        self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &mut ReadBuf<'_>,
    ) -> Poll<io::Result<()>> {
        Pin::new(&mut self.get_mut().stream).poll_read(cx, buf)
    }
}

impl AsyncWrite for HandOffStream {
    fn poll_write(
        self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &[u8],
    ) -> Poll<io::Result<usize>> {
        let this = self.get_mut();
        let written = Pin::new(&mut this.stream).poll_write(cx, buf);
        this.hand_off(&written);
        written
    }

    fn poll_write_vectored(
        self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        bufs: &[io::IoSlice<'_>],
    ) -> Poll<io::Result<usize>> {
        let this = self.get_mut();
        let written = Pin::new(&mut this.stream).poll_write_vectored(cx, bufs);
        this.hand_off(&written);
        written
    }

    fn is_write_vectored(&self) -> bool {
        self.stream.is_write_vectored()
    }

    fn poll_flush(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.get_mut().stream).poll_flush(cx)
    }

    fn poll_shutdown(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.get_mut().stream).poll_shutdown(cx)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tokio::io::{AsyncReadExt, AsyncWriteExt};

    fn addr(text: &str) -> SocketAddr {
        text.parse().expect("a socket address")
    }

    #[test]
    fn loopback_and_own_address_are_this_host_others_are_not() {
        let cases = [
            ("127.0.0.1:40000", "127.0.0.1:502", true),
            // Any 127/8 address is loopback.
            ("127.0.0.1:40000", "127.1.2.3:502", true),
            ("[::1]:40000", "[::1]:502", true),
            // An IPv6 socket talking to an IPv4 peer sees it mapped.
            ("[::ffff:127.0.0.1]:40000", "[::ffff:127.0.0.1]:502", true),
            // This machine's own LAN address on both ends.
            ("192.168.10.5:40000", "192.168.10.5:502", true),
            ("[::ffff:192.168.10.5]:40000", "192.168.10.5:502", true),
            // An arm on the network.
            ("192.168.10.5:40000", "192.168.10.20:502", false),
            ("[fe80::1]:40000", "[fe80::2]:502", false),
        ];
        for (local, peer, expected) in cases {
            assert_eq!(
                on_this_host(addr(local), addr(peer)),
                expected,
                "{local} -> {peer}"
            );
        }
    }

    #[tokio::test]
    async fn a_loopback_stream_hands_off_and_carries_bytes_both_ways() {
        let listener = tokio::net::TcpListener::bind("127.0.0.1:0")
            .await
            .expect("bind");
        let addr = listener.local_addr().expect("address");
        let (client, accepted) = tokio::join!(TcpStream::connect(addr), listener.accept());
        let mut client = HandOffStream::new(client.expect("connect"));
        let (mut server, _) = accepted.expect("accept");
        assert!(client.peer_on_this_host());

        client.write_all(b"STOP").await.expect("write");
        client.flush().await.expect("flush");
        let mut got = [0u8; 4];
        server.read_exact(&mut got).await.expect("server read");
        assert_eq!(&got, b"STOP");

        server.write_all(b"ACK\0").await.expect("server write");
        client.read_exact(&mut got).await.expect("read");
        assert_eq!(&got, b"ACK\0");

        client.shutdown().await.expect("shutdown");
        let mut rest = Vec::new();
        server
            .read_to_end(&mut rest)
            .await
            .expect("server reads the end");
        assert!(rest.is_empty());
    }
}
