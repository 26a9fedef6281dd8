//! `armjog status` and `armjog modbus` end to end: the binary against the fake arm on loopback.

use crate::armjog_run::{armjog, command};
use crate::modbus_fake;

use std::process::Stdio;
use std::time::Duration;

use modbus_fake::{Behaviour, FakeArm, Written, fill_known_telemetry};
use serde_json::Value;
use tokio::io::{AsyncBufReadExt, BufReader};
use tokio_modbus::{ExceptionCode, Request};

async fn known_arm() -> FakeArm {
    let arm = FakeArm::start().await;
    arm.with(fill_known_telemetry);
    arm
}

#[tokio::test]
async fn status_prints_a_readable_table() {
    let arm = known_arm().await;
    let run = armjog(&["status", "--modbus", &arm.addr()]).await;
    assert_eq!(run.code, 0, "{}", run.stderr);
    let out = &run.stdout;
    assert!(out.contains("robot state   ready (7)"), "{out}");
    assert!(
        out.contains("emergency_stop (Emergency stop activated)"),
        "{out}"
    );
    assert!(
        out.contains("warnings      maximum_ambient_temperature"),
        "{out}"
    );
    assert!(out.contains("voltage 24.000 V"), "{out}");
    assert!(out.contains("action        completed (1)   id 2   move type twist (3)"));
    assert!(out.contains("x 456.6 mm   y 1.0 mm   z 433.8 mm"), "{out}");
    // Speeds below 1 m/s in mm/s.
    assert!(
        out.contains("tcp twist     x 250.0 mm/s   y -500.0 mm/s   z 125.0 mm/s"),
        "{out}"
    );
    assert!(out.contains("speed limits  linear 500.0 mm/s"), "{out}");
    // Holding register 0 has no meaning the ICD gives: not shown.
    assert!(!out.contains("holding reg"), "{out}");
    assert!(!out.contains("-0.0"), "no negative zero: {out}");
    // Seven joint rows: joint 7's temperature is 56.0.
    let joint7 = out
        .lines()
        .find(|l| l.trim_start().starts_with("7 "))
        .unwrap();
    assert!(joint7.trim_end().ends_with("56.0"), "{joint7}");
    assert!(arm.writes().is_empty(), "status never writes");
}

#[tokio::test]
async fn status_json_has_the_documented_keys_and_values() {
    let arm = known_arm().await;
    let run = armjog(&["status", "--modbus", &arm.addr(), "--json"]).await;
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(run.stdout.lines().count(), 1);
    let v: Value = serde_json::from_str(&run.stdout).unwrap();
    assert_eq!(v["robot_state"], "ready");
    assert_eq!(
        v["faults"],
        serde_json::json!(["firmware_update_failure", "joint_fault", "emergency_stop"])
    );
    assert_eq!(v["arm"]["voltage"], 24.0);
    assert_eq!(v["joints"][6]["temperature"], 56.0);
    assert_eq!(v["tcp"]["twist"]["y"], -0.5);
    assert_eq!(v["tcp"]["wrench"]["torque_z"], 12.0);
    assert_eq!(v["action"]["move_type"], "twist");
    assert_eq!(v["speed_limits"]["linear"], 0.5);
    assert!(run.stdout.contains(r#""x":0.4566"#), "{}", run.stdout);
}

#[tokio::test]
async fn status_uses_the_unit_id() {
    let arm = known_arm().await;
    let run = armjog(&["status", "--modbus", &arm.addr(), "--unit", "9", "--json"]).await;
    assert_eq!(run.code, 0, "{}", run.stderr);
    let units: Vec<u8> = arm.with(|s| s.log.iter().map(|l| l.unit).collect());
    assert!(
        !units.is_empty() && units.iter().all(|u| *u == 9),
        "{units:?}"
    );
}

#[tokio::test]
async fn status_watch_keeps_printing() {
    let arm = known_arm().await;
    let mut child = command(&["status", "--modbus", &arm.addr(), "--json", "--watch", "20"])
        .stdout(Stdio::piped())
        .kill_on_drop(true)
        .spawn()
        .unwrap();
    let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
    for _ in 0..3 {
        let line = tokio::time::timeout(Duration::from_secs(5), lines.next_line())
            .await
            .unwrap()
            .unwrap()
            .unwrap();
        let v: Value = serde_json::from_str(&line).unwrap();
        assert_eq!(v["robot_state"], "ready");
        let time = v["time"].as_str().expect("a time field");
        assert!(is_rfc3339_utc(time), "{time}");
    }
    child.kill().await.unwrap();
}

/// `2026-11-30T22:54:05.942Z`: RFC 3339, UTC, milliseconds.
fn is_rfc3339_utc(text: &str) -> bool {
    let b = text.as_bytes();
    let digits = |range: std::ops::Range<usize>| b[range].iter().all(u8::is_ascii_digit);
    b.len() == 24
        && digits(0..4)
        && b[4] == b'-'
        && digits(5..7)
        && b[7] == b'-'
        && digits(8..10)
        && b[10] == b'T'
        && digits(11..13)
        && b[13] == b':'
        && digits(14..16)
        && b[16] == b':'
        && digits(17..19)
        && b[19] == b'.'
        && digits(20..23)
        && b[23] == b'Z'
}

#[tokio::test]
async fn every_status_watch_line_starts_with_its_time() {
    let arm = known_arm().await;
    let mut child = command(&["status", "--modbus", &arm.addr(), "--watch", "20"])
        .stdout(Stdio::piped())
        .kill_on_drop(true)
        .spawn()
        .unwrap();
    let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
    let mut tables = 0;
    let mut times = Vec::new();
    while tables < 2 {
        let line = tokio::time::timeout(Duration::from_secs(5), lines.next_line())
            .await
            .unwrap()
            .unwrap()
            .unwrap();
        if line.is_empty() {
            // The blank line between tables.
            tables += 1;
            continue;
        }
        let (time, rest) = line.split_at_checked(24).expect("a time first");
        assert!(is_rfc3339_utc(time), "{line}");
        assert!(rest.starts_with("  "), "{line}");
        times.push(time.to_string());
        if rest.trim_start().starts_with("robot state") {
            assert_eq!(rest, "  robot state   ready (7)");
        }
    }
    assert!(times.windows(2).all(|w| w[0] <= w[1]), "{times:?}");
    child.kill().await.unwrap();
}

#[tokio::test]
async fn status_exit_codes() {
    let arm = known_arm().await;
    // Nobody listening: a link failure.
    let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let closed = listener.local_addr().unwrap().to_string();
    drop(listener);
    let run = armjog(&["status", "--modbus", &closed]).await;
    assert_eq!(run.code, 3, "{}", run.stderr);
    assert!(run.stderr.contains("refused"), "{}", run.stderr);
    // Bad arguments.
    let run = armjog(&["status", "--modbus", &arm.addr(), "--unit", "300"]).await;
    assert_eq!(run.code, 2);
    let run = armjog(&["status", "--modbus", &arm.addr(), "--watch", "0"]).await;
    assert_eq!(run.code, 2);
    // An exception answer.
    arm.rule(|r| match r {
        Request::ReadInputRegisters(..) => {
            Some(Behaviour::Exception(ExceptionCode::GatewayTargetDevice))
        }
        _ => None,
    });
    let run = armjog(&["status", "--modbus", &arm.addr()]).await;
    assert_eq!(run.code, 1, "{}", run.stderr);
    assert!(
        run.stderr
            .contains("gateway target device failed to respond (0x0B)"),
        "{}",
        run.stderr
    );
    // No reply at all.
    arm.clear_rules();
    arm.rule(|_| Some(Behaviour::Stall(Duration::from_secs(3))));
    let run = armjog(&["status", "--modbus", &arm.addr(), "--timeout", "100"]).await;
    assert_eq!(run.code, 3, "{}", run.stderr);
    assert!(
        run.stderr.contains("no reply within 100ms"),
        "{}",
        run.stderr
    );
}

#[tokio::test]
async fn modbus_commands_write_their_sequences() {
    let arm = FakeArm::start().await;
    // A start is capped at 250 mm/s and 30 deg/s: limits already there need no write.
    arm.with(|s| {
        s.set_holding_f32(104, 0.25);
        s.set_holding_f32(106, 30.0);
    });
    let addr = arm.addr();
    for args in [
        vec!["quick-stop"],
        vec!["abort"],
        vec!["fault-reset"],
        vec!["stop"],
        // The fake arm never runs actions: do not wait for their end.
        vec!["home", "--no-wait"],
        vec!["home", "--action-id", "5", "--no-wait"],
        vec!["speed-limit", "--linear", "0.25", "--angular", "50"],
    ] {
        let mut full = vec!["modbus", "--modbus", addr.as_str()];
        full.extend(args.iter());
        let run = armjog(&full).await;
        assert_eq!(run.code, 0, "{args:?}: {}", run.stderr);
    }
    assert_eq!(
        arm.writes(),
        vec![
            Written::Coil(0, true),
            Written::Coil(0, false),
            Written::Coil(1, true),
            Written::Coil(1, false),
            Written::Coil(2, true),
            Written::Coil(2, false),
            Written::Registers(200, vec![2]),
            Written::Registers(200, vec![0]),
            Written::Registers(201, vec![2, 0]),
            Written::Registers(200, vec![1]),
            Written::Registers(200, vec![0]),
            Written::Registers(201, vec![5, 0]),
            Written::Registers(200, vec![1]),
            Written::Registers(216, vec![0x0000, 0x3E80, 0x0000, 0x4248]),
        ]
    );
}

#[tokio::test]
async fn modbus_json_output_and_refusals() {
    let arm = FakeArm::start().await;
    let run = armjog(&["modbus", "--modbus", &arm.addr(), "--json", "quick-stop"]).await;
    assert_eq!(run.code, 0, "{}", run.stderr);
    let v: Value = serde_json::from_str(&run.stdout).unwrap();
    assert_eq!(v["command"], "quick_stop");
    assert_eq!(
        v["writes"],
        serde_json::json!([
            {"function_code": 5, "address": 0, "value": true},
            {"function_code": 5, "address": 0, "value": false}
        ])
    );
    let before = arm.with(|s| s.log.len());
    for (linear, angular) in [("0.6", "50"), ("0", "50"), ("nan", "50"), ("0.1", "101")] {
        let run = armjog(&[
            "modbus",
            "--modbus",
            &arm.addr(),
            "speed-limit",
            "--linear",
            linear,
            "--angular",
            angular,
        ])
        .await;
        assert_eq!(run.code, 2, "{linear} {angular}: {}", run.stderr);
        assert!(run.stderr.contains("refused before anything was sent"));
    }
    assert_eq!(arm.with(|s| s.log.len()), before, "nothing reached the arm");
    assert_eq!(
        arm.with(|s| s.connections),
        1,
        "no connection was even made"
    );
    arm.rule(|r| match r {
        Request::WriteSingleCoil(2, _) => {
            Some(Behaviour::Exception(ExceptionCode::IllegalDataAddress))
        }
        _ => None,
    });
    let run = armjog(&["modbus", "--modbus", &arm.addr(), "fault-reset"]).await;
    assert_eq!(run.code, 1);
    assert!(
        run.stderr.contains("illegal data address"),
        "{}",
        run.stderr
    );
}

/// Polls the fake arm until `done` holds; panics after 10 s.
async fn fake_until(arm: &FakeArm, what: &str, done: impl Fn(&modbus_fake::ArmState) -> bool) {
    let until = std::time::Instant::now() + Duration::from_secs(10);
    while !arm.with(|s| done(s)) {
        assert!(std::time::Instant::now() < until, "not within 10 s: {what}");
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
}

/// The simulator's home is a joint-space move that never passes a limit, so an arm whose home
/// stops at a joint limit is played by the fake: it takes the home, reports it started and
/// moving, then aborted with J4 at its limit and a joint-fault warning.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn home_aborted_at_a_joint_limit_names_the_joint_and_exits_1() {
    let arm = FakeArm::start().await;
    arm.with(|s| {
        s.input_registers[0] = 7; // ready
        for (j, deg) in [0.0, 15.0, 180.0, 230.0, 0.0, 55.0, 90.0]
            .iter()
            .enumerate()
        {
            s.set_input_f32(34 + 2 * j, *deg);
        }
        s.holding_registers[100] = 1; // an earlier action completed
        // Limits the capped home can lower for its run.
        s.set_holding_f32(104, 0.5);
        s.set_holding_f32(106, 100.0);
    });
    let home = command(&["modbus", "--modbus", &arm.addr(), "home"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .kill_on_drop(true)
        .spawn()
        .expect("spawn armjog modbus home");
    let start = Written::Registers(200, vec![1]);
    fake_until(&arm, "home started", |s| s.writes().contains(&start)).await;
    let reads_before = arm.with(|s| {
        s.holding_registers[100] = 0; // started
        s.holding_registers[101] = 2; // the home action
        s.set_input_f32(48 + 2 * 3, -20.0); // J4 turning
        s.reads().len()
    });
    // Once the waiting command has read the action status as started, the arm stops at the
    // limit.
    fake_until(&arm, "action status read while started", |s| {
        s.reads()[reads_before..]
            .iter()
            .any(|&(fc, at, n)| fc == 3 && at <= 100 && 100 < at + n)
    })
    .await;
    arm.with(|s| {
        s.set_input_f32(34 + 2 * 3, 147.8);
        s.set_input_f32(48 + 2 * 3, 0.0);
        s.input_registers[4] = 1 << 4; // warning: joint_fault
        s.holding_registers[100] = 3; // aborted
    });
    let out = tokio::time::timeout(Duration::from_secs(20), home.wait_with_output())
        .await
        .expect("armjog modbus home returns after the abort")
        .expect("armjog modbus home output");
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert_eq!(out.status.code(), Some(1), "{stdout}{stderr}");
    assert!(
        stderr.contains("home failed: aborted, J4 at its limit"),
        "{stderr}"
    );
    assert!(!stderr.contains("at once"), "{stderr}");
    assert!(!stdout.contains("completed"), "{stdout}");
}

// ---- `armjog modbus home` waits for the action's end, against the simulator ----

mod home {
    use super::{armjog, command};
    use armjog::sim::arm_model::Arm;
    use armjog::sim::kinematics::to_radians;
    use armjog::sim::{SimConfig, Simulator};
    use std::process::Stdio;
    use std::time::{Duration, Instant};

    /// A simulated arm (Modbus only) away from home, or as given.
    async fn sim(arm: Arm) -> Simulator {
        let mut config = SimConfig::ephemeral();
        config.arm = arm;
        Simulator::start(config).await.expect("simulator")
    }

    fn away() -> Arm {
        Arm::at(to_radians(&[10.0, 30.0, 170.0, 240.0, 10.0, 40.0, 80.0]))
    }

    fn addr(sim: &Simulator) -> String {
        sim.modbus_addr.expect("modbus server").to_string()
    }

    #[tokio::test(flavor = "multi_thread", worker_threads = 2)]
    async fn home_on_a_healthy_arm_waits_for_the_end_and_exits_0() {
        let sim = sim(away()).await;
        let run = armjog(&["modbus", "--modbus", &addr(&sim), "home"]).await;
        assert_eq!(run.code, 0, "{}{}", run.stdout, run.stderr);
        assert!(run.stdout.contains("home: completed in"), "{}", run.stdout);
        let s = sim.arm.snapshot().await.expect("sim");
        assert!(!s.moving, "at rest when it says completed");
        let home = [0.0, 15.0, 180.0, 230.0, 0.0, 55.0, 90.0];
        for (j, (at, want)) in s.joint_position.iter().zip(home).enumerate() {
            // Reported 0-360: 360 is 0.
            let off = (at - want).rem_euclid(360.0);
            assert!(off.min(360.0 - off) < 0.1, "J{}: {at} vs {want}", j + 1);
        }
    }

    #[tokio::test(flavor = "multi_thread", worker_threads = 2)]
    async fn home_on_an_arm_in_fault_exits_1_and_starts_nothing() {
        let mut arm = away();
        arm.raise_fault(4);
        let sim = sim(arm).await;
        let before = sim.arm.snapshot().await.expect("sim").joint_position;
        let run = armjog(&["modbus", "--modbus", &addr(&sim), "home"]).await;
        assert_eq!(run.code, 1, "{}{}", run.stdout, run.stderr);
        assert!(
            run.stderr
                .contains("home failed: the arm is in fault: joint_fault"),
            "{}",
            run.stderr
        );
        tokio::time::sleep(Duration::from_millis(200)).await;
        let after = sim.arm.snapshot().await.expect("sim").joint_position;
        assert_eq!(before, after, "nothing moved");
    }

    #[tokio::test(flavor = "multi_thread", worker_threads = 2)]
    async fn home_with_an_action_id_the_arm_does_not_have_exits_1() {
        let sim = sim(away()).await;
        let run = armjog(&[
            "modbus",
            "--modbus",
            &addr(&sim),
            "home",
            "--action-id",
            "99",
        ])
        .await;
        assert_eq!(run.code, 1, "{}{}", run.stdout, run.stderr);
        assert!(run.stderr.contains("action 99"), "{}", run.stderr);
        assert!(!run.stdout.contains("completed"), "{}", run.stdout);
    }

    /// J1 170 degrees from home and the tool limited to 50 mm/s: the home takes over 20 s,
    /// time enough to abort it however slowly a second process starts.
    fn far_from_home() -> Arm {
        let mut arm = Arm::at(to_radians(&[170.0, 30.0, 170.0, 240.0, 10.0, 40.0, 80.0]));
        arm.set_speed_limits(0.05, 100.0).expect("valid limits");
        arm
    }

    #[tokio::test(flavor = "multi_thread", worker_threads = 2)]
    async fn home_aborted_by_another_client_while_waiting_exits_1() {
        let sim = sim(far_from_home()).await;
        let home = command(&["modbus", "--modbus", &addr(&sim), "home"])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .kill_on_drop(true)
            .spawn()
            .expect("spawn armjog modbus home");
        // Abort only once the home runs, from a second client, as a technician would.
        let until = Instant::now() + Duration::from_secs(10);
        while !sim.arm.snapshot().await.expect("sim").moving {
            assert!(Instant::now() < until, "the home never started");
            tokio::time::sleep(Duration::from_millis(20)).await;
        }
        // The home process must also have read the action running before the abort, or it
        // rightly takes an action that ends at once for one the arm does not have. On a loaded
        // machine its first poll can come late; the home still has well over 15 s to go.
        tokio::time::sleep(Duration::from_secs(2)).await;
        let abort = armjog(&["modbus", "--modbus", &addr(&sim), "abort"]).await;
        assert_eq!(abort.code, 0, "{}", abort.stderr);
        let out = tokio::time::timeout(Duration::from_secs(20), home.wait_with_output())
            .await
            .expect("armjog modbus home returns after the abort")
            .expect("armjog modbus home output");
        let (stdout, stderr) = (
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr),
        );
        assert_eq!(out.status.code(), Some(1), "{stdout}{stderr}");
        assert!(stderr.contains("home failed: aborted"), "{stderr}");
        // It had seen the home start: the abort is not mistaken for a missing action.
        assert!(!stderr.contains("at once"), "{stderr}");
        assert!(!stdout.contains("completed"), "{stdout}");
        let s = sim.arm.snapshot().await.expect("sim");
        assert!(!s.moving, "the abort stopped the arm");
        let j1 = s.joint_position[0];
        assert!(
            (1.0..=170.0).contains(&j1),
            "stopped short of home: J1 at {j1}"
        );
    }

    #[tokio::test(flavor = "multi_thread", worker_threads = 2)]
    async fn a_home_past_its_wait_timeout_is_stopped_and_exits_1() {
        let sim = sim(away()).await;
        let run = armjog(&[
            "modbus",
            "--modbus",
            &addr(&sim),
            "home",
            "--wait-timeout",
            "0.2",
        ])
        .await;
        assert_eq!(run.code, 1, "{}{}", run.stdout, run.stderr);
        assert!(
            run.stderr.contains("no end within 0.2 s; stopped"),
            "{}",
            run.stderr
        );
        assert!(!sim.arm.snapshot().await.expect("sim").moving, "stopped");
    }

    #[tokio::test(flavor = "multi_thread", worker_threads = 2)]
    async fn home_no_wait_returns_while_the_arm_still_moves() {
        let mut arm = away();
        arm.set_speed_limits(0.5, 30.0).expect("valid limits");
        let sim = sim(arm).await;
        let started = Instant::now();
        // Limits of 0.5 m/s and 30 deg/s keep a 500 mm/s cap and its turn rate: nothing needs
        // lowering.
        let run = armjog(&[
            "modbus",
            "--modbus",
            &addr(&sim),
            "home",
            "--no-wait",
            "--max-jog-speed",
            "500",
        ])
        .await;
        assert_eq!(run.code, 0, "{}{}", run.stdout, run.stderr);
        assert!(run.stdout.starts_with("home: started"), "{}", run.stdout);
        assert!(
            sim.arm.snapshot().await.expect("sim").moving,
            "returned before the end ({:?})",
            started.elapsed()
        );
    }
}
