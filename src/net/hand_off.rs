//! Whether a link's peer is a process on this machine (the built-in simulator, `armjog sim`, an
//! operator run beside the console), and how the Talos link gives it the CPU once a START or
//! STOP is written (`link/talos/task.rs`).
//!
//! Why: a loopback write wakes its reader on the writer's core (the kernel's wake-up is a sync
//! one: it expects the writer to sleep soon), and the reader then runs only once the console's
//! thread sleeps: after everything else a key's burst does (`perf sched timehist` shows the
//! operator stand-in running right after the console's burst, on its core).
//!
//! How ([`give_way`]): the thread yields, and when the yield came straight back (nobody else ran:
//! on a busy core the kernel's scheduler, EEVDF, lets a thread it just woke run on until it
//! sleeps or its slice ends, and picks it again at the yield), it sleeps for the shortest time
//! it can. That sleep lasts the thread's timer slack (50 us by default; 68 us measured on the
//! 2-core VM), and the console does nothing meanwhile: so only a START or STOP earns it, not the
//! telemetry polls. At rest the yield hands over (the operator, woken on this core, runs), and
//! a sleep then cost the tail: with the sleep alone press->START p99 was 0.57-0.63 ms against
//! 0.47-0.57 for the yield alone.
//! Measured with `benches/pty_latency.py --compare`, 300 cycles, the yield alone against this
//! (and the Python floor), same run: under `stress --cpu 2` release->STOP p50 0.098 / 0.104 ms
//! (0.046), p99 1.84 / **0.245** ms (0.228); press->START p50 0.183 / **0.144** ms (0.124), p99
//! 4.06 / **0.243** ms (4.88). At rest release->STOP p50 0.254 / 0.255 ms (0.310), p99 0.479 /
//! 0.521 (0.561); press->START p50 0.313 / 0.316 (0.304), p99 0.506 / 0.523 (0.525).
//!
//! A reader on another machine gains nothing from it, so the link gives way only to one on this
//! machine, and only once the frames queued are all written: a stop set is several frames (the
//! ICD dialect's three), and its polar STOP must not wait for the operator's turn on the first.
//! The Modbus link does not give way, and a Talos link does not either when the console also has
//! a Modbus link (`TalosConfig::give_way`, set by the driver): in a stop set the Modbus STOP is
//! written by a task that may come after the Talos link's, and must not wait for the operator's
//! turn.

use std::net::SocketAddr;
use std::time::{Duration, Instant};

use tokio::net::TcpStream;

/// What the thread asks to sleep when it gives way: the least there is. It sleeps its timer slack.
const GIVE_WAY: Duration = Duration::from_nanos(1);

/// A yield shorter than this gave nobody the CPU: on the VM one that switches to nobody comes
/// back in 0.2-0.4 us (p50, at rest and under load), and one that let another process run lasts
/// that process's turn (the harness's: 15 us and more, `perf sched timehist`).
const YIELD_HANDED_OVER: Duration = Duration::from_micros(8);

/// Gives the CPU to the local process a write just woke: this thread yields, and sleeps for a
/// moment if nobody ran (see the module's notes). It blocks the runtime's thread: call it only
/// after a START or STOP, and only where no other link's STOP waits on this thread.
pub fn give_way() {
    let yielded = Instant::now();
    std::thread::yield_now();
    if yielded.elapsed() < YIELD_HANDED_OVER {
        std::thread::sleep(GIVE_WAY);
    }
}

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
