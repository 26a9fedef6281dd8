//! A client that opens connections until `armjog sim` runs out of file descriptors makes its
//! accepts fail ("too many open files"). Once those connections are gone, both servers must
//! serve again: an accept error must not end a server.

use crate::attack_support;

use std::time::Duration;

use tokio::net::TcpStream;

use armjog::talos::Checksum;

use attack_support::process::SimProcess;
use attack_support::{distinctive_id, modbus_state_answered, talos_handshake_answered};

/// The sim's open-file limit: a few dozen connections exhaust it.
const FD_LIMIT: u32 = 48;

/// Retries `check` for up to 10 s: a server that backs off after an accept error takes a moment
/// to accept again.
async fn eventually<F, Fut>(what: &str, check: F)
where
    F: Fn() -> Fut,
    Fut: std::future::Future<Output = Result<(), String>>,
{
    let mut last = String::new();
    for _ in 0..20 {
        match tokio::time::timeout(Duration::from_secs(2), check()).await {
            Ok(Ok(())) => return,
            Ok(Err(e)) => last = e,
            Err(_) => last = "no answer within 2 s".into(),
        }
        tokio::time::sleep(Duration::from_millis(500)).await;
    }
    panic!("{what}: not served again within 10 s: {last}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn both_servers_serve_again_after_connections_exhaust_the_descriptor_limit() {
    let mut sim = SimProcess::spawn(Some(FD_LIMIT));
    let (talos, modbus) = (sim.talos, sim.modbus);
    talos_handshake_answered(talos, Checksum::Crc16, distinctive_id(0))
        .await
        .expect("talos serves before the attack");
    modbus_state_answered(modbus, 1)
        .await
        .expect("modbus serves before the attack");

    for (name, addr) in [("modbus", modbus), ("talos", talos)] {
        // More connections than the sim has descriptors: the kernel completes them all (the
        // listen backlog), the sim accepts until its limit, then its accepts fail.
        // (A server that stopped on the first failed accept closes its port: later connects
        // are refused, which the checks below then catch.)
        let mut held = Vec::new();
        for _ in 0..FD_LIMIT + 16 {
            if let Ok(stream) = TcpStream::connect(addr).await {
                held.push(stream);
            }
        }
        // Hold them a little while the sim keeps failing to accept.
        tokio::time::sleep(Duration::from_millis(300)).await;
        drop(held);
        assert!(sim.alive(), "{name}: the sim process died");
        eventually(&format!("after holding {name} connections, talos"), || {
            talos_handshake_answered(talos, Checksum::Crc16, distinctive_id(1))
        })
        .await;
        eventually(&format!("after holding {name} connections, modbus"), || {
            modbus_state_answered(modbus, 2)
        })
        .await;
        // Checked last, so that a server that died shows as not serving, above.
        let failure = match name {
            "modbus" => "sim modbus: accepting failed",
            _ => "sim talos: accept failed",
        };
        assert!(
            sim.logged(failure).await,
            "{name}: no failed accept logged: the attack did not exhaust the descriptors"
        );
    }
}
