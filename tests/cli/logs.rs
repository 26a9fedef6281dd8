//! Each program writes its own log files: `armjog sim` to `armjog-sim.DATE.log`, a one-shot
//! `send` to `armjog-cli.DATE.log` with its exchange (both frames in hex, the answer, the round
//! trip).

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use crate::log_files::{is_daily_log, read_existing_logs, read_logs};

const BIN: &str = env!("CARGO_BIN_EXE_armjog");

fn fresh_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("armjog-logs-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// `armjog sim` on ephemeral ports, logging to `log_dir`; its Talos address.
fn start_sim(log_dir: &Path) -> (Child, String) {
    let mut child = Command::new(BIN)
        .args(["sim", "--talos-listen", "127.0.0.1:0", "--no-modbus"])
        .env("ARMJOG_LOG_DIR", log_dir)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("spawn armjog sim");
    let stdout = child.stdout.take().expect("piped stdout");
    let mut lines = BufReader::new(stdout).lines().map_while(Result::ok);
    // Whoever reads the simulator's terminal is told first that no hardware moves.
    let first = lines.next().unwrap_or_default();
    assert!(
        first.starts_with("armjog sim: SIMULATED ARM (no hardware)"),
        "banner: {first:?}"
    );
    let talos = lines
        .find(|line| line.contains("talos operator"))
        .and_then(|line| line.split_whitespace().nth(2).map(str::to_string))
        .expect("armjog sim prints its Talos address");
    (child, talos)
}

/// Waits (the logs are written in the background) until `prefix`'s logs in `dir` contain
/// `needle`.
fn wait_for_log(dir: &Path, prefix: &str, needle: &str) -> String {
    let until = Instant::now() + Duration::from_secs(20);
    loop {
        let text = read_logs(dir, prefix);
        if text.contains(needle) || Instant::now() > until {
            return text;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// `dir` holds `prefix`'s daily log files (one, or two over a midnight) and nothing else.
fn assert_only_logs_of(dir: &Path, prefix: &str) {
    let names = files_in(dir);
    assert!(
        (1..=2).contains(&names.len()) && names.iter().all(|n| is_daily_log(n, prefix)),
        "{prefix}'s logs alone: {names:?}"
    );
}

fn files_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("read dir")
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn the_simulator_and_send_log_to_their_own_files_and_send_logs_its_exchange() {
    let sim_dir = fresh_dir("sim");
    let cli_dir = fresh_dir("cli");
    let (mut sim, talos) = start_sim(&sim_dir);

    let out = Command::new(BIN)
        .args(["send", "--talos", &talos, "get-speed"])
        .env("ARMJOG_LOG_DIR", &cli_dir)
        .output()
        .expect("run armjog send");
    assert!(
        out.status.success(),
        "send: {}",
        String::from_utf8_lossy(&out.stderr)
    );

    // The exchange, in the one-shot's own file (written before the process ended).
    let cli_log = read_existing_logs(&cli_dir, "armjog-cli");
    let line = cli_log
        .lines()
        .find(|l| l.contains("send to") && l.contains("get_speed"))
        .unwrap_or_else(|| panic!("no exchange logged:\n{cli_log}"));
    assert!(line.contains(" INFO "), "{line}");
    assert!(line.contains(&format!("to {talos}")), "{line}");
    assert!(
        line.contains("request [") && line.contains("reply ["),
        "{line}"
    );
    assert!(line.trim_end().ends_with(" ms]"), "the round trip: {line}");
    assert_only_logs_of(&cli_dir, "armjog-cli");

    // The simulator saw the client, in its file alone.
    let sim_log = wait_for_log(&sim_dir, "armjog-sim", "connected");
    assert!(sim_log.contains("sim talos: client"), "sim log:\n{sim_log}");
    let _ = Command::new("kill")
        .args(["-TERM", &sim.id().to_string()])
        .status();
    let until = Instant::now() + Duration::from_secs(10);
    while sim.try_wait().ok().flatten().is_none() && Instant::now() < until {
        std::thread::sleep(Duration::from_millis(50));
    }
    let _ = sim.kill();
    let _ = sim.wait();
    assert_only_logs_of(&sim_dir, "armjog-sim");
    let _ = std::fs::remove_dir_all(&sim_dir);
    let _ = std::fs::remove_dir_all(&cli_dir);
}

/// The case: twenty days of `armjog-cli` files made oldest-last (as a restore from a
/// backup may make them) and files of other names; a one-shot run keeps the 13 newest days by
/// name and its own day's file, and touches nothing else.
#[test]
fn a_run_prunes_its_oldest_files_by_the_date_in_their_names() {
    let dir = fresh_dir("prune");
    let days: Vec<String> = (1..=20)
        .map(|day| format!("armjog-cli.2000-11-{day:02}.log"))
        .collect();
    let others = [
        "armjog-cli.log",
        "armjog-cli.backup.log",
        "armjog-console.2000-10-01.log",
        "audit-2000-10-01.jsonl",
        "notes.txt",
    ];
    for name in others
        .iter()
        .copied()
        .chain(days.iter().rev().map(String::as_str))
    {
        std::fs::write(dir.join(name), "old\n").expect("write");
        // Creation times come from a coarse clock: apart, so they disagree with the names.
        std::thread::sleep(Duration::from_millis(25));
    }
    let config = dir.join("config.toml");
    std::fs::write(&config, "").expect("config");
    let out = Command::new(BIN)
        .args(["arms", "--config"])
        .arg(&config)
        .env("ARMJOG_LOG_DIR", &dir)
        .output()
        .expect("run armjog arms");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let names = files_in(&dir);
    let kept: Vec<&String> = names
        .iter()
        .filter(|n| n.starts_with("armjog-cli.2000-"))
        .collect();
    assert_eq!(kept, days[7..].iter().collect::<Vec<_>>(), "{names:?}");
    for other in others.iter().chain(&["config.toml"]) {
        assert!(
            names.iter().any(|n| n == other),
            "{other} removed: {names:?}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
