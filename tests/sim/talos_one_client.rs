//! `one_client` (`armjog sim --one-client`): the simulated operator serves one client at a time,
//! as the deployed operator does. A second connection is accepted by the kernel but gets no
//! answer while the first is open; once the first closes, the second is served, frames it sent
//! meanwhile included. Without the option both are served at once (`talos::several_clients_…`).

use std::time::Duration;

use armjog::link::{Dialect, TalosConfig, TalosLink};
use armjog::sim::{SimConfig, Simulator};
use armjog::talos::{Checksum, Request};

fn ack_xor8(sim: &Simulator) -> TalosConfig {
    let mut config = TalosConfig::new(sim.talos_addr.to_string());
    config.dialect = Dialect::Ack;
    config.checksum = Checksum::Xor8;
    config.request_timeout = Duration::from_millis(300);
    config
}

async fn one_client_sim() -> Simulator {
    let mut config = SimConfig::ephemeral();
    config.modbus_listen = None;
    config.talos.dialect = Dialect::Ack;
    config.talos.checksum = Checksum::Xor8;
    config.talos.one_client = true;
    Simulator::start(config).await.expect("simulator starts")
}

#[tokio::test]
async fn a_second_client_waits_unanswered_until_the_first_has_gone() {
    let sim = one_client_sim().await;
    let (first, _first_events) = TalosLink::connect(ack_xor8(&sim)).await.expect("first");
    first
        .request(Request::Handshake { oid: None })
        .await
        .expect("the first client is served");

    // The kernel takes the second connection: connect succeeds, nothing answers it.
    let (second, _second_events) = TalosLink::connect(ack_xor8(&sim))
        .await
        .expect("the second connection is accepted by the kernel");
    let unanswered = second
        .submit(Request::Handshake { oid: None })
        .expect("queued");
    assert!(
        tokio::time::timeout(Duration::from_millis(600), unanswered.wait())
            .await
            .map_or(true, |answer| answer.is_err()),
        "no answer while the first client is connected"
    );
    first
        .request(Request::PolarPanStop)
        .await
        .expect("the first client is still served");

    // The first client goes: the second is served, what it sent meanwhile too.
    drop(first);
    let started = tokio::time::Instant::now();
    let answered = loop {
        let pending = second.submit(Request::PolarPanStop).expect("queued");
        if pending.wait().await.is_ok() {
            break true;
        }
        if started.elapsed() > Duration::from_secs(5) {
            break false;
        }
    };
    assert!(
        answered,
        "the second client is served once the first has gone"
    );
}
