//! The Modbus link against an in-process fake arm on loopback: polls, exact write sequences,
//! exceptions, timeouts, reconnects, and the stops that keep a twist from running on.

use crate::common::home_tcp;
use crate::modbus_fake;

use std::time::Duration;

use armjog::kortex::{Pose, ReferenceFrame, RobotState, SLOW_REFRESH, Twist};
use armjog::link::modbus::{ModbusConfig, ModbusError, ModbusEvent, ModbusLink, StopReason};
use modbus_fake::{Behaviour, FakeArm, Written, fill_known_telemetry, from_cdab, stop_write};
use tokio_modbus::{ExceptionCode, Request};

const WAIT: Duration = Duration::from_secs(3);

fn config(arm: &FakeArm) -> ModbusConfig {
    let mut config = ModbusConfig::new(arm.addr());
    config.poll_rate_hz = None;
    config.twist_hold = None;
    config.request_timeout = Duration::from_millis(200);
    config.reconnect_delay = Duration::from_millis(20);
    config.reconnect_max_delay = Duration::from_millis(100);
    config
}

/// x 0.25 m/s, z -0.25 m/s, theta z 90 deg/s.
fn sample_twist() -> Twist {
    Twist {
        x: 0.25,
        z: -0.25,
        theta_z: 90.0,
        ..Twist::ZERO
    }
}

/// The twist start sequence for `sample_twist` in the base frame, written out by hand.
/// A fake arm with known telemetry that refuses reads over addresses the ICD does not list.
async fn strict_arm() -> FakeArm {
    let arm = FakeArm::start().await;
    arm.with(|s| {
        fill_known_telemetry(s);
        s.strict_addresses = true;
    });
    arm
}

fn sample_twist_writes() -> Vec<Written> {
    vec![
        Written::Registers(200, vec![0]),
        Written::Registers(
            202,
            vec![
                3, 3, // twist, base frame
                0x0000, 0x3E80, // x 0.25
                0x0000, 0x0000, // y 0
                0x0000, 0xBE80, // z -0.25
                0x0000, 0x0000, // theta x 0
                0x0000, 0x0000, // theta y 0
                0x0000, 0x42B4, // theta z 90
            ],
        ),
        Written::Registers(200, vec![1]),
    ]
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
    link.fault_reset().await.unwrap();
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
    link.go_to_pose_capped(ReferenceFrame::Base, pose, cap)
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

#[tokio::test]
async fn a_twist_is_written_exactly_and_stopped_on_request() {
    let arm = FakeArm::start().await;
    let (link, _events) = ModbusLink::connect(config(&arm)).await.unwrap();
    let report = link
        .jog_twist(ReferenceFrame::Base, sample_twist())
        .await
        .unwrap();
    assert_eq!(report.writes.len(), 3);
    assert_eq!(arm.writes(), sample_twist_writes());
    // The same twist again only refreshes the hold.
    let again = link
        .jog_twist(ReferenceFrame::Base, sample_twist())
        .await
        .unwrap();
    assert!(again.writes.is_empty());
    assert_eq!(arm.writes().len(), 3);
    link.stop().await.unwrap();
    let mut expected = sample_twist_writes();
    expected.push(stop_write());
    assert_eq!(arm.writes(), expected);
}

#[tokio::test]
async fn an_update_restarts_the_twist_with_the_new_values_and_frame() {
    let arm = FakeArm::start().await;
    let (link, _events) = ModbusLink::connect(config(&arm)).await.unwrap();
    link.jog_twist(ReferenceFrame::Base, sample_twist())
        .await
        .unwrap();
    let slower = Twist {
        y: -0.5,
        ..Twist::ZERO
    };
    link.jog_twist(ReferenceFrame::Tool, slower).await.unwrap();
    let writes = arm.writes();
    assert_eq!(writes.len(), 6);
    assert_eq!(writes[3], Written::Registers(200, vec![0]));
    assert_eq!(
        writes[4],
        Written::Registers(
            202,
            vec![3, 2, 0, 0, 0x0000, 0xBF00, 0, 0, 0, 0, 0, 0, 0, 0]
        )
    );
    assert_eq!(writes[5], Written::Registers(200, vec![1]));
    // A zero twist is a stop.
    link.jog_twist(ReferenceFrame::Tool, Twist::ZERO)
        .await
        .unwrap();
    assert_eq!(arm.writes()[6], stop_write());
}

#[tokio::test]
async fn values_that_cannot_be_written_are_refused_before_sending() {
    let arm = FakeArm::start().await;
    let (link, _events) = ModbusLink::connect(config(&arm)).await.unwrap();
    let bad_twists = [
        Twist {
            x: f32::NAN,
            ..Twist::ZERO
        },
        Twist {
            theta_y: f32::INFINITY,
            ..Twist::ZERO
        },
        Twist {
            x: 0.4,
            y: 0.4,
            ..Twist::ZERO
        },
        Twist {
            theta_x: 80.0,
            theta_z: 80.0,
            ..Twist::ZERO
        },
    ];
    for twist in bad_twists {
        let e = link
            .jog_twist(ReferenceFrame::Base, twist)
            .await
            .unwrap_err();
        assert!(e.refused_before_sending(), "{e}");
    }
    for (linear, angular) in [(0.6, 50.0), (0.0, 50.0), (0.2, 101.0), (f32::NAN, 10.0)] {
        let e = link.set_speed_limits(linear, angular).await.unwrap_err();
        assert!(e.refused_before_sending(), "{e}");
    }
    let far = Pose {
        x: 456.6,
        ..Pose::default()
    };
    assert!(link.go_to_pose(ReferenceFrame::Base, far).await.is_err());
    assert!(link.polar_pan(1.5, 0.0).await.is_err());
    for motion in [
        armjog::kortex::StoredMotion::Action,
        armjog::kortex::StoredMotion::Sequence,
    ] {
        let e = link.start_stored(0, motion).await.unwrap_err();
        assert!(e.refused_before_sending(), "{e}");
        let e = link
            .start_stored_capped(
                0,
                motion,
                armjog::kortex::SpeedLimits {
                    linear: 0.1,
                    angular: 10.0,
                },
            )
            .await
            .unwrap_err();
        assert!(e.refused_before_sending(), "{e}");
    }
    assert!(arm.with(|s| s.log.is_empty()), "nothing was sent");
}

#[tokio::test]
async fn pose_action_speed_limit_and_coil_sequences() {
    let arm = FakeArm::start().await;
    let (link, _events) = ModbusLink::connect(config(&arm)).await.unwrap();
    let pose = home_tcp();
    link.go_to_pose(ReferenceFrame::Base, pose).await.unwrap();
    link.home().await.unwrap();
    link.start_stored(17, armjog::kortex::StoredMotion::Sequence)
        .await
        .unwrap();
    link.set_speed_limits(0.25, 100.0).await.unwrap();
    link.quick_stop().await.unwrap();
    link.abort().await.unwrap();
    link.fault_reset().await.unwrap();
    assert_eq!(
        arm.writes(),
        vec![
            Written::Registers(200, vec![0]),
            Written::Registers(
                202,
                vec![
                    2, 3, // cartesian trajectory, base
                    0xC77A, 0x3EE9, // 0.4566
                    0x126F, 0x3A83, // 0.001
                    0x1B09, 0x3EDE, // 0.4338
                    0x0000, 0x42B4, // 90
                    0x0000, 0x0000, // 0
                    0x0000, 0x42B4, // 90
                ]
            ),
            Written::Registers(200, vec![1]),
            // Home: action id 2 (the default), move type action.
            Written::Registers(200, vec![0]),
            Written::Registers(201, vec![2, 0]),
            Written::Registers(200, vec![1]),
            Written::Registers(200, vec![0]),
            Written::Registers(201, vec![17, 1]),
            Written::Registers(200, vec![1]),
            Written::Registers(216, vec![0x0000, 0x3E80, 0x0000, 0x42C8]),
            Written::Coil(0, true),
            Written::Coil(0, false),
            Written::Coil(1, true),
            Written::Coil(1, false),
            Written::Coil(2, true),
            Written::Coil(2, false),
        ]
    );
}

#[tokio::test]
async fn exceptions_are_typed_by_name() {
    let arm = FakeArm::start().await;
    arm.rule(|r| match r {
        Request::WriteSingleCoil(2, _) => {
            Some(Behaviour::Exception(ExceptionCode::IllegalFunction))
        }
        Request::ReadDiscreteInputs(..) => {
            Some(Behaviour::Exception(ExceptionCode::ServerDeviceBusy))
        }
        _ => None,
    });
    let (link, _events) = ModbusLink::connect(config(&arm)).await.unwrap();
    let e = link.fault_reset().await.unwrap_err();
    assert_eq!(e.exception(), Some(ExceptionCode::IllegalFunction));
    assert!(e.to_string().contains("illegal function (0x01)"), "{e}");
    assert!(e.to_string().contains("coil 2"), "{e}");
    let e = link.read_telemetry().await.unwrap_err();
    assert_eq!(e.exception(), Some(ExceptionCode::ServerDeviceBusy));
    assert!(!e.breaks_connection());
    // The connection is still in use: no reconnect for an exception.
    link.set_speed_limits(0.1, 10.0).await.unwrap();
    assert_eq!(arm.with(|s| s.connections), 1);
}

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
    link.home().await.unwrap();
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

#[tokio::test]
async fn polar_pan_orbits_the_base_from_the_live_pose() {
    let arm = FakeArm::start().await;
    arm.with(|s| {
        s.set_input_f32(104, 0.5);
        s.set_input_f32(108, 0.3);
    });
    let mut config = config(&arm);
    config.poll_rate_hz = Some(50.0);
    let (link, _events) = ModbusLink::connect(config).await.unwrap();
    link.polar_pan(1.0, 0.0).await.unwrap();
    let twist_block = |s: &modbus_fake::ArmState| {
        s.writes().into_iter().rev().find_map(|w| match w {
            Written::Registers(202, v) => Some(v),
            _ => None,
        })
    };
    let block = arm.with(|s| twist_block(s)).unwrap();
    assert_eq!(block[..2], [3, 3], "twist in the base frame");
    // Azimuth at 10 deg/s about base Z from (0.5, 0, 0.3): v = w x p = (0, 0.5 w, 0).
    let w = 10f32.to_radians();
    let value = |i: usize| from_cdab(&block[2 + 2 * i..4 + 2 * i]);
    assert!((value(1) - 0.5 * w).abs() < 1e-6, "{}", value(1));
    assert_eq!([value(0), value(2), value(3), value(4)], [0.0; 4]);
    assert_eq!(value(5), 10.0);
    // The arm moves: the next poll brings a new pose and a new twist.
    arm.with(|s| {
        s.set_input_f32(104, 0.0);
        s.set_input_f32(106, 0.5);
    });
    arm.wait_for(WAIT, |s| {
        twist_block(s).is_some_and(|b| from_cdab(&b[2..4]) < -0.08)
    })
    .await;
    link.polar_pan(0.0, 0.0).await.unwrap();
    assert_eq!(arm.writes().last(), Some(&stop_write()));
}

#[tokio::test]
async fn polar_pan_on_the_base_axis_is_refused_without_moving() {
    let arm = FakeArm::start().await;
    arm.with(|s| s.set_input_f32(108, 0.9));
    let mut config = config(&arm);
    config.poll_rate_hz = Some(20.0);
    let (link, _events) = ModbusLink::connect(config).await.unwrap();
    let e = link.polar_pan(0.0, 1.0).await.unwrap_err();
    assert!(e.to_string().contains("base Z axis"), "{e}");
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

/// Builder for the tests above.
trait WithX {
    fn with_x(self, x: f32) -> Self;
}

impl WithX for Twist {
    fn with_x(self, x: f32) -> Self {
        Twist { x, ..self }
    }
}
