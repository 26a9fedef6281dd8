//! The Modbus link's connection: a timeout typed and reconnected, a twist stopped and a
//! read-only link silent after a reconnect, jobs failing at once while the arm is gone and the
//! stop waiting for its return, a refused connection typed.

use crate::modbus_fake;

use std::time::Duration;

use armjog::kortex::{ReferenceFrame, Twist};
use armjog::link::modbus::{ModbusConfig, ModbusError, ModbusEvent, ModbusLink, StopReason};
use modbus_fake::{Behaviour, FakeArm, stop_write};
use tokio_modbus::Request;

use super::modbus::{WAIT, WithX, config, sample_twist};

#[tokio::test]
async fn a_timeout_is_typed_and_the_link_reconnects() {
    let arm = FakeArm::start().await;
    arm.rule(|r| match r {
        Request::ReadHoldingRegisters(..) => Some(Behaviour::Stall(Duration::from_secs(2))),
        _ => None,
    });
    let (link, mut events) = ModbusLink::connect(config(&arm)).await.unwrap();
    let started = std::time::Instant::now();
    let e = link.read_telemetry().await.unwrap_err();
    assert!(matches!(e, ModbusError::Timeout { .. }), "{e}");
    assert!(e.to_string().contains("holding registers 0-107"), "{e}");
    assert!(started.elapsed() < Duration::from_millis(1000));
    assert!(matches!(
        events.recv().await,
        Some(ModbusEvent::Disconnected { .. })
    ));
    assert!(matches!(
        events.recv().await,
        Some(ModbusEvent::Reconnected { .. })
    ));
    arm.clear_rules();
    link.read_telemetry().await.unwrap();
    assert_eq!(arm.with(|s| s.connections), 2);
}

#[tokio::test]
async fn a_twist_is_stopped_after_a_reconnect() {
    let arm = FakeArm::start().await;
    let (link, mut events) = ModbusLink::connect(config(&arm)).await.unwrap();
    link.jog_twist(ReferenceFrame::Base, sample_twist())
        .await
        .unwrap();
    arm.hang_up_all();
    // The next request finds the connection gone.
    let e = link.read_telemetry().await.unwrap_err();
    assert!(e.breaks_connection(), "{e}");
    arm.wait_for(WAIT, |s| s.writes().last() == Some(&stop_write()))
        .await;
    let stop = arm.with(|s| {
        s.log
            .iter()
            .rfind(|l| matches!(l.request, Request::WriteMultipleRegisters(200, _)))
            .map(|l| l.connection)
    });
    assert_eq!(stop, Some(2), "the stop went out on the new connection");
    let mut saw_stop = false;
    while let Ok(Some(event)) =
        tokio::time::timeout(Duration::from_millis(200), events.recv()).await
    {
        saw_stop |= event
            == ModbusEvent::Stopped {
                reason: StopReason::Reconnected,
            };
    }
    assert!(saw_stop);
}

#[tokio::test]
async fn a_read_only_link_writes_nothing_after_a_reconnect() {
    let arm = FakeArm::start().await;
    let (link, mut events) = ModbusLink::connect(config(&arm)).await.unwrap();
    link.read_telemetry().await.unwrap();
    arm.hang_up_all();
    let _ = link.read_telemetry().await;
    loop {
        if let Some(ModbusEvent::Reconnected { .. }) = events.recv().await {
            break;
        }
    }
    link.read_telemetry().await.unwrap();
    assert!(arm.writes().is_empty());
}

#[tokio::test]
async fn while_the_arm_is_gone_jobs_fail_at_once_and_the_stop_waits_for_its_return() {
    let arm = FakeArm::start().await;
    let addr = arm.addr;
    let (link, _events) = ModbusLink::connect(config(&arm)).await.unwrap();
    link.jog_twist(ReferenceFrame::Base, sample_twist())
        .await
        .unwrap();
    drop(arm);
    assert!(link.read_telemetry().await.is_err());
    // Reconnects are refused now: a jog fails at once rather than waiting or queueing.
    let started = std::time::Instant::now();
    let e = link
        .jog_twist(ReferenceFrame::Base, Twist::ZERO.with_x(0.1))
        .await
        .unwrap_err();
    assert!(matches!(e, ModbusError::Disconnected { .. }), "{e}");
    assert!(started.elapsed() < Duration::from_millis(100));
    // The arm comes back: the owed stop is written, the refused jog is not.
    let back = FakeArm::start_at(addr).await;
    back.wait_for(WAIT, |s| s.writes() == [stop_write()]).await;
    tokio::time::sleep(Duration::from_millis(100)).await;
    assert_eq!(back.writes(), [stop_write()]);
}

#[tokio::test]
async fn connection_refused_is_typed() {
    let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = listener.local_addr().unwrap().to_string();
    drop(listener);
    let e = ModbusLink::connect(ModbusConfig::new(addr))
        .await
        .unwrap_err();
    assert!(
        matches!(
            e,
            ModbusError::Connect(armjog::net::ConnectError::Refused { .. })
        ),
        "{e}"
    );
}
