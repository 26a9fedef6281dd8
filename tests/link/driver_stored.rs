//! A stored action or sequence by id through the arm driver over a Talos link alone: refused
//! with the reason, and nothing goes out for it (Talos starts only its Home, by no id).

use crate::common;

use std::sync::Arc;
use std::time::Duration;

use armjog::kortex::{Stored, StoredMotion};
use armjog::link::driver::{Driver, DriverConfig, STORED_NEEDS_MODBUS};
use armjog::link::interface::{ArmCommand, ArmError, ArmEvent, CommandKind, LinkStatus};
use armjog::link::{Dialect, TalosConfig};
use armjog::talos::{Checksum, TalosFrame};
use common::{Action, TestOperator};

const WAIT: Duration = Duration::from_secs(5);

#[tokio::test]
async fn over_talos_alone_a_stored_run_is_refused_and_nothing_is_sent() {
    let script: common::Script = Arc::new(|_: &TalosFrame| vec![Action::Write(b"ACK\0".to_vec())]);
    let mut op = TestOperator::start(Checksum::Xor8, script).await;
    let mut talos = TalosConfig::new(op.addr.clone());
    talos.dialect = Dialect::Ack;
    talos.checksum = Checksum::Xor8;
    let (driver, mut events) = Driver::spawn(DriverConfig::new(Some(talos), None));
    let refusal = async {
        let run = ArmCommand::StartStored(Stored {
            motion: StoredMotion::Action,
            id: 5,
        });
        let mut sent = false;
        while let Some(event) = events.recv().await {
            match event {
                ArmEvent::Status(LinkStatus::Up { .. }) if !sent => {
                    assert!(driver.send(run.clone()));
                    sent = true;
                }
                ArmEvent::Failed {
                    command: CommandKind::StartStored,
                    error,
                } => return error,
                _ => {}
            }
        }
        panic!("driver ended before the refusal");
    };
    let error = tokio::time::timeout(WAIT, refusal)
        .await
        .expect("refused within 5 s");
    assert_eq!(error, ArmError::Unsupported(STORED_NEEDS_MODBUS));
    assert!(error.to_string().contains("Modbus"), "{error}");
    // The handshake, then home (which Talos has): nothing went out for the stored run.
    assert_eq!(op.next_frame().await.command, 0x0000, "the handshake");
    assert!(driver.send(ArmCommand::Home));
    let next = op.next_frame().await;
    // Home is command 0x0002 in the Talos ICD.
    assert_eq!(next.command, 0x0002, "the next frame is home's");
    driver.shutdown().await;
}
