//! Memory and file descriptors stay flat over 2,000 connect/disconnect cycles against `armjog
//! sim` in its own process: a quarter send a valid request and wait for the reply, a quarter
//! send garbage, a quarter drop mid-frame, a quarter connect and leave. The process's VmRSS is
//! read from /proc after a warm-up and after the cycles; its open descriptors must come back to
//! their count after the warm-up (no leaked sockets or tasks holding them).

use crate::attack_support;

use std::time::Duration;

use tokio::io::AsyncWriteExt;
use tokio::net::TcpStream;

use armjog::talos::Checksum;

use attack_support::process::SimProcess;
use attack_support::{
    distinctive_id, modbus_read_state, modbus_state_answered, talos_handshake,
    talos_handshake_answered,
};

const WARM_UP: u32 = 200;
const CYCLES: u32 = 2_000;
/// Generous: allocator arenas and tokio's worker caches may settle a little after the warm-up.
const MAX_GROWTH_KB: u64 = 4 * 1024;

#[derive(Clone, Copy)]
enum Protocol {
    Talos,
    Modbus,
}

/// One connect/disconnect cycle of kind `n % 4`.
async fn cycle(sim: &SimProcess, protocol: Protocol, n: u32) {
    let (addr, valid) = match protocol {
        Protocol::Talos => (
            sim.talos,
            talos_handshake(distinctive_id(n), Checksum::Crc16),
        ),
        Protocol::Modbus => (sim.modbus, modbus_read_state(n as u16)),
    };
    match n % 4 {
        0 => match protocol {
            Protocol::Talos => talos_handshake_answered(addr, Checksum::Crc16, distinctive_id(n))
                .await
                .unwrap_or_else(|e| panic!("cycle {n}: {e}")),
            Protocol::Modbus => modbus_state_answered(addr, n as u16)
                .await
                .unwrap_or_else(|e| panic!("cycle {n}: {e}")),
        },
        kind => {
            let mut stream = TcpStream::connect(addr)
                .await
                .unwrap_or_else(|e| panic!("cycle {n}: connect to {addr}: {e}"));
            // The server may already have closed on the garbage: a failed write is fine.
            let _ = match kind {
                1 => {
                    let garbage: Vec<u8> = (0..256u32).map(|i| (i * 37 + n) as u8).collect();
                    stream.write_all(&garbage).await
                }
                2 => stream.write_all(&valid[..valid.len() / 2]).await,
                _ => Ok(()),
            };
        }
    }
}

async fn flat_over_cycles(protocol: Protocol, name: &str) {
    let mut sim = SimProcess::spawn(None);
    for n in 0..WARM_UP {
        cycle(&sim, protocol, n).await;
    }
    // Let the server finish the warm-up's closes before taking the baseline.
    tokio::time::sleep(Duration::from_millis(300)).await;
    let fds_before = sim.open_fds();
    let rss_before = sim.rss_kb();
    for n in WARM_UP..WARM_UP + CYCLES {
        cycle(&sim, protocol, n).await;
    }
    let fds_after = sim.settle_fds(fds_before).await;
    let rss_after = sim.rss_kb();
    eprintln!(
        "{name}: VmRSS {rss_before} kB after {WARM_UP} warm-up cycles, {rss_after} kB after {CYCLES} more; fds {fds_before} -> {fds_after}"
    );
    assert!(sim.alive(), "{name}: the sim process died");
    assert!(
        fds_after <= fds_before,
        "{name}: {fds_before} descriptors open after the warm-up, {fds_after} after the cycles"
    );
    assert!(
        rss_after <= rss_before + MAX_GROWTH_KB,
        "{name}: VmRSS grew from {rss_before} kB to {rss_after} kB over {CYCLES} cycles"
    );
}

#[tokio::test]
async fn talos_memory_and_descriptors_stay_flat_over_2000_connections() {
    flat_over_cycles(Protocol::Talos, "talos").await;
}

#[tokio::test]
async fn modbus_memory_and_descriptors_stay_flat_over_2000_connections() {
    flat_over_cycles(Protocol::Modbus, "modbus").await;
}
