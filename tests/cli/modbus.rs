//! `armjog status` and `armjog modbus` end to end: the binary against the fake arm on loopback.
//! `armjog modbus home` is in `modbus_home.rs`, its stored runs in `stored.rs`.

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
