//! The stops that keep a Modbus twist from running on: the last handle dropped, close, a
//! failed update; a refused stop escalates to the abort coil, a stop that cannot be written is
//! an error and an event.

use crate::modbus_fake;

use std::time::Duration;

use armjog::kortex::{ReferenceFrame, Twist};
use armjog::link::modbus::{ModbusError, ModbusEvent, ModbusLink, StopReason};
use modbus_fake::{Behaviour, FakeArm, Written, stop_write};
use tokio_modbus::{ExceptionCode, Request};

use super::modbus::{WAIT, WithX, config, sample_twist};

#[tokio::test]
async fn dropping_the_last_handle_stops_the_twist() {
    let arm = FakeArm::start().await;
    let (link, _events) = ModbusLink::connect(config(&arm)).await.unwrap();
    let clone = link.clone();
    link.jog_twist(ReferenceFrame::Base, sample_twist())
        .await
        .unwrap();
    drop(link);
    tokio::time::sleep(Duration::from_millis(50)).await;
    assert_eq!(arm.writes().len(), 3, "a clone still holds the link");
    drop(clone);
    arm.wait_for(WAIT, |s| s.writes().len() == 4).await;
    assert_eq!(arm.writes()[3], stop_write());
}

#[tokio::test]
async fn dropping_an_idle_link_writes_nothing() {
    let arm = FakeArm::start().await;
    let (link, _events) = ModbusLink::connect(config(&arm)).await.unwrap();
    link.start_stored(link.config().home_action(), None)
        .await
        .unwrap();
    drop(link);
    tokio::time::sleep(Duration::from_millis(100)).await;
    // Home runs to its end: only its own three writes.
    assert_eq!(arm.writes().len(), 3);
}

#[tokio::test]
async fn close_reports_the_stop() {
    let arm = FakeArm::start().await;
    let (link, _events) = ModbusLink::connect(config(&arm)).await.unwrap();
    link.jog_twist(ReferenceFrame::Base, sample_twist())
        .await
        .unwrap();
    link.close().await.unwrap();
    assert_eq!(arm.writes().last(), Some(&stop_write()));
}

#[tokio::test]
async fn a_failed_update_stops_the_twist() {
    let arm = FakeArm::start().await;
    let (link, mut events) = ModbusLink::connect(config(&arm)).await.unwrap();
    link.jog_twist(ReferenceFrame::Base, sample_twist())
        .await
        .unwrap();
    arm.rule(|r| match r {
        Request::WriteMultipleRegisters(202, _) => {
            Some(Behaviour::Exception(ExceptionCode::IllegalDataValue))
        }
        _ => None,
    });
    let e = link
        .jog_twist(ReferenceFrame::Base, Twist::ZERO.with_x(0.1))
        .await
        .unwrap_err();
    assert_eq!(e.exception(), Some(ExceptionCode::IllegalDataValue));
    // The refused block (x 0.1 = 0x3DCCCCCD), then the stop.
    let writes = arm.writes();
    assert_eq!(
        writes[3..],
        [
            Written::Registers(200, vec![0]),
            Written::Registers(
                202,
                vec![3, 3, 0xCCCD, 0x3DCC, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]
            ),
            stop_write()
        ]
    );
    let mut reasons = Vec::new();
    while let Ok(Some(event)) =
        tokio::time::timeout(Duration::from_millis(100), events.recv()).await
    {
        reasons.push(event);
    }
    assert!(reasons.contains(&ModbusEvent::Stopped {
        reason: StopReason::WriteFailed
    }));
}

#[tokio::test]
async fn a_refused_stop_escalates_to_the_abort_coil() {
    let arm = FakeArm::start().await;
    arm.rule(|r| match r {
        Request::WriteMultipleRegisters(200, v) if v[..] == [2] => {
            Some(Behaviour::Exception(ExceptionCode::ServerDeviceFailure))
        }
        _ => None,
    });
    let (link, mut events) = ModbusLink::connect(config(&arm)).await.unwrap();
    link.jog_twist(ReferenceFrame::Base, sample_twist())
        .await
        .unwrap();
    let report = link.stop().await.unwrap();
    assert_eq!(
        report.writes.len(),
        3,
        "the refused stop, then the abort pulse"
    );
    assert_eq!(
        arm.writes()[3..],
        [
            stop_write(),
            Written::Coil(1, true),
            Written::Coil(1, false)
        ]
    );
    assert!(matches!(
        events.recv().await,
        Some(ModbusEvent::StopEscalated { .. })
    ));
}

#[tokio::test]
async fn a_stop_that_cannot_be_written_is_an_error_and_an_event() {
    let arm = FakeArm::start().await;
    arm.rule(|r| match r {
        Request::WriteMultipleRegisters(200, v) if v[..] == [2] => {
            Some(Behaviour::Exception(ExceptionCode::ServerDeviceFailure))
        }
        Request::WriteSingleCoil(1, _) => {
            Some(Behaviour::Exception(ExceptionCode::ServerDeviceFailure))
        }
        _ => None,
    });
    let (link, mut events) = ModbusLink::connect(config(&arm)).await.unwrap();
    link.jog_twist(ReferenceFrame::Base, sample_twist())
        .await
        .unwrap();
    let e = link.stop().await.unwrap_err();
    assert!(matches!(e, ModbusError::StopFailed { .. }), "{e}");
    assert!(e.to_string().contains("may still move"), "{e}");
    assert!(matches!(
        events.recv().await,
        Some(ModbusEvent::StopFailed {
            reason: StopReason::Requested,
            ..
        })
    ));
    // Still owed: closing tries again, and says it failed.
    assert!(link.close().await.is_err());
}
