//! The console's speed setting through the arm driver: it is adopted only once the arm accepts
//! it, and over Modbus it is the console's own (it never rewrites the arm's speed limits).

use crate::common;

use std::sync::Arc;
use std::time::Duration;

use tokio::sync::mpsc::UnboundedReceiver;

use armjog::link::driver::{Driver, DriverConfig};
use armjog::link::interface::{ArmCommand, ArmError, ArmEvent, CommandKind, LinkStatus};
use armjog::link::{ModbusConfig, TalosConfig};
use armjog::sim::{SimConfig, Simulator};
use armjog::talos::{Checksum, Reply, Request, ReturnCode, TalosFrame};
use common::{Action, TestOperator, reply_bytes};

/// Waits (up to 10 s) for an event that `wanted` picks, returning it and every event before it.
async fn until_event(
    events: &mut UnboundedReceiver<ArmEvent>,
    wanted: impl Fn(&ArmEvent) -> bool,
) -> (ArmEvent, Vec<ArmEvent>) {
    let mut before = Vec::new();
    let wait = async {
        while let Some(event) = events.recv().await {
            if wanted(&event) {
                return event;
            }
            before.push(event);
        }
        panic!("the driver ended");
    };
    let event = tokio::time::timeout(Duration::from_secs(10), wait)
        .await
        .expect("the event came within 10 s");
    (event, before)
}

async fn link_up(events: &mut UnboundedReceiver<ArmEvent>) {
    until_event(events, |e| {
        matches!(e, ArmEvent::Status(LinkStatus::Up { .. }))
    })
    .await;
}

fn is_speed(e: &ArmEvent) -> bool {
    matches!(e, ArmEvent::Speed(_))
}

fn speed_events(events: &[ArmEvent]) -> Vec<u8> {
    events
        .iter()
        .filter_map(|e| match e {
            ArmEvent::Speed(s) => Some(*s),
            _ => None,
        })
        .collect()
}

/// Holding registers 216-219 as last written, and the limits in force (m/s, deg/s).
async fn limits(sim: &Simulator) -> ([u16; 4], (f64, f64)) {
    sim.arm
        .with_world(|w| {
            let mut desired = [0u16; 4];
            desired.copy_from_slice(&w.command_block[16..20]);
            (desired, w.arm.speed_limits())
        })
        .await
        .expect("sim alive")
}

#[tokio::test]
async fn speed_keys_over_modbus_never_write_the_arms_speed_limits() {
    let sim = Simulator::start(SimConfig::ephemeral())
        .await
        .expect("simulator");
    // The technician configured the arm's limits beforehand (`armjog modbus speed-limit`).
    sim.arm
        .with(|arm, _| arm.set_speed_limits(0.05, 20.0))
        .await
        .expect("sim alive")
        .expect("limits accepted");
    let before = limits(&sim).await;
    let modbus = ModbusConfig::new(sim.modbus_addr.expect("modbus").to_string());
    let (driver, mut events) = Driver::spawn(DriverConfig::new(None, Some(modbus)));
    link_up(&mut events).await;

    for (speed, expect) in [(60u8, 60u8), (40, 40), (100, 100), (1, 1)] {
        assert!(driver.send(ArmCommand::SetSpeed(speed)));
        let (event, _) = until_event(&mut events, is_speed).await;
        assert_eq!(event, ArmEvent::Speed(expect));
    }
    assert_eq!(limits(&sim).await, before, "216-219 and 104-107 unchanged");
    assert_eq!(before.1, (0.05, 20.0));
    driver.shutdown().await;
    assert_eq!(limits(&sim).await, before, "still unchanged after quit");
}

#[tokio::test]
async fn a_speed_outside_1_to_100_over_modbus_is_refused_and_the_old_one_stays() {
    let sim = Simulator::start(SimConfig::ephemeral())
        .await
        .expect("simulator");
    let modbus = ModbusConfig::new(sim.modbus_addr.expect("modbus").to_string());
    let (driver, mut events) = Driver::spawn(DriverConfig::new(None, Some(modbus)));
    link_up(&mut events).await;
    assert!(driver.send(ArmCommand::SetSpeed(30)));
    assert_eq!(
        until_event(&mut events, is_speed).await.0,
        ArmEvent::Speed(30)
    );

    for bad in [0u8, 101, 255] {
        assert!(driver.send(ArmCommand::SetSpeed(bad)));
        let (failed, before) =
            until_event(&mut events, |e| matches!(e, ArmEvent::Failed { .. })).await;
        assert!(speed_events(&before).is_empty(), "{before:?}");
        let ArmEvent::Failed { command, error } = failed else {
            unreachable!()
        };
        assert_eq!(command, CommandKind::SetSpeed);
        assert_eq!(
            error,
            ArmError::SpeedOutOfRange {
                requested: bad,
                in_force: 30
            },
            "names the speed in force"
        );
    }
    // The speed in force is still 30: a jog refresh now sends a 30 % twist (75 mm/s).
    assert!(driver.send(ArmCommand::Jog(
        armjog::console::jog::JogMotion::Cartesian { x: 1, y: 0, z: 0 }
    )));
    let twist = async {
        loop {
            let s = sim.arm.snapshot().await.expect("sim alive");
            if s.tcp_linear_velocity[0] > 0.05 {
                return s.tcp_linear_velocity[0];
            }
            tokio::time::sleep(Duration::from_millis(10)).await;
        }
    };
    let vx = tokio::time::timeout(Duration::from_secs(10), twist)
        .await
        .expect("the jog moved the arm");
    assert!(driver.send(ArmCommand::Stop));
    assert!((0.06..=0.0755).contains(&vx), "30 % of 250 mm/s: {vx}");
    driver.shutdown().await;
}

#[tokio::test]
async fn a_set_speed_the_simulated_operator_refuses_leaves_the_speed_unchanged() {
    let sim = Simulator::start(SimConfig::ephemeral())
        .await
        .expect("simulator");
    let talos = TalosConfig::new(sim.talos_addr.to_string());
    let (driver, mut events) = Driver::spawn(DriverConfig::new(Some(talos), None));
    // The speed read at connection (the operator's 50 %).
    assert_eq!(
        until_event(&mut events, is_speed).await.0,
        ArmEvent::Speed(50)
    );
    link_up(&mut events).await;

    assert!(driver.send(ArmCommand::SetSpeed(0)));
    let (failed, before) = until_event(&mut events, |e| matches!(e, ArmEvent::Failed { .. })).await;
    assert!(speed_events(&before).is_empty(), "{before:?}");
    assert!(
        matches!(
            &failed,
            ArmEvent::Failed {
                command: CommandKind::SetSpeed,
                error: ArmError::ReturnCode(ReturnCode::OUT_OF_RANGE)
            }
        ),
        "{failed:?}"
    );
    // Joint jogs still run at 50 % of 20 deg/s (a refused 0 % adopted would not move at all).
    until_event(&mut events, |e| matches!(e, ArmEvent::Telemetry(_))).await;
    assert!(
        driver.send(ArmCommand::Jog(armjog::console::jog::JogMotion::Joint {
            joint: 1,
            direction: 1
        }))
    );
    let moving = async {
        loop {
            let s = sim.arm.snapshot().await.expect("sim alive");
            if s.joint_velocity[0] > 1.0 {
                return s.joint_velocity[0];
            }
            tokio::time::sleep(Duration::from_millis(10)).await;
        }
    };
    let rate = tokio::time::timeout(Duration::from_secs(10), moving)
        .await
        .expect("the joint jog moved J1");
    assert!(driver.send(ArmCommand::Stop));
    assert!((rate - 10.0).abs() < 0.01, "J1 at {rate} deg/s");
    // An accepted one is adopted after the reply.
    assert!(driver.send(ArmCommand::SetSpeed(70)));
    let (event, before) = until_event(&mut events, is_speed).await;
    assert_eq!(event, ArmEvent::Speed(70));
    assert!(!before.iter().any(|e| matches!(e, ArmEvent::Failed { .. })));
    assert_eq!(
        sim.arm.with(|_, op| op.speed()).await.expect("sim alive"),
        70
    );
    driver.shutdown().await;
}

#[tokio::test]
async fn a_set_speed_answered_with_an_error_is_not_adopted() {
    // A scripted operator: speed 40 at connection, every Set Speed answered INTERNAL_ERROR.
    let checksum = Checksum::Crc16;
    let script: common::Script = Arc::new(move |f: &TalosFrame| {
        let reply = match Request::from_frame(f) {
            Ok(Request::Handshake { .. }) => Reply::Handshake {
                return_code: ReturnCode::OK,
                major_version: 1,
                minor_version: 0,
            },
            Ok(Request::GetSpeed) => Reply::GetSpeed {
                return_code: ReturnCode::OK,
                speed: 40,
            },
            Ok(other) if other.command() == Request::SetSpeed { speed: 1 }.command() => {
                Reply::error(other.command(), ReturnCode::INTERNAL_ERROR)
            }
            Ok(other) => Reply::error(other.command(), ReturnCode::OK),
            Err(_) => return Vec::new(),
        };
        vec![Action::Write(reply_bytes(&reply, f.id, checksum))]
    });
    let op = TestOperator::start(checksum, script).await;
    let mut talos = TalosConfig::new(op.addr.clone());
    talos.checksum = checksum;
    let mut config = DriverConfig::new(Some(talos), None);
    // No telemetry polls cluttering the scripted operator.
    config.hw_telemetry_hz = 0.5;
    let (driver, mut events) = Driver::spawn(config);
    assert_eq!(
        until_event(&mut events, is_speed).await.0,
        ArmEvent::Speed(40)
    );
    link_up(&mut events).await;

    for speed in [80u8, 10] {
        assert!(driver.send(ArmCommand::SetSpeed(speed)));
        let (failed, before) =
            until_event(&mut events, |e| matches!(e, ArmEvent::Failed { .. })).await;
        assert!(speed_events(&before).is_empty(), "{before:?}");
        assert!(
            matches!(
                &failed,
                ArmEvent::Failed {
                    command: CommandKind::SetSpeed,
                    error: ArmError::ReturnCode(ReturnCode::INTERNAL_ERROR)
                }
            ),
            "{failed:?}"
        );
    }
    driver.shutdown().await;
}

#[tokio::test]
async fn talos_joint_jogs_keep_the_tool_under_the_consoles_cap() {
    // The operator would allow 500 mm/s: only the console's lever-arm bound keeps J2 under the
    // console's 50 mm/s, whatever joint jog rate is configured.
    let sim = Simulator::start(SimConfig {
        max_jog_speed: 0.5,
        ..SimConfig::ephemeral()
    })
    .await
    .expect("simulator");
    let talos = TalosConfig::new(sim.talos_addr.to_string());
    let mut config = DriverConfig::new(Some(talos), None);
    config.max_jog_speed = 0.05;
    config.joint_jog_speed = 60.0;
    let (driver, mut events) = Driver::spawn(config);
    link_up(&mut events).await;
    assert!(driver.send(ArmCommand::SetSpeed(100)));
    assert_eq!(
        until_event(&mut events, is_speed).await.0,
        ArmEvent::Speed(100)
    );
    until_event(&mut events, |e| matches!(e, ArmEvent::Telemetry(_))).await;

    for (joint, direction) in [(2u8, -1i8), (1, 1), (4, 1)] {
        let jog = ArmCommand::Jog(armjog::console::jog::JogMotion::Joint { joint, direction });
        let mut top = 0.0f64;
        let until = tokio::time::Instant::now() + Duration::from_millis(800);
        let mut resend = tokio::time::Instant::now();
        while tokio::time::Instant::now() < until {
            if tokio::time::Instant::now() >= resend {
                assert!(driver.send(jog.clone()));
                resend += Duration::from_millis(100);
            }
            let v = sim
                .arm
                .snapshot()
                .await
                .expect("sim alive")
                .tcp_linear_velocity;
            top = top.max((v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt());
            tokio::time::sleep(Duration::from_millis(5)).await;
        }
        assert!(driver.send(ArmCommand::Stop));
        let stopped = async {
            while sim.arm.snapshot().await.expect("sim alive").moving {
                tokio::time::sleep(Duration::from_millis(10)).await;
            }
        };
        tokio::time::timeout(Duration::from_secs(10), stopped)
            .await
            .expect("stopped");
        assert!(
            top <= 0.05 * 1.01 && top > 0.025,
            "J{joint}: top tool speed {:.1} mm/s",
            top * 1000.0
        );
    }
    driver.shutdown().await;
}

#[test]
fn the_status_bar_shows_the_jog_speed_from_the_cap_and_the_percent() {
    use armjog::console::app::{App, AppConfig, Input};
    use armjog::console::jog::ReleaseMode;
    use armjog::console::keymap::Keymap;
    use armjog::console::positions::PositionBook;
    use armjog::console::ui::status::speed_text;
    use armjog::console::view::View;

    let mut app = App::new(
        AppConfig {
            keymap: Keymap::builtin("default").expect("keymap").into(),
            release_mode: ReleaseMode::Reported,
            refresh: Duration::from_millis(100),
            positions_on_operator: false,
            max_jog_speed: 0.05,
            joint_jog_speed: armjog::link::driver::JOINT_JOG_SPEED,
            frames: true,
            simulated: false,
            arm_name: None,
            home_action: None,
            fence: None,

            config_file: None,

            new_profile: Vec::new(),

            recording_off: false,
        },
        PositionBook::new(),
    );
    assert_eq!(
        speed_text(&View::new(&app)),
        "?",
        "unknown until the arm reports it"
    );
    let now = std::time::Instant::now();
    for (percent, text) in [
        (100, "100% (≤50 mm/s)"),
        (40, "40% (≤20 mm/s)"),
        (1, "1% (≤0.5 mm/s)"),
    ] {
        app.handle(Input::Arm(ArmEvent::Speed(percent)), now);
        assert_eq!(speed_text(&View::new(&app)), text);
    }
}

#[tokio::test]
async fn a_speed_the_operator_accepted_also_bounds_moves_over_modbus() {
    // Jogs through the operator, go-to of the console's own poses over Modbus: one speed in
    // force for both, whichever link set it.
    let sim = Simulator::start(SimConfig::ephemeral())
        .await
        .expect("simulator");
    sim.arm
        .with(|arm, _| arm.set_speed_limits(0.3, 80.0))
        .await
        .expect("sim alive")
        .expect("limits accepted");
    let talos = TalosConfig::new(sim.talos_addr.to_string());
    let modbus = ModbusConfig::new(sim.modbus_addr.expect("modbus").to_string());
    let mut config = DriverConfig::new(Some(talos), Some(modbus));
    config.max_jog_speed = 0.1;
    let (driver, mut events) = Driver::spawn(config);
    link_up(&mut events).await;
    assert!(driver.send(ArmCommand::SetSpeed(20)));
    let (event, before) = until_event(&mut events, is_speed).await;
    assert_eq!(event, ArmEvent::Speed(20), "{before:?}");

    let (telemetry, _) = until_event(&mut events, |e| matches!(e, ArmEvent::Telemetry(_))).await;
    let ArmEvent::Telemetry(telemetry) = telemetry else {
        unreachable!()
    };
    let mut target = telemetry.tcp.pose;
    target.x += 0.01;
    assert!(driver.send(ArmCommand::MoveToPose(target)));
    // The link lowers the arm's linear limit to the tool speed for the move: 20 % of 100 mm/s.
    let lowest = async {
        loop {
            let s = sim.arm.snapshot().await.expect("sim alive");
            if s.speed_limit_linear < 0.29 {
                return s.speed_limit_linear;
            }
            tokio::time::sleep(Duration::from_millis(2)).await;
        }
    };
    let lowered = tokio::time::timeout(Duration::from_secs(10), lowest)
        .await
        .expect("the move lowered the limit within 10 s");
    assert!(
        (lowered - 0.02).abs() < 1e-4,
        "moved at a limit of {lowered} m/s, not the 0.02 m/s the speed in force gives"
    );
    driver.shutdown().await;
}

#[tokio::test]
async fn a_go_to_turns_the_tool_no_faster_than_the_turn_rate_of_the_speed_in_force() {
    // At 20 % of a 250 mm/s cap: the tool at 50 mm/s, its turn at 20 % of 30 deg/s = 6 deg/s,
    // the rate an orientation jog turns at. The arm's own limits are its hard ones (0.5 m/s,
    // 100 deg/s): the move lowers both, and a 120 degree turn runs at 6 deg/s, not 100.
    let sim = Simulator::start(SimConfig::ephemeral())
        .await
        .expect("simulator");
    let modbus = ModbusConfig::new(sim.modbus_addr.expect("modbus").to_string());
    let mut config = DriverConfig::new(None, Some(modbus));
    config.max_jog_speed = 0.25;
    let (driver, mut events) = Driver::spawn(config);
    link_up(&mut events).await;
    assert!(driver.send(ArmCommand::SetSpeed(20)));
    until_event(&mut events, is_speed).await;
    let (telemetry, _) = until_event(&mut events, |e| matches!(e, ArmEvent::Telemetry(_))).await;
    let ArmEvent::Telemetry(telemetry) = telemetry else {
        unreachable!()
    };
    // A turn about the tool's own axis (the home pose's theta y), the point kept.
    let mut target = telemetry.tcp.pose;
    target.theta_y -= 120.0;
    assert!(driver.send(ArmCommand::MoveToPose(target)));

    let lowered = async {
        loop {
            let s = sim.arm.snapshot().await.expect("sim alive");
            if s.speed_limit_linear < 0.49 {
                return;
            }
            tokio::time::sleep(Duration::from_millis(2)).await;
        }
    };
    tokio::time::timeout(Duration::from_secs(10), lowered)
        .await
        .expect("the move lowered the limits within 10 s");
    // 216-219, CDAB: 0.05 = 0x3D4CCCCD, 6.0 = 0x40C00000.
    let (written, in_force) = limits(&sim).await;
    assert_eq!(written, [0xCCCD, 0x3D4C, 0x0000, 0x40C0]);
    assert!(
        (in_force.0 - 0.05).abs() < 1e-6 && (in_force.1 - 6.0).abs() < 1e-4,
        "{in_force:?}"
    );

    // Measured on the simulated arm over 2 s of the turn.
    let mut fastest = 0.0f64;
    let until = tokio::time::Instant::now() + Duration::from_secs(2);
    while tokio::time::Instant::now() < until {
        let s = sim.arm.snapshot().await.expect("sim alive");
        let w = s.tcp_angular_velocity;
        fastest = fastest.max((w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt());
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    assert!(fastest > 3.0, "the tool did not turn: {fastest:.1} deg/s");
    assert!(
        fastest <= 6.0 * 1.05,
        "the tool turned at {fastest:.1} deg/s, over the 6 deg/s of the speed in force"
    );
    driver.shutdown().await;
}
