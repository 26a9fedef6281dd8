//! `armjog send` end to end: the binary against a scripted operator on loopback.

use crate::common;

use std::sync::Arc;
use std::time::Duration;

use crate::armjog_run::armjog;
use armjog::talos::{Checksum, Reply, Request, ReturnCode, TalosFrame};
use common::{Action, TestOperator, reply_bytes};
use serde_json::Value;

/// A typed reply with recognisable field values for every request.
fn canned_reply(request: &Request) -> Reply {
    let ok = ReturnCode::OK;
    match request {
        Request::Handshake { .. } => Reply::Handshake {
            return_code: ok,
            major_version: 1,
            minor_version: 2,
        },
        Request::GetSpeed => Reply::GetSpeed {
            return_code: ok,
            speed: 42,
        },
        Request::GetPolarPosition { .. } => Reply::GetPolarPosition {
            return_code: ok,
            delta: -15,
            azimuth: 900,
            radius: 1234,
        },
        Request::GetCartesianPosition { name } if name == "missing" => {
            Reply::error(request.command(), ReturnCode::UNKNOWN_POSITION)
        }
        Request::GetCartesianPosition { .. } => Reply::GetCartesianPosition {
            return_code: ok,
            x: 4566,
            y: -10,
            z: 4338,
        },
        Request::HardwareOperation { subcommand, .. } => Reply::HardwareOperation {
            return_code: ok,
            subcommand: *subcommand,
            payload: vec![0xAB, 0xCD],
        },
        Request::GoToPosition { name } if name == "missing" => {
            Reply::error(request.command(), ReturnCode::UNKNOWN_POSITION)
        }
        other => Reply::error(other.command(), ok),
    }
}

async fn operator(checksum: Checksum) -> TestOperator {
    let script: common::Script = Arc::new(move |f: &TalosFrame| {
        let request = Request::from_frame(f).expect("the CLI sent a valid request");
        vec![Action::Write(reply_bytes(
            &canned_reply(&request),
            f.id,
            checksum,
        ))]
    });
    TestOperator::start(checksum, script).await
}

/// Runs `armjog send --talos ADDR --json <args>` and returns the JSON and the request the operator
/// decoded.
async fn send_json(args: &[&str]) -> (Value, Request) {
    let mut op = operator(Checksum::Crc16).await;
    let mut full = vec!["send", "--talos", &op.addr, "--json"];
    full.extend_from_slice(args);
    let run = armjog(&full).await;
    assert_eq!(run.code, 0, "{args:?}: stderr {}", run.stderr);
    let json: Value = serde_json::from_str(run.stdout.trim()).expect("one JSON object");
    let frame = op.next_frame().await;
    (json, Request::from_frame(&frame).expect("request"))
}

#[tokio::test(flavor = "multi_thread")]
async fn every_command_reaches_the_operator_as_typed() {
    let name = |s: &str| s.to_string();
    let cases: Vec<(Vec<&str>, Request)> = vec![
        (
            vec!["handshake", "--oid", "7"],
            Request::Handshake { oid: Some(7) },
        ),
        (
            vec![
                "polar-pan",
                "--azimuth",
                "-10",
                "--altitude",
                "5",
                "--delay",
                "100",
                "--time",
                "2000",
            ],
            Request::PolarPan {
                delta_azimuth: -10,
                delta_altitude: 5,
                delay_ms: 100,
                time_ms: 2000,
            },
        ),
        (
            vec!["home", "--delay", "250"],
            Request::Home { delay_ms: 250 },
        ),
        (
            vec!["polar-start", "--azimuth", "1", "--altitude", "-1"],
            Request::PolarPanStart {
                moving_azimuth: 1,
                moving_altitude: -1,
            },
        ),
        (vec!["polar-stop"], Request::PolarPanStop),
        (
            vec!["cart-move", "--x", "100", "--y", "-200", "--z", "0"],
            Request::CartesianMove {
                delta_x: 100,
                delta_y: -200,
                delta_z: 0,
                delay_ms: 0,
                time_ms: 0,
            },
        ),
        (
            vec!["cart-start", "--x", "0", "--y", "1", "--z", "-1"],
            Request::CartesianMoveStart {
                moving_x: 0,
                moving_y: 1,
                moving_z: -1,
            },
        ),
        (vec!["cart-stop"], Request::CartesianMoveStop),
        (
            vec!["hw-op", "--sub", "1", "--payload", "00"],
            Request::HardwareOperation {
                subcommand: 1,
                reserved: 0,
                payload: vec![0],
            },
        ),
        (vec!["get-speed"], Request::GetSpeed),
        (vec!["set-speed", "55"], Request::SetSpeed { speed: 55 }),
        (
            vec!["save", "pick", "--anchor", "--parent", "table"],
            Request::SavePosition {
                name: name("pick"),
                anchor: true,
                parent: name("table"),
            },
        ),
        (
            vec!["save", "pick"],
            Request::SavePosition {
                name: name("pick"),
                anchor: false,
                parent: String::new(),
            },
        ),
        (
            vec!["delete", "pick"],
            Request::DeletePosition { name: name("pick") },
        ),
        (
            vec!["goto", "pick"],
            Request::GoToPosition { name: name("pick") },
        ),
        (
            vec![
                "set-polar",
                "pick",
                "--delta",
                "-5",
                "--azimuth",
                "900",
                "--radius",
                "30",
            ],
            Request::SetPolarPosition {
                name: name("pick"),
                delta: -5,
                azimuth: 900,
                radius: 30,
            },
        ),
        (
            vec!["get-polar", "pick"],
            Request::GetPolarPosition { name: name("pick") },
        ),
        (
            vec![
                "set-cart", "pick", "--x", "4566", "--y", "-1", "--z", "4338",
            ],
            Request::SetCartesianPosition {
                name: name("pick"),
                x: 4566,
                y: -1,
                z: 4338,
            },
        ),
        (
            vec!["get-cart", "pick"],
            Request::GetCartesianPosition { name: name("pick") },
        ),
    ];
    for (args, expected) in cases {
        let (json, sent) = send_json(&args).await;
        assert_eq!(sent, expected, "{args:?}");
        assert_eq!(json["command"], expected.command().name(), "{args:?}");
        assert_eq!(json["id"], 0, "{args:?}");
        assert_eq!(json["return_code"], 0, "{args:?}");
    }
}

#[tokio::test(flavor = "multi_thread")]
async fn reply_fields_are_printed_with_the_icds_names() {
    let (json, _) = send_json(&["handshake"]).await;
    assert_eq!(
        (
            json["major_version"].as_u64(),
            json["minor_version"].as_u64()
        ),
        (Some(1), Some(2))
    );
    let (json, _) = send_json(&["get-speed"]).await;
    assert_eq!(json["speed"], 42);
    let (json, _) = send_json(&["get-polar", "p"]).await;
    assert_eq!(
        (
            json["delta"].as_i64(),
            json["azimuth"].as_i64(),
            json["radius"].as_i64()
        ),
        (Some(-15), Some(900), Some(1234))
    );
    let (json, _) = send_json(&["get-cart", "p"]).await;
    assert_eq!(
        (json["x"].as_i64(), json["y"].as_i64(), json["z"].as_i64()),
        (Some(4566), Some(-10), Some(4338))
    );
    let (json, _) = send_json(&["hw-op", "--sub", "3"]).await;
    assert_eq!(
        (json["subcommand"].as_u64(), json["payload"].as_str()),
        (Some(3), Some("ABCD"))
    );
}

#[tokio::test(flavor = "multi_thread")]
async fn the_default_output_is_one_readable_line_and_hex_adds_both_frames() {
    let op = operator(Checksum::Xor8).await;
    let run = armjog(&[
        "send",
        "--talos",
        &op.addr,
        "--checksum",
        "xor8",
        "--hex",
        "get-speed",
    ])
    .await;
    assert_eq!(run.code, 0, "{}", run.stderr);
    let lines: Vec<&str> = run.stdout.lines().collect();
    assert!(
        lines[0].starts_with("get_speed (id 0): 0x0000 OK speed=42"),
        "{}",
        lines[0]
    );
    // Get Speed, id 0, no payload; XOR of the header is 0x09.
    assert_eq!(lines[1], "sent     00 00 00 00 00 00 00 09 00 00 09");
    // Reply id 1, value 0x8009, length 3, return code 0, speed 42 (0x2A):
    // XOR = 0x01 ^ 0x80 ^ 0x09 ^ 0x03 ^ 0x2A = 0xA1.
    assert_eq!(
        lines[2],
        "received 00 00 00 01 00 00 80 09 00 03 00 00 2A A1"
    );
}

#[tokio::test(flavor = "multi_thread")]
async fn a_hardware_reply_is_decoded_by_the_companion_icd() {
    use armjog::sim::{SimConfig, Simulator};
    let sim = Simulator::start(SimConfig::ephemeral()).await.unwrap();
    let addr = sim.talos_addr.to_string();
    let run = armjog(&["send", "--talos", &addr, "--json", "hw-op", "--sub", "3"]).await;
    assert_eq!(run.code, 0, "{}", run.stderr);
    let json: Value = serde_json::from_str(run.stdout.trim()).unwrap();
    let state = &json["decoded"]["GetArmState"]["state"];
    let x = state["tcp_position_m"][0].as_f64().unwrap_or(0.0);
    assert!((x - 0.4566).abs() < 1e-3, "{json}");
}

#[tokio::test(flavor = "multi_thread")]
async fn a_hardware_reply_as_text_is_formatted_with_units() {
    use armjog::sim::{SimConfig, Simulator};
    let sim = Simulator::start(SimConfig::ephemeral()).await.unwrap();
    let addr = sim.talos_addr.to_string();
    let run = armjog(&["send", "--talos", &addr, "hw-op", "--sub", "3"]).await;
    assert_eq!(run.code, 0, "{}", run.stderr);
    let out = &run.stdout;
    let first = out.lines().next().unwrap_or_default();
    assert!(
        first.starts_with("hw_op (id 0): 0x0000 OK subcommand=3 ["),
        "{out}"
    );
    assert!(
        !out.contains('{') && !out.contains("payload="),
        "no raw JSON or hex: {out}"
    );
    assert!(out.contains("  robot state   ready"), "{out}");
    assert!(
        out.contains("  tcp pose      x 456.6 mm   y 1.0 mm   z 433.8 mm"),
        "{out}"
    );
    assert!(out.contains("tcp twist     x 0.0 mm/s"), "{out}");
    // No float printed with more than three decimals.
    let long_decimals = out
        .split(|c: char| !(c.is_ascii_digit() || c == '.'))
        .any(|n| {
            n.split_once('.')
                .is_some_and(|(_, decimals)| decimals.len() > 3)
        });
    assert!(!long_decimals, "{out}");

    let run = armjog(&[
        "send",
        "--talos",
        &addr,
        "hw-op",
        "--sub",
        "1",
        "--payload",
        "00",
    ])
    .await;
    assert_eq!(run.code, 0, "{}", run.stderr);
    let rows: Vec<&str> = run.stdout.lines().skip(2).take(7).collect();
    assert_eq!(rows.len(), 7, "{}", run.stdout);
    assert!(
        rows[1].trim_start().starts_with("2        15.000"),
        "{}",
        run.stdout
    );
}

#[tokio::test(flavor = "multi_thread")]
async fn an_error_return_code_exits_non_zero_with_a_reason() {
    let op = operator(Checksum::Crc16).await;
    let run = armjog(&["send", "--talos", &op.addr, "--json", "goto", "missing"]).await;
    assert_eq!(run.code, 1);
    let json: Value = serde_json::from_str(run.stdout.trim()).unwrap();
    assert_eq!(json["return_code"], 4);
    assert_eq!(json["return_code_name"], "UNKNOWN_POSITION");
    assert_eq!(run.stderr.lines().count(), 1, "{}", run.stderr);
    assert!(run.stderr.contains("UNKNOWN_POSITION"), "{}", run.stderr);
}

#[tokio::test(flavor = "multi_thread")]
async fn a_failed_reply_as_text_shows_its_status_and_no_fields() {
    let op = operator(Checksum::Crc16).await;
    let run = armjog(&["send", "--talos", &op.addr, "get-cart", "missing"]).await;
    assert_eq!(run.code, 1, "{}", run.stderr);
    let line = run.stdout.trim_end();
    assert_eq!(run.stdout.lines().count(), 1, "{}", run.stdout);
    assert!(
        line.starts_with("get_cart (id 0): 0x0004 UNKNOWN_POSITION ["),
        "{line}"
    );
    assert!(line.ends_with(" ms]"), "{line}");
    assert!(!line.contains('='), "no zero fields: {line}");
    // A successful reply of the same command still shows its fields.
    let run = armjog(&["send", "--talos", &op.addr, "get-cart", "pick"]).await;
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(
        run.stdout.contains("OK x=4566 y=-10 z=4338 ["),
        "{}",
        run.stdout
    );
}

#[tokio::test(flavor = "multi_thread")]
async fn bad_arguments_are_refused_before_anything_is_sent() {
    let mut op = operator(Checksum::Crc16).await;
    for args in [
        vec!["set-speed", "256"],
        vec!["polar-start", "--azimuth", "2", "--altitude", "0"],
        vec!["cart-move", "--x", "2147483648", "--y", "0", "--z", "0"],
        vec!["home", "--delay", "-1"],
        vec!["goto", ""],
        vec!["save", "bad\tname"],
        vec!["hw-op", "--sub", "1", "--payload", "0G"],
    ] {
        let mut full = vec!["send", "--talos", &op.addr];
        full.extend_from_slice(&args);
        let run = armjog(&full).await;
        assert_eq!(
            run.code, 2,
            "{args:?} must be a usage error: {}",
            run.stderr
        );
        assert!(
            run.stderr.contains("invalid value"),
            "{args:?}: {}",
            run.stderr
        );
    }
    assert!(
        tokio::time::timeout(Duration::from_millis(100), op.received.recv())
            .await
            .is_err(),
        "nothing may reach the operator"
    );
}

#[tokio::test(flavor = "multi_thread")]
async fn link_failures_exit_3_with_one_line() {
    let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = listener.local_addr().unwrap().to_string();
    drop(listener);
    let run = armjog(&["send", "--talos", &addr, "get-speed"]).await;
    assert_eq!(run.code, 3);
    assert!(run.stderr.contains("refused"), "{}", run.stderr);

    let op = operator(Checksum::Crc16).await;
    let run = armjog(&["send", "--talos", &op.addr, "--dialect", "ack", "get-speed"]).await;
    assert_eq!(run.code, 3);
    assert!(run.stderr.contains("ack dialect"), "{}", run.stderr);
}

#[tokio::test(flavor = "multi_thread")]
async fn ack_dialect_prints_the_acknowledgement() {
    let script: common::Script = Arc::new(|_: &TalosFrame| vec![Action::Write(b"ACK\0".to_vec())]);
    let mut op = TestOperator::start(Checksum::Xor8, script).await;
    let run = armjog(&[
        "send",
        "--talos",
        &op.addr,
        "--dialect",
        "ack",
        "--checksum",
        "xor8",
        "--json",
        "polar-start",
        "--azimuth",
        "-1",
        "--altitude",
        "0",
    ])
    .await;
    assert_eq!(run.code, 0, "{}", run.stderr);
    let json: Value = serde_json::from_str(run.stdout.trim()).unwrap();
    assert_eq!(json["ack"], true);
    assert_eq!(json["command"], "polar_start");
    let frame = op.next_frame().await;
    assert_eq!(frame.payload, [0xFF, 0x00]);
}
