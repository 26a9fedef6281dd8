//! The Modbus link's polls against the fake arm: everything in four requests, the unit id, an
//! arm that refuses unlisted addresses read block by block, its slow blocks once a second and
//! its speed limits read afresh around a capped move.

use crate::common::home_tcp;
use crate::modbus_fake;

use std::time::Duration;

use armjog::kortex::{ReferenceFrame, RobotState, SLOW_REFRESH};
use armjog::link::modbus::{ModbusEvent, ModbusLink};
use modbus_fake::{FakeArm, Written, fill_known_telemetry};

use super::modbus::config;

/// A fake arm with known telemetry that refuses reads over addresses the ICD does not list.
async fn strict_arm() -> FakeArm {
    let arm = FakeArm::start().await;
    arm.with(|s| {
        fill_known_telemetry(s);
        s.strict_addresses = true;
    });
    arm
}

#[tokio::test]
async fn a_poll_reads_everything_in_four_requests_and_decodes_it() {
    let arm = FakeArm::start().await;
    arm.with(fill_known_telemetry);
    let (link, _events) = ModbusLink::connect(config(&arm)).await.unwrap();
    let subscriber = link.subscribe();
    let telemetry = link.read_telemetry().await.unwrap();
    assert_eq!(
        arm.with(|s| s.reads()),
        vec![(2, 0, 95), (4, 0, 14), (4, 34, 106), (3, 0, 108)]
    );
    assert_eq!(telemetry.robot_state.known(), Some(RobotState::Ready));
    assert_eq!(
        telemetry.faults.names(),
        vec!["firmware_update_failure", "joint_fault", "emergency_stop"]
    );
    assert_eq!(telemetry.tcp.pose.x, 0.4566);
    assert_eq!(telemetry.joints[6].temperature, 56.0);
    assert_eq!(telemetry.speed_limits.angular, 100.0);
    let published = subscriber.borrow().clone().unwrap();
    assert_eq!(published.sequence, 1);
    assert_eq!(published.telemetry, telemetry);
    assert!(arm.writes().is_empty(), "reading never writes");
}

#[tokio::test]
async fn the_unit_id_is_sent_with_every_request() {
    let arm = FakeArm::start().await;
    let mut config = config(&arm);
    config.unit = 7;
    let (link, _events) = ModbusLink::connect(config).await.unwrap();
    link.read_telemetry().await.unwrap();
    link.pulse(armjog::kortex::ControlCoil::FaultReset)
        .await
        .unwrap();
    let units: Vec<u8> = arm.with(|s| s.log.iter().map(|l| l.unit).collect());
    assert_eq!(units.len(), 6);
    assert!(units.iter().all(|u| *u == 7), "{units:?}");
}

#[tokio::test]
async fn an_arm_refusing_unlisted_addresses_is_read_block_by_block() {
    let arm = strict_arm().await;
    let (link, mut events) = ModbusLink::connect(config(&arm)).await.unwrap();
    let telemetry = link.read_telemetry().await.unwrap();
    assert_eq!(telemetry.speed_limits.linear, 0.5);
    assert_eq!(telemetry.tcp.wrench.torque_z, 12.0);
    let reads = arm.with(|s| s.reads());
    // The compact plan's first read spans unlisted flag inputs; the nine ICD blocks follow.
    assert_eq!(reads[0], (2, 0, 95));
    assert_eq!(
        reads[1..],
        [
            (2, 0, 10),
            (2, 32, 31),
            (2, 64, 31),
            (4, 0, 1),
            (4, 2, 12),
            (4, 34, 106),
            (3, 0, 1),
            (3, 100, 3),
            (3, 104, 4)
        ]
    );
    assert!(matches!(
        events.recv().await,
        Some(ModbusEvent::PlanFallback { .. })
    ));
}

#[tokio::test]
async fn a_strict_arms_state_warning_control_and_limit_blocks_are_read_once_a_second() {
    let arm = strict_arm().await;
    let (link, _events) = ModbusLink::connect(config(&arm)).await.unwrap();
    link.read_telemetry().await.unwrap();
    let first = arm.with(|s| s.reads()).len();
    // The next snapshots skip the robot-state and warning flag inputs, holding register 0 and
    // the speed limits (holding registers 104-107).
    let telemetry = link.read_telemetry().await.unwrap();
    let reads = arm.with(|s| s.reads());
    assert_eq!(
        reads[first..],
        [
            (2, 32, 31),
            (4, 0, 1),
            (4, 2, 12),
            (4, 34, 106),
            (3, 100, 3)
        ]
    );
    // What they carried is kept from the last read of them.
    assert_eq!(telemetry.speed_limits.linear, 0.5);
    assert_eq!(telemetry.tcp.wrench.torque_z, 12.0);
    // A second on, a snapshot reads them again.
    tokio::time::sleep(SLOW_REFRESH + Duration::from_millis(50)).await;
    let before = arm.with(|s| s.reads()).len();
    link.read_telemetry().await.unwrap();
    let reads = arm.with(|s| s.reads());
    assert_eq!(reads[before..].len(), 9, "{:?}", &reads[before..]);
    assert!(reads[before..].contains(&(2, 0, 10)) && reads[before..].contains(&(3, 0, 1)));
}

#[tokio::test]
async fn a_strict_arms_speed_limits_are_read_afresh_before_a_capped_move_and_after_a_write() {
    let arm = strict_arm().await;
    let (link, _events) = ModbusLink::connect(config(&arm)).await.unwrap();
    link.read_telemetry().await.unwrap();
    link.read_telemetry().await.unwrap();
    // The integrator lowers the arm's limit to 0.2 m/s within the second the limits are not
    // polled: a move capped at 0.25 m/s must see it, or it would raise the limit to the cap.
    arm.with(|s| s.set_holding_f32(104, 0.2));
    let before = arm.with(|s| s.reads()).len();
    let pose = home_tcp();
    // The turn at the arm's hard limit: only the linear limit is in question here.
    let cap = armjog::kortex::SpeedLimits {
        linear: 0.25,
        angular: armjog::kortex::commands::MAX_ANGULAR_SPEED,
    };
    link.go_to_pose(ReferenceFrame::Base, pose, Some(cap))
        .await
        .unwrap();
    let reads = arm.with(|s| s.reads());
    assert!(
        reads[before..].contains(&(3, 104, 4)),
        "{:?}",
        &reads[before..]
    );
    assert!(
        !arm.writes()
            .iter()
            .any(|w| matches!(w, Written::Registers(216, _))),
        "the limits were written: {:?}",
        arm.writes()
    );
    // A limit the console writes is read back in the next snapshot, within the second too.
    link.read_telemetry().await.unwrap();
    link.set_speed_limits(0.1, 10.0).await.unwrap();
    let before = arm.with(|s| s.reads()).len();
    link.read_telemetry().await.unwrap();
    let reads = arm.with(|s| s.reads());
    assert!(
        reads[before..].contains(&(3, 104, 4)),
        "{:?}",
        &reads[before..]
    );
}
