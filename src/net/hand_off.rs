//! Whether a link's peer is a process on this machine (the built-in simulator, `armjog sim`, an
//! operator run beside the console): the Talos link then gives it the CPU once its frames are
//! written (`link/talos/task.rs`).
//!
//! Why: a loopback write wakes its reader on the writer's core (the kernel's wake-up is a sync
//! one: it expects the writer to sleep soon), and the reader then runs only once the console's
//! thread sleeps: after everything else a key's burst does (`perf sched timehist` shows the
//! operator stand-in running right after the console's burst, on its core). Measured on the
//! 2-core VM with `benches/pty_latency.py --compare`, 300 cycles, without and with a yield after
//! the write: release->STOP p50 0.331 -> 0.297 ms at rest (p99 0.660 -> 0.615), and under
//! `stress --cpu 2` p50 0.129 both, p90 0.292 -> 0.260, p99 4.06 -> 2.17 ms; press->START p50
//! 0.374 -> 0.356 ms at rest and 0.220 -> 0.215 under stress (p99 4.69 -> 3.53 ms).
//! A reader on another machine gains nothing from it, so the link yields only for one on this
//! machine, and only once the frames queued are all written: a stop set is several frames (the
//! ICD dialect's three), and its polar STOP must not wait for the operator's turn on the first.
//! The Modbus link does not yield: in a stop set the driver hands the Modbus worker its STOP
//! first, and its write must not wait for the operator's turn either.

use std::net::SocketAddr;

use tokio::net::TcpStream;

/// Whether `stream`'s peer is on this machine. A stream whose addresses cannot be read (one
/// already reset) is taken as remote: its writes fail anyway.
pub fn peer_on_this_host(stream: &TcpStream) -> bool {
    match (stream.local_addr(), stream.peer_addr()) {
        (Ok(local), Ok(peer)) => on_this_host(local, peer),
        _ => false,
    }
}

/// Whether a connection from `local` to `peer` stays on this machine: a loopback address, or
/// this machine's own address on both ends.
pub fn on_this_host(local: SocketAddr, peer: SocketAddr) -> bool {
    let peer_ip = peer.ip().to_canonical();
    peer_ip.is_loopback() || peer_ip == local.ip().to_canonical()
}

#[cfg(test)]
mod tests {
    use super::*;

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
    async fn both_ends_of_a_loopback_connection_are_on_this_host() {
        let listener = tokio::net::TcpListener::bind("127.0.0.1:0")
            .await
            .expect("bind");
        let addr = listener.local_addr().expect("address");
        let (client, accepted) = tokio::join!(TcpStream::connect(addr), listener.accept());
        let client = client.expect("connect");
        let (server, _) = accepted.expect("accept");
        assert!(peer_on_this_host(&client));
        assert!(peer_on_this_host(&server));
    }
}
