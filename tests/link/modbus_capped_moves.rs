//! Capped moves over Modbus against the fake arm: the exact limit writes around a move, the
//! limits put back on each way a move ends, and what happens when they cannot be.

use crate::modbus_fake;

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use armjog::kortex::{Pose, ReferenceFrame, SpeedLimits};
use armjog::link::modbus::{ModbusConfig, ModbusError, ModbusEvent, ModbusLink};
use modbus_fake::{Behaviour, FakeArm, Written, cdab, fill_known_telemetry, stop_write};
use tokio::sync::mpsc::UnboundedReceiver;
use tokio_modbus::{ExceptionCode, Request};

const WAIT: Duration = Duration::from_secs(5);
/// The cap of these moves: the tool at 50 mm/s, its turn at 15 deg/s.
const CAP: SpeedLimits = SpeedLimits {
    linear: 0.05,
    angular: 15.0,
};

/// A fake arm at rest whose configured limits are 0.3 m/s and 80 deg/s.
async fn arm() -> FakeArm {
    let arm = FakeArm::start().await;
    arm.with(|s| {
        fill_known_telemetry(s);
        s.set_holding_f32(104, 0.3);
        s.set_holding_f32(106, 80.0);
    });
    arm
}

async fn link(arm: &FakeArm) -> (ModbusLink, UnboundedReceiver<ModbusEvent>) {
    let mut config = ModbusConfig::new(arm.addr());
    config.poll_rate_hz = Some(50.0);
    config.request_timeout = Duration::from_millis(300);
    config.reconnect_delay = Duration::from_millis(20);
    config.reconnect_max_delay = Duration::from_millis(100);
    ModbusLink::connect(config).await.expect("connect")
}

fn limits_write(linear: f32, angular: f32) -> Written {
    let [a, b] = cdab(linear);
    let [c, d] = cdab(angular);
    Written::Registers(216, vec![a, b, c, d])
}

fn target() -> Pose {
    Pose {
        x: 0.4,
        y: 0.1,
        z: 0.5,
        theta_x: 90.0,
        theta_y: 0.0,
        theta_z: 90.0,
    }
}

fn limit_writes(arm: &FakeArm) -> Vec<Written> {
    arm.writes()
        .into_iter()
        .filter(|w| matches!(w, Written::Registers(216, _)))
        .collect()
}

async fn next_matching(
    events: &mut UnboundedReceiver<ModbusEvent>,
    wanted: impl Fn(&ModbusEvent) -> bool,
) -> ModbusEvent {
    let wait = async {
        while let Some(e) = events.recv().await {
            if wanted(&e) {
                return e;
            }
        }
        panic!("link ended");
    };
    tokio::time::timeout(WAIT, wait)
        .await
        .expect("event in time")
}

#[tokio::test]
async fn a_capped_move_lowers_the_limit_first_and_restores_it_when_the_arm_reports_the_end() {
    let arm = arm().await;
    let (link, mut events) = link(&arm).await;
    let report = link
        .go_to_pose(ReferenceFrame::Base, target(), Some(CAP))
        .await
        .expect("move");
    let writes = arm.writes();
    // The limits first (both lowered to the cap), then Kinova's start sequence.
    assert_eq!(writes[0], limits_write(0.05, 15.0));
    assert_eq!(writes[1], Written::Registers(200, vec![0]));
    assert_eq!(writes.last(), Some(&Written::Registers(200, vec![1])));
    assert_eq!(
        report.writes.len(),
        writes.len(),
        "the report lists them all"
    );
    let lowered = next_matching(&mut events, |e| {
        matches!(e, ModbusEvent::SpeedLimitsLowered { .. })
    })
    .await;
    assert_eq!(
        lowered,
        ModbusEvent::SpeedLimitsLowered {
            limits: CAP,
            previous: SpeedLimits {
                linear: 0.3,
                angular: 80.0
            }
        }
    );

    // The arm runs the move (status started), then completes it.
    arm.with(|s| s.holding_registers[100] = 0);
    tokio::time::sleep(Duration::from_millis(200)).await;
    assert_eq!(limit_writes(&arm).len(), 1, "kept low while the move runs");
    arm.with(|s| s.holding_registers[100] = 1);
    next_matching(&mut events, |e| {
        matches!(e, ModbusEvent::SpeedLimitsRestored { .. })
    })
    .await;
    assert_eq!(
        limit_writes(&arm),
        [limits_write(0.05, 15.0), limits_write(0.3, 80.0)]
    );
    link.close().await.expect("close");
    assert_eq!(limit_writes(&arm).len(), 2, "nothing more on close");
}

#[tokio::test]
async fn limits_already_under_the_cap_are_left_alone() {
    let arm = arm().await;
    arm.with(|s| {
        s.set_holding_f32(104, 0.03);
        s.set_holding_f32(106, 10.0);
    });
    let (link, _events) = link(&arm).await;
    link.start_stored(link.config().home_action(), Some(CAP))
        .await
        .expect("home");
    assert!(limit_writes(&arm).is_empty(), "{:?}", arm.writes());
    link.close().await.expect("close");
    assert!(limit_writes(&arm).is_empty());
}

#[tokio::test]
async fn each_limit_is_lowered_to_the_caps_and_never_raised() {
    // The arm turns slower than the cap allows: its angular limit is kept, the linear lowered.
    let arm = arm().await;
    arm.with(|s| s.set_holding_f32(106, 10.0));
    let (link, _events) = link(&arm).await;
    link.go_to_pose(ReferenceFrame::Base, target(), Some(CAP))
        .await
        .expect("move");
    assert_eq!(limit_writes(&arm), [limits_write(0.05, 10.0)]);
    link.close().await.expect("close");
    assert_eq!(limit_writes(&arm)[1..], [limits_write(0.3, 10.0)]);

    // The arm's tool is slower than the cap: only the turn is lowered.
    let arm = self::arm().await;
    arm.with(|s| s.set_holding_f32(104, 0.03));
    let (link, _events) = self::link(&arm).await;
    link.start_stored(link.config().home_action(), Some(CAP))
        .await
        .expect("home");
    assert_eq!(limit_writes(&arm), [limits_write(0.03, 15.0)]);
    link.close().await.expect("close");
    assert_eq!(limit_writes(&arm)[1..], [limits_write(0.03, 80.0)]);
}

#[tokio::test]
async fn a_move_is_refused_when_the_arm_reports_no_usable_limits() {
    let arm = arm().await;
    arm.with(|s| s.set_holding_f32(104, f32::NAN));
    let (link, _events) = link(&arm).await;
    let e = link
        .go_to_pose(ReferenceFrame::Base, target(), Some(CAP))
        .await
        .expect_err("refused");
    assert!(matches!(e, ModbusError::SpeedLimitsUnknown { .. }), "{e}");
    assert!(arm.writes().is_empty(), "{:?}", arm.writes());
}

#[tokio::test]
async fn a_stop_or_a_jog_ends_the_move_and_gives_the_limits_back() {
    let arm = arm().await;
    let (link, _events) = link(&arm).await;
    link.start_stored(link.config().home_action(), Some(CAP))
        .await
        .expect("home");
    arm.with(|s| s.holding_registers[100] = 0);
    link.stop().await.expect("stop");
    let writes = arm.writes();
    let n = writes.len();
    assert_eq!(writes[n - 2..], [stop_write(), limits_write(0.3, 80.0)]);

    // A twist replacing a capped move: limits back after the twist is written.
    link.go_to_pose(ReferenceFrame::Base, target(), Some(CAP))
        .await
        .expect("move");
    let twist = armjog::kortex::Twist {
        x: 0.02,
        ..armjog::kortex::Twist::ZERO
    };
    link.jog_twist(ReferenceFrame::Base, twist)
        .await
        .expect("twist");
    assert_eq!(arm.writes().last(), Some(&limits_write(0.3, 80.0)));
    link.close().await.expect("close");
}

#[tokio::test]
async fn closing_the_link_mid_move_stops_it_before_restoring_the_limits() {
    let arm = arm().await;
    let (link, _events) = link(&arm).await;
    link.go_to_pose(ReferenceFrame::Base, target(), Some(CAP))
        .await
        .expect("move");
    arm.with(|s| s.holding_registers[100] = 0);
    let before = arm.writes().len();
    link.close().await.expect("close");
    assert_eq!(
        arm.writes()[before..],
        [stop_write(), limits_write(0.3, 80.0)]
    );
}

#[tokio::test]
async fn a_restore_the_arm_refuses_is_reported_with_the_limits_to_set_again() {
    let arm = arm().await;
    // The first limit write is accepted, every later one refused.
    let seen = Arc::new(AtomicUsize::new(0));
    arm.rule(move |r| match r {
        Request::WriteMultipleRegisters(216, _) if seen.fetch_add(1, Ordering::SeqCst) > 0 => {
            Some(Behaviour::Exception(ExceptionCode::IllegalDataValue))
        }
        _ => None,
    });
    let (link, mut events) = link(&arm).await;
    link.start_stored(link.config().home_action(), Some(CAP))
        .await
        .expect("home");
    link.stop().await.expect("stop");
    let e = next_matching(&mut events, |e| {
        matches!(e, ModbusEvent::SpeedLimitsNotRestored { .. })
    })
    .await;
    let ModbusEvent::SpeedLimitsNotRestored { limits, error } = e else {
        unreachable!()
    };
    assert_eq!(
        limits,
        SpeedLimits {
            linear: 0.3,
            angular: 80.0
        }
    );
    assert!(error.to_string().contains("illegal data value"), "{error}");
    link.close().await.expect("close");
}

#[tokio::test]
async fn limits_owed_when_the_connection_drops_are_restored_after_the_reconnect() {
    let arm = arm().await;
    let (link, mut events) = link(&arm).await;
    link.start_stored(link.config().home_action(), Some(CAP))
        .await
        .expect("home");
    arm.with(|s| s.holding_registers[100] = 0);
    // Give the background polls a chance to see the move running, then hang up.
    tokio::time::sleep(Duration::from_millis(100)).await;
    arm.hang_up_all();
    next_matching(&mut events, |e| {
        matches!(e, ModbusEvent::Reconnected { .. })
    })
    .await;
    // The move ends on the arm: the next polls see it and the limits go back.
    arm.with(|s| s.holding_registers[100] = 1);
    next_matching(&mut events, |e| {
        matches!(e, ModbusEvent::SpeedLimitsRestored { .. })
    })
    .await;
    assert_eq!(limit_writes(&arm).last(), Some(&limits_write(0.3, 80.0)));
    link.close().await.expect("close");
}

/// Another client's capped move runs (the arm reports action 5 started and moves): the limits
/// in force may be that client's lowered ones, which a move of ours would put back at its end
/// as the arm's own, for good. Nothing is written; a twist the arm runs is no such move.
#[tokio::test]
async fn no_capped_move_is_started_over_another_clients_running_move() {
    let arm = arm().await;
    arm.with(|s| {
        s.holding_registers[100] = 0; // started
        s.holding_registers[101] = 5;
        s.holding_registers[102] = 0; // action
    });
    let (link, _events) = link(&arm).await;
    let e = link
        .go_to_pose(ReferenceFrame::Base, target(), Some(CAP))
        .await
        .expect_err("refused");
    assert!(
        matches!(&e, ModbusError::AnotherMoveRuns(what) if what == "action 5"),
        "{e}"
    );
    assert!(arm.writes().is_empty(), "{:?}", arm.writes());

    // The same arm running a twist (a jog: no limits lowered for it) takes the move.
    arm.with(|s| s.holding_registers[102] = 3);
    link.go_to_pose(ReferenceFrame::Base, target(), Some(CAP))
        .await
        .expect("move");
    assert_eq!(limit_writes(&arm), [limits_write(0.05, 15.0)]);
    link.close().await.expect("close");
}
