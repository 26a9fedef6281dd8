//! The real binary in tmux on the built-in simulator: a quiet start (no WARN in the console's
//! log), the simulator's lines in a file of their own, and the session's audit file.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::{Duration, Instant};

use crate::log_files::read_existing_logs;

/// A tmux server of our own, killed on drop.
struct Tmux {
    socket: String,
}

impl Tmux {
    fn start(command: &str) -> Tmux {
        // One server per test: the tests of this file run in parallel.
        static STARTED: AtomicU32 = AtomicU32::new(0);
        let socket = format!(
            "armjog-logs-{}-{}",
            std::process::id(),
            STARTED.fetch_add(1, Ordering::Relaxed)
        );
        let status = Command::new("tmux")
            .args(["-L", &socket, "new-session", "-d", "-s", "console"])
            .args(["-x", "100", "-y", "30"])
            .arg(command)
            .status()
            .expect("tmux must be installed (apt-get install -y tmux)");
        assert!(status.success(), "tmux new-session failed");
        Tmux { socket }
    }

    fn keys(&self, keys: &[&str]) {
        let status = Command::new("tmux")
            .args(["-L", &self.socket, "send-keys", "-t", "console"])
            .args(keys)
            .status()
            .expect("tmux send-keys");
        assert!(status.success());
    }

    fn screen(&self) -> String {
        let out = Command::new("tmux")
            .args(["-L", &self.socket, "capture-pane", "-p", "-t", "console"])
            .output()
            .expect("tmux capture-pane");
        String::from_utf8_lossy(&out.stdout).into_owned()
    }

    /// The pid of the pane's process (the console itself, run with `exec`).
    fn pane_pid(&self) -> u32 {
        let shown = Command::new("tmux")
            .args(["-L", &self.socket, "display", "-p", "-t", "console"])
            .arg("#{pane_pid}")
            .output()
            .expect("tmux display");
        String::from_utf8_lossy(&shown.stdout)
            .trim()
            .parse()
            .expect("the console's pid")
    }

    fn wait_for(&self, what: &str, done: impl Fn(&str) -> bool) -> String {
        let until = Instant::now() + Duration::from_secs(30);
        loop {
            let screen = self.screen();
            if done(&screen) {
                return screen;
            }
            assert!(
                Instant::now() < until,
                "waited for {what}; screen:\n{screen}"
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    }
}

impl Drop for Tmux {
    fn drop(&mut self) {
        let _ = Command::new("tmux")
            .args(["-L", &self.socket, "kill-server"])
            .status();
    }
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Every audit line of the session, from however many day files it spans.
fn audit_lines(dir: &Path) -> Vec<serde_json::Value> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("the audit directory was made")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("audit-") && n.ends_with(".jsonl"))
        })
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no audit file in {}", dir.display());
    files
        .iter()
        .flat_map(|f| {
            read(f)
                .lines()
                .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{l}: {e}")))
                .collect::<Vec<serde_json::Value>>()
        })
        .collect()
}

/// A fresh directory for one test's logs and state, named for it.
fn fresh_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("armjog-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// The console on the built-in simulator, its logs in `dir` and its audit in `state`; `run`
/// is put before the binary (`exec`, or nothing), `then` after it.
fn console_command(dir: &Path, state: &Path, run: &str, then: &str) -> String {
    format!(
        "ARMJOG_DATA_DIR={d} ARMJOG_LOG_DIR={d} ARMJOG_STATE_DIR={s} {run}{bin} --key-release repeat{then}",
        d = dir.display(),
        s = state.display(),
        bin = env!("CARGO_BIN_EXE_armjog"),
    )
}

#[test]
fn the_console_starts_quietly_logs_apart_from_its_simulator_and_audits_the_session() {
    let dir = fresh_dir("logs-e2e");
    let state = dir.join("state");
    let command = console_command(&dir, &state, "", "; echo ARMJOG-EXITED-$?; sleep 30");
    let tmux = Tmux::start(&command);
    tmux.wait_for("the link to come up", |s| {
        s.contains("LINK UP") && s.contains("pos mm")
    });
    // A few polls on the link, then a speed change and a stop.
    std::thread::sleep(Duration::from_millis(500));
    tmux.keys(&["-"]);
    std::thread::sleep(Duration::from_millis(300));
    tmux.keys(&["Space"]);
    std::thread::sleep(Duration::from_millis(300));
    tmux.keys(&["q"]);
    let back = tmux.wait_for("the console to exit", |s| s.contains("ARMJOG-EXITED-"));
    assert!(back.contains("ARMJOG-EXITED-0"), "exit status 0:\n{back}");

    let console = read_existing_logs(&dir, "armjog-console");
    for bad in [" WARN ", " ERROR "] {
        assert!(
            !console.contains(bad),
            "the console's log has a{bad}line at a plain start:\n{console}"
        );
    }
    assert!(
        !console.contains("armjog::sim"),
        "the simulator's lines are in the console's log:\n{console}"
    );
    let sim = read_existing_logs(&dir, "armjog-sim");
    assert!(sim.contains("sim talos: client"), "sim log:\n{sim}");
    assert!(
        sim.lines().all(|l| l.contains("armjog::sim")),
        "only the simulator in its log:\n{sim}"
    );

    let lines = audit_lines(&state);
    for line in &lines {
        let ts = line["ts"].as_str().unwrap_or_default();
        assert!(ts.len() == 24 && ts.ends_with('Z'), "timestamp {line}");
    }
    let events: Vec<&str> = lines.iter().filter_map(|l| l["event"].as_str()).collect();
    let order = ["session_start", "link_up", "speed", "stop", "session_end"];
    let mut at = 0;
    for want in order {
        match events[at..].iter().position(|e| *e == want) {
            Some(i) => at += i + 1,
            None => panic!("{want} missing or out of order in {events:?}"),
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_audit_file_that_cannot_be_written_is_shown_and_stops_nothing() {
    let dir = fresh_dir("logs-blocked");
    // A file where the audit directory should be: unwritable even for root.
    let blocked = dir.join("not-a-dir");
    std::fs::write(&blocked, "").expect("seed");
    let command = console_command(
        &dir,
        &blocked.join("state"),
        "",
        "; echo ARMJOG-EXITED-$?; sleep 30",
    );
    let tmux = Tmux::start(&command);
    tmux.wait_for("the link and the audit failure", |s| {
        s.contains("LINK UP") && s.contains("audit log")
    });
    // Still at the technician's command: a tap steps, and the console quits cleanly.
    tmux.keys(&["w"]);
    std::thread::sleep(Duration::from_millis(300));
    tmux.keys(&["q"]);
    let back = tmux.wait_for("the console to exit", |s| s.contains("ARMJOG-EXITED-"));
    assert!(back.contains("ARMJOG-EXITED-0"), "exit status 0:\n{back}");
    let console = read_existing_logs(&dir, "armjog-console");
    assert_eq!(
        console.matches("audit log not written").count(),
        1,
        "warned once:\n{console}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Whether process `pid` is still running (not gone, and not a zombie left for its parent).
fn running(pid: u32) -> bool {
    std::fs::read_to_string(format!("/proc/{pid}/stat"))
        .map(|stat| {
            !stat
                .rsplit(')')
                .next()
                .unwrap_or_default()
                .trim()
                .starts_with('Z')
        })
        .unwrap_or(false)
}

#[test]
fn a_terminal_that_hangs_up_ends_the_console_without_a_panic() {
    // An SSH session that drops: the terminal goes, and with it stderr.
    let dir = fresh_dir("hangup-e2e");
    let state = dir.join("state");
    // The console itself in the pane (no shell between), so the hang-up is its own.
    let command = console_command(&dir, &state, "exec ", "");
    let tmux = Tmux::start(&command);
    tmux.wait_for("the link to come up", |s| {
        s.contains("LINK UP") && s.contains("pos mm")
    });
    let pid = tmux.pane_pid();
    // The terminal hangs up while the console draws (a jog's frames).
    tmux.keys(&["w"]);
    drop(tmux);
    let until = Instant::now() + Duration::from_secs(20);
    while running(pid) {
        assert!(
            Instant::now() < until,
            "the console did not end after the hang-up"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    let console = read_existing_logs(&dir, "armjog-console");
    assert!(
        !console.contains("panic"),
        "the console panicked after the hang-up:\n{console}"
    );
    let events: Vec<String> = audit_lines(&state)
        .iter()
        .filter_map(|l| l["event"].as_str().map(str::to_string))
        .collect();
    assert!(
        events.iter().any(|e| e == "session_end"),
        "no session_end in {events:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A console killed outright (SIGKILL) leaves a recording readable up to its last second: the
/// recorder closes a chunk every second.
#[test]
fn a_console_killed_outright_leaves_its_recording_readable_up_to_its_last_second() {
    let dir = fresh_dir("recording-killed");
    let state = dir.join("state");
    let tmux = Tmux::start(&console_command(&dir, &state, "exec ", ""));
    tmux.wait_for("the link to come up", |s| {
        s.contains("LINK UP") && s.contains("pos mm")
    });
    std::thread::sleep(Duration::from_millis(2500));
    let pid = tmux.pane_pid().to_string();
    let killed_at = std::time::SystemTime::now();
    let status = Command::new("kill")
        .args(["-KILL", &pid])
        .status()
        .expect("kill");
    assert!(status.success(), "kill -KILL {pid}");
    std::thread::sleep(Duration::from_millis(300));
    let recording = std::fs::read_dir(&state)
        .expect("the state folder")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .find(|p| p.extension().is_some_and(|e| e == "mcap"))
        .expect("a recording beside the audit");
    let bytes = std::fs::read(&recording).expect("the recording");
    let last = mcap::MessageStream::new(&bytes)
        .expect("an MCAP start")
        .map_while(Result::ok)
        .map(|m| m.log_time)
        .max()
        .expect("messages readable");
    let killed_ns = killed_at
        .duration_since(std::time::SystemTime::UNIX_EPOCH)
        .expect("after 1970")
        .as_nanos() as u64;
    let lost = Duration::from_nanos(killed_ns.saturating_sub(last));
    // A chunk a second, and a loaded machine's scheduling: generous.
    assert!(
        lost < Duration::from_millis(2500),
        "{lost:?} before the kill lost"
    );
    // And it plays back, up to the same last second, saying it was cut short.
    let played = armjog::console::replay::Recording::read(&recording).expect("playable");
    // Its last sample (a few ms before the last message of any kind).
    assert!(
        last - played.last_ns < 100_000_000,
        "{last} vs {}",
        played.last_ns
    );
    assert!(
        played.cut_short.is_some(),
        "no summary: the end is not the file's"
    );
    let mut player =
        armjog::console::replay::Player::new(played, (120, 40), std::time::Instant::now());
    player.seek(last);
    let view = player.view();
    assert!(view.arm.telemetry.is_some(), "the arm as last recorded");
    let said = view
        .screen
        .message
        .map(|(text, _)| text)
        .unwrap_or_default();
    assert!(said.contains("recording cut short"), "{said}");
}
