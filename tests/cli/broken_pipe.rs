//! Every printing command ends quietly when its reader goes away (`armjog status | head -c 10`):
//! no panic message, no "101" exit. Runs the real binary against an in-test simulator, with
//! stdout a pipe closed before the output (one-shot commands) or after a few bytes (`--watch`).

use std::process::Stdio;
use std::time::Duration;

use tokio::io::AsyncReadExt;
use tokio::process::{Child, Command};

use armjog::sim::{SimConfig, Simulator};

/// Rust's exit status for a panic in `main`.
const PANICKED: i32 = 101;

async fn sim() -> Simulator {
    Simulator::start(SimConfig::ephemeral())
        .await
        .expect("simulator starts")
}

fn modbus_addr(sim: &Simulator) -> String {
    sim.modbus_addr.expect("the Modbus server runs").to_string()
}

fn spawn(args: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_armjog"))
        .args(args)
        .env(
            "ARMJOG_LOG_DIR",
            std::env::temp_dir().join("armjog-test-logs"),
        )
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .kill_on_drop(true)
        .spawn()
        .expect("spawn armjog")
}

/// Waits (generously) for the child to end; asserts it neither panicked nor hung.
async fn assert_ends_quietly(mut child: Child, what: &str) {
    let mut stderr = child.stderr.take().expect("stderr piped");
    let status = tokio::time::timeout(Duration::from_secs(10), child.wait())
        .await
        .unwrap_or_else(|_| panic!("{what}: still running 10 s after its reader went away"))
        .expect("wait for armjog");
    let mut err = String::new();
    stderr.read_to_string(&mut err).await.expect("read stderr");
    assert!(!err.contains("panicked"), "{what}: panicked: {err}");
    assert!(!err.contains("backtrace"), "{what}: backtrace: {err}");
    assert_ne!(status.code(), Some(PANICKED), "{what}: exit 101; {err}");
    // 0, or 141 for a SIGPIPE-style end; any other status means a failure was reported.
    assert!(
        matches!(status.code(), Some(0) | Some(141)) || status.code().is_none(),
        "{what}: exit {status}; {err}"
    );
}

/// Runs a one-shot command whose stdout reader is gone before it prints anything.
async fn run_with_stdout_closed(args: &[&str], what: &str) {
    let mut child = spawn(args);
    drop(child.stdout.take());
    assert_ends_quietly(child, what).await;
}

#[tokio::test]
async fn status_ends_quietly_when_its_reader_is_gone() {
    let sim = sim().await;
    let addr = modbus_addr(&sim);
    run_with_stdout_closed(&["status", "--modbus", &addr], "status").await;
    run_with_stdout_closed(&["status", "--modbus", &addr, "--json"], "status --json").await;
}

#[tokio::test]
async fn status_watch_ends_quietly_when_its_reader_leaves_after_a_few_bytes() {
    let sim = sim().await;
    let addr = modbus_addr(&sim);
    for json in [false, true] {
        let mut args = vec!["status", "--modbus", &addr, "--watch", "50"];
        if json {
            args.push("--json");
        }
        let what = format!("status --watch (json {json})");
        let mut child = spawn(&args);
        let mut stdout = child.stdout.take().expect("stdout piped");
        // `head -c 10`: read ten bytes, then go away.
        let mut first = [0u8; 10];
        tokio::time::timeout(Duration::from_secs(10), stdout.read_exact(&mut first))
            .await
            .unwrap_or_else(|_| panic!("{what}: printed nothing within 10 s"))
            .unwrap_or_else(|e| panic!("{what}: {e}"));
        drop(stdout);
        assert_ends_quietly(child, &what).await;
    }
}

#[tokio::test]
async fn send_ends_quietly_when_its_reader_is_gone() {
    let sim = sim().await;
    let addr = sim.talos_addr.to_string();
    run_with_stdout_closed(&["send", "--talos", &addr, "handshake"], "send handshake").await;
    run_with_stdout_closed(
        &["send", "--talos", &addr, "--json", "get-speed"],
        "send --json get-speed",
    )
    .await;
}

#[tokio::test]
async fn modbus_ends_quietly_when_its_reader_is_gone() {
    let sim = sim().await;
    let addr = modbus_addr(&sim);
    run_with_stdout_closed(&["modbus", "--modbus", &addr, "abort"], "modbus abort").await;
    run_with_stdout_closed(
        &["modbus", "--modbus", &addr, "--json", "fault-reset"],
        "modbus --json fault-reset",
    )
    .await;
}

#[tokio::test]
async fn sim_keeps_serving_with_its_banner_unread_and_stops_quietly() {
    let mut child = spawn(&[
        "sim",
        "--talos-listen",
        "127.0.0.1:0",
        "--modbus-listen",
        "127.0.0.1:0",
    ]);
    drop(child.stdout.take());
    // The banner went nowhere; the simulator must still be running, then stop on SIGTERM.
    tokio::time::sleep(Duration::from_millis(300)).await;
    assert!(
        child.try_wait().expect("poll armjog sim").is_none(),
        "sim ended when its banner could not be printed"
    );
    let pid = child.id().expect("sim is running").to_string();
    let killed = Command::new("kill")
        .args(["-TERM", &pid])
        .status()
        .await
        .expect("run kill");
    assert!(killed.success(), "kill -TERM {pid}");
    assert_ends_quietly(child, "sim").await;
}

/// The console's own errors go to a stderr that cannot be written (a terminal that hung up:
/// an SSH session that dropped): its exit status is still its own, not a panic's.
#[tokio::test]
async fn the_console_reports_its_errors_quietly_when_stderr_is_gone() {
    let cases: [(&[&str], i32); 2] = [
        (&["--keymap", "/nonexistent/armjog-keymap.json"], 2),
        (&["--telemetry-hz", "0"], 2),
    ];
    for (args, expected) in cases {
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .expect("/dev/full");
        let status = Command::new(env!("CARGO_BIN_EXE_armjog"))
            .args(args)
            .env(
                "ARMJOG_LOG_DIR",
                std::env::temp_dir().join("armjog-test-logs"),
            )
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(full)
            .kill_on_drop(true)
            .status();
        let status = tokio::time::timeout(Duration::from_secs(10), status)
            .await
            .unwrap_or_else(|_| panic!("{args:?}: still running after 10 s"))
            .expect("run armjog");
        assert_eq!(status.code(), Some(expected), "{args:?}: {status}");
    }
}
