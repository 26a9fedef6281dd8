//! Orientation jogs through the arm driver: over Modbus the exact twist registers (a zero
//! linear part, the angular part in deg/s, the jog frame), at the speed in force and never above
//! the arm's angular limit; over Talos a refusal that sends nothing.

use crate::{common, modbus_fake};

use std::sync::Arc;
use std::time::Duration;

use tokio::sync::mpsc::UnboundedReceiver;

use armjog::kortex::ReferenceFrame;
use armjog::link::driver::{Driver, DriverConfig, ORIENTATION_NEEDS_MODBUS};
use armjog::link::interface::{ArmCommand, ArmError, ArmEvent, CommandKind, JogMotion, LinkStatus};
use armjog::link::{Dialect, ModbusConfig, TalosConfig};
use armjog::talos::{Checksum, TalosFrame};
use common::{Action, TestOperator};
use modbus_fake::{FakeArm, Written, cdab, stop_write};

const WAIT: Duration = Duration::from_secs(5);

async fn wait_for<T>(
    events: &mut UnboundedReceiver<ArmEvent>,
    what: &str,
    pick: impl Fn(&ArmEvent) -> Option<T>,
) -> T {
    let wait = async {
        while let Some(e) = events.recv().await {
            if let Some(found) = pick(&e) {
                return found;
            }
        }
        panic!("driver ended before {what}");
    };
    tokio::time::timeout(WAIT, wait)
        .await
        .unwrap_or_else(|_| panic!("no {what} within {WAIT:?}"))
}

async fn done(events: &mut UnboundedReceiver<ArmEvent>, command: &ArmCommand) {
    wait_for(events, "the command done", |e| match e {
        ArmEvent::Done { command: c } if c == command => Some(()),
        ArmEvent::Failed {
            command: kind,
            error,
        } if *kind == command.kind() => {
            panic!("{kind} failed: {error}")
        }
        _ => None,
    })
    .await;
}

/// A Modbus-only driver on a fake arm whose configured angular limit is `arm_angular` deg/s,
/// with telemetry in (so the driver knows that limit).
async fn modbus_rig(arm_angular: f32) -> (FakeArm, Driver, UnboundedReceiver<ArmEvent>) {
    let arm = FakeArm::start().await;
    arm.with(|s| {
        s.set_holding_f32(104, 0.5);
        s.set_holding_f32(106, arm_angular);
    });
    let mut modbus = ModbusConfig::new(arm.addr());
    modbus.poll_rate_hz = Some(20.0);
    let (driver, mut events) = Driver::spawn(DriverConfig::new(None, Some(modbus)));
    wait_for(&mut events, "telemetry", |e| {
        matches!(e, ArmEvent::Telemetry(_)).then_some(())
    })
    .await;
    (arm, driver, events)
}

/// The twist start sequence with this frame code and angular words (theta x, y, z).
fn twist_writes(frame: u16, angular: [[u16; 2]; 3]) -> Vec<Written> {
    let mut block = vec![3, frame];
    block.extend([0u16; 6]); // no linear part: x, y, z 0 m/s
    for words in angular {
        block.extend(words);
    }
    vec![
        Written::Registers(200, vec![0]),
        Written::Registers(202, block),
        Written::Registers(200, vec![1]),
    ]
}

#[tokio::test]
async fn an_orientation_jog_writes_a_pure_angular_twist_in_the_jog_frame() {
    let (arm, driver, mut events) = modbus_rig(100.0).await;
    for command in [
        ArmCommand::SetSpeed(50),
        ArmCommand::SetFrame(ReferenceFrame::Tool),
    ] {
        assert!(driver.send(command.clone()));
        done(&mut events, &command).await;
    }
    let turn = ArmCommand::Jog(JogMotion::Orientation {
        rx: 0,
        ry: 0,
        rz: -1,
    });
    assert!(driver.send(turn.clone()));
    done(&mut events, &turn).await;
    assert!(driver.send(ArmCommand::Stop));
    done(&mut events, &ArmCommand::Stop).await;
    // 50 % of 30 deg/s about -Z of the tool frame (203 = 2): -15.0 is 0xC1700000.
    let mut expected = twist_writes(2, [[0, 0], [0, 0], [0x0000, 0xC170]]);
    expected.push(stop_write());
    assert_eq!(arm.writes(), expected);
    driver.shutdown().await;
}

#[tokio::test]
async fn a_diagonal_turn_keeps_the_rate_and_the_arms_angular_limit_caps_it() {
    // The arm is configured for 10 deg/s: 100 % (30 deg/s) is capped to it.
    let (arm, driver, mut events) = modbus_rig(10.0).await;
    let speed = ArmCommand::SetSpeed(100);
    assert!(driver.send(speed.clone()));
    done(&mut events, &speed).await;
    let turn = ArmCommand::Jog(JogMotion::Orientation {
        rx: 1,
        ry: 1,
        rz: 0,
    });
    assert!(driver.send(turn.clone()));
    done(&mut events, &turn).await;
    assert!(driver.send(ArmCommand::Stop));
    done(&mut events, &ArmCommand::Stop).await;
    // Base frame (203 = 3), 10 deg/s about the X-Y diagonal.
    let each = 10.0 / 2f32.sqrt();
    let mut expected = twist_writes(3, [cdab(each), cdab(each), [0, 0]]);
    expected.push(stop_write());
    assert_eq!(arm.writes(), expected);
    driver.shutdown().await;
}

#[tokio::test]
async fn over_talos_alone_an_orientation_jog_is_refused_and_nothing_is_sent() {
    let script: common::Script = Arc::new(|_: &TalosFrame| vec![Action::Write(b"ACK\0".to_vec())]);
    let mut op = TestOperator::start(Checksum::Xor8, script).await;
    let mut talos = TalosConfig::new(op.addr.clone());
    talos.dialect = Dialect::Ack;
    talos.checksum = Checksum::Xor8;
    let (driver, mut events) = Driver::spawn(DriverConfig::new(Some(talos), None));
    wait_for(&mut events, "the link up", |e| {
        matches!(e, ArmEvent::Status(LinkStatus::Up { .. })).then_some(())
    })
    .await;
    let handshake = op.next_frame().await;
    assert_eq!(handshake.command, 0x0000);
    let turn = ArmCommand::Jog(JogMotion::Orientation {
        rx: 1,
        ry: 0,
        rz: 0,
    });
    assert!(driver.send(turn));
    let error = wait_for(&mut events, "the refusal", |e| match e {
        ArmEvent::Failed {
            command: CommandKind::Jog,
            error,
        } => Some(error.clone()),
        _ => None,
    })
    .await;
    assert_eq!(error, ArmError::Unsupported(ORIENTATION_NEEDS_MODBUS));
    assert!(
        error.to_string().contains("Talos has no orientation jog"),
        "{error}"
    );
    // The next frame the operator sees is the polar pan sent after: nothing went out for the
    // turn.
    let pan = JogMotion::Polar {
        azimuth: 1,
        altitude: 0,
    };
    assert!(driver.send(ArmCommand::Jog(pan)));
    let next = op.next_frame().await;
    assert_eq!(next.command, 0x0003, "{next:?}");
    driver.shutdown().await;
}
