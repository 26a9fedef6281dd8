//! While one client is hostile (floods garbage, trickles a frame byte by byte, or holds 50 idle
//! connections), another client's requests to the simulator are still answered, over Talos and
//! over Modbus, on one connection and on fresh ones.

use crate::attack_support;

use std::net::SocketAddr;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Duration;

use tokio::io::AsyncWriteExt;
use tokio::net::TcpStream;
use tokio::task::JoinHandle;
use tokio::time::Instant;

use armjog::sim::{SimConfig, Simulator};
use armjog::talos::{Checksum, CommandValue, TalosFrame};

use attack_support::{
    ModbusOutcome, REPLY_BOUND, check_handshake_reply, distinctive_id, is_state_reply,
    modbus_read_state, modbus_reply_to, modbus_state_answered, talos_handshake,
    talos_handshake_answered, talos_reply_to,
};

const IDLE_CONNECTIONS: usize = 50;
const REQUESTS: u32 = 20;

/// Pseudo-random garbage (xorshift), reproducible and dependency-free.
fn garbage(seed: &mut u64, len: usize) -> Vec<u8> {
    (0..len)
        .map(|_| {
            *seed ^= *seed << 13;
            *seed ^= *seed >> 7;
            *seed ^= *seed << 17;
            (*seed >> 24) as u8
        })
        .collect()
}

/// The hostile clients, running until dropped or stopped.
struct Hostiles {
    stop: Arc<AtomicBool>,
    flooded: Arc<AtomicU64>,
    trickled: Arc<AtomicU64>,
    tasks: Vec<JoinHandle<()>>,
    _idle: Vec<TcpStream>,
}

impl Hostiles {
    /// Floods garbage, trickles `slow_frame` a byte per 100 ms (reconnecting whenever the server
    /// closes either), and holds idle connections, all against `addr`.
    async fn start(addr: SocketAddr, slow_frame: Vec<u8>) -> Hostiles {
        let mut idle = Vec::new();
        for _ in 0..IDLE_CONNECTIONS {
            idle.push(TcpStream::connect(addr).await.expect("an idle connection"));
        }
        let stop = Arc::new(AtomicBool::new(false));
        let flooded = Arc::new(AtomicU64::new(0));
        let trickled = Arc::new(AtomicU64::new(0));
        let flood = {
            let (stop, flooded) = (stop.clone(), flooded.clone());
            tokio::spawn(async move {
                let mut seed = 0x9E37_79B9_7F4A_7C15u64;
                while !stop.load(Ordering::Relaxed) {
                    let Ok(mut stream) = TcpStream::connect(addr).await else {
                        continue;
                    };
                    while !stop.load(Ordering::Relaxed) {
                        let chunk = garbage(&mut seed, 4096);
                        if stream.write_all(&chunk).await.is_err() {
                            break;
                        }
                        flooded.fetch_add(chunk.len() as u64, Ordering::Relaxed);
                        tokio::task::yield_now().await;
                    }
                }
            })
        };
        let slowloris = {
            let (stop, trickled) = (stop.clone(), trickled.clone());
            tokio::spawn(async move {
                while !stop.load(Ordering::Relaxed) {
                    let Ok(mut stream) = TcpStream::connect(addr).await else {
                        continue;
                    };
                    for byte in slow_frame.iter().cycle() {
                        if stop.load(Ordering::Relaxed) || stream.write_all(&[*byte]).await.is_err()
                        {
                            break;
                        }
                        trickled.fetch_add(1, Ordering::Relaxed);
                        tokio::time::sleep(Duration::from_millis(100)).await;
                    }
                }
            })
        };
        Hostiles {
            stop,
            flooded,
            trickled,
            tasks: vec![flood, slowloris],
            _idle: idle,
        }
    }

    /// Stops the attack; the bytes flooded and trickled.
    async fn stop(self) -> (u64, u64) {
        self.stop.store(true, Ordering::Relaxed);
        for task in self.tasks {
            let _ = tokio::time::timeout(Duration::from_secs(5), task).await;
        }
        (
            self.flooded.load(Ordering::Relaxed),
            self.trickled.load(Ordering::Relaxed),
        )
    }
}

async fn sim() -> Simulator {
    Simulator::start(SimConfig::ephemeral())
        .await
        .expect("simulator starts")
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_talos_server_answers_others_while_one_client_is_hostile() {
    let sim = sim().await;
    let checksum = Checksum::Crc16;
    // An Execute Hardware Operation announcing 1000 payload bytes: a plausible frame to wait for.
    let slow = TalosFrame::new(
        7,
        CommandValue::ExecuteHardwareOperation.request_value(),
        vec![0; 1000],
    )
    .to_bytes(checksum)
    .expect("fits");
    let hostiles = Hostiles::start(sim.talos_addr, slow).await;

    let mut stream = TcpStream::connect(sim.talos_addr).await.expect("connect");
    let mut slowest = Duration::ZERO;
    for n in 0..REQUESTS {
        let id = distinctive_id(n);
        let sent = Instant::now();
        stream
            .write_all(&talos_handshake(id, checksum))
            .await
            .expect("send a handshake");
        let reply = talos_reply_to(&mut stream, checksum, id, REPLY_BOUND)
            .await
            .unwrap_or_else(|e| panic!("request {n} during the attack: {e}"));
        check_handshake_reply(&reply).unwrap_or_else(|e| panic!("request {n}: {e}"));
        slowest = slowest.max(sent.elapsed());
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    for n in 0..5 {
        talos_handshake_answered(sim.talos_addr, checksum, distinctive_id(100 + n))
            .await
            .unwrap_or_else(|e| panic!("fresh connection {n} during the attack: {e}"));
    }
    let (flooded, trickled) = hostiles.stop().await;
    eprintln!("talos: slowest reply {slowest:?}; {flooded} bytes flooded, {trickled} trickled");
    assert!(flooded > 64 * 1024, "the flood ran: {flooded} bytes");
    assert!(trickled > 5, "the trickle ran: {trickled} bytes");
    assert!(sim.arm.snapshot().await.is_ok(), "the arm task lives");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_modbus_server_answers_others_while_one_client_is_hostile() {
    let sim = sim().await;
    let addr = sim.modbus_addr.expect("the Modbus server runs");
    // A write of 123 registers at 0 announcing its 254-byte MBAP length, sent a byte at a time.
    let mut slow = vec![0, 9, 0, 0, 0, 254, 1, 0x10, 0, 0, 0, 123, 246];
    slow.extend([0u8; 246]);
    let hostiles = Hostiles::start(addr, slow).await;

    let mut stream = TcpStream::connect(addr).await.expect("connect");
    let mut slowest = Duration::ZERO;
    for n in 0..REQUESTS {
        let transaction = 0xF000 + n as u16;
        let sent = Instant::now();
        stream
            .write_all(&modbus_read_state(transaction))
            .await
            .expect("send a read");
        match modbus_reply_to(&mut stream, transaction, REPLY_BOUND).await {
            ModbusOutcome::Reply(pdu) if is_state_reply(&pdu) => {}
            other => panic!("request {n} during the attack: {other:?}"),
        }
        slowest = slowest.max(sent.elapsed());
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    for n in 0..5 {
        modbus_state_answered(addr, 0xE000 + n)
            .await
            .unwrap_or_else(|e| panic!("fresh connection {n} during the attack: {e}"));
    }
    let (flooded, trickled) = hostiles.stop().await;
    eprintln!("modbus: slowest reply {slowest:?}; {flooded} bytes flooded, {trickled} trickled");
    assert!(flooded > 64 * 1024, "the flood ran: {flooded} bytes");
    assert!(trickled > 5, "the trickle ran: {trickled} bytes");
    assert!(sim.arm.snapshot().await.is_ok(), "the arm task lives");
}
