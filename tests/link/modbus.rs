//! The Modbus link against an in-process fake arm on loopback: exact write sequences (a
//! twist, its update, poses, actions, speed limits, coils, the polar pan), values refused
//! before sending, exceptions by name. Polls are in `modbus_polls.rs`, timeouts and reconnects
//! in `modbus_reconnects.rs`, the stops that keep a twist from running on in `modbus_stops.rs`.

use crate::common::home_tcp;
use crate::modbus_fake;

use std::time::Duration;

use armjog::kortex::{ControlCoil, Pose, ReferenceFrame, Stored, Twist};
use armjog::link::modbus::{ModbusConfig, ModbusLink};
use modbus_fake::{Behaviour, FakeArm, Written, from_cdab, stop_write};
use tokio_modbus::{ExceptionCode, Request};

pub(crate) const WAIT: Duration = Duration::from_secs(3);

pub(crate) fn config(arm: &FakeArm) -> ModbusConfig {
    let mut config = ModbusConfig::new(arm.addr());
    config.poll_rate_hz = None;
    config.twist_hold = None;
    config.request_timeout = Duration::from_millis(200);
    config.reconnect_delay = Duration::from_millis(20);
    config.reconnect_max_delay = Duration::from_millis(100);
    config
}

/// x 0.25 m/s, z -0.25 m/s, theta z 90 deg/s.
pub(crate) fn sample_twist() -> Twist {
    Twist {
        x: 0.25,
        z: -0.25,
        theta_z: 90.0,
        ..Twist::ZERO
    }
}

/// The twist start sequence for `sample_twist` in the base frame, written out by hand.
pub(crate) fn sample_twist_writes() -> Vec<Written> {
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
    assert!(
        link.go_to_pose(ReferenceFrame::Base, far, None)
            .await
            .is_err()
    );
    assert!(
        link.polar_pan_with(1.5, 0.0, link.config().polar)
            .await
            .is_err()
    );
    for motion in [
        armjog::kortex::StoredMotion::Action,
        armjog::kortex::StoredMotion::Sequence,
    ] {
        let e = link
            .start_stored(Stored { motion, id: 0 }, None)
            .await
            .unwrap_err();
        assert!(e.refused_before_sending(), "{e}");
        let e = link
            .start_stored(
                Stored { motion, id: 0 },
                Some(armjog::kortex::SpeedLimits {
                    linear: 0.1,
                    angular: 10.0,
                }),
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
    link.go_to_pose(ReferenceFrame::Base, pose, None)
        .await
        .unwrap();
    link.start_stored(link.config().home_action(), None)
        .await
        .unwrap();
    link.start_stored(
        Stored {
            motion: armjog::kortex::StoredMotion::Sequence,
            id: 17,
        },
        None,
    )
    .await
    .unwrap();
    link.set_speed_limits(0.25, 100.0).await.unwrap();
    link.pulse(ControlCoil::QuickStop).await.unwrap();
    link.pulse(ControlCoil::Abort).await.unwrap();
    link.pulse(ControlCoil::FaultReset).await.unwrap();
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
    let e = link.pulse(ControlCoil::FaultReset).await.unwrap_err();
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
async fn polar_pan_orbits_the_base_from_the_live_pose() {
    let arm = FakeArm::start().await;
    arm.with(|s| {
        s.set_input_f32(104, 0.5);
        s.set_input_f32(108, 0.3);
    });
    let mut config = config(&arm);
    config.poll_rate_hz = Some(50.0);
    let (link, _events) = ModbusLink::connect(config).await.unwrap();
    link.polar_pan_with(1.0, 0.0, link.config().polar)
        .await
        .unwrap();
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
    link.polar_pan_with(0.0, 0.0, link.config().polar)
        .await
        .unwrap();
    assert_eq!(arm.writes().last(), Some(&stop_write()));
}

#[tokio::test]
async fn polar_pan_on_the_base_axis_is_refused_without_moving() {
    let arm = FakeArm::start().await;
    arm.with(|s| s.set_input_f32(108, 0.9));
    let mut config = config(&arm);
    config.poll_rate_hz = Some(20.0);
    let (link, _events) = ModbusLink::connect(config).await.unwrap();
    let e = link
        .polar_pan_with(0.0, 1.0, link.config().polar)
        .await
        .unwrap_err();
    assert!(e.to_string().contains("base Z axis"), "{e}");
    assert!(arm.writes().is_empty());
}

/// Builder for the tests above.
pub(crate) trait WithX {
    fn with_x(self, x: f32) -> Self;
}

impl WithX for Twist {
    fn with_x(self, x: f32) -> Self {
        Twist { x, ..self }
    }
}
