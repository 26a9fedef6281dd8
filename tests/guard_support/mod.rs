//! What the stop guard tests share: the in-test simulated arm and how to watch it move.

// Each test file uses its own part of this module.
#![allow(dead_code)]

use std::process::Stdio;
use std::time::Duration;

use tokio::io::{AsyncBufReadExt, AsyncWriteExt, BufReader, Lines};
use tokio::process::{Child, ChildStdin, ChildStdout, Command};
use tokio::sync::mpsc::UnboundedReceiver;
use tokio::time::Instant;

use armjog::kortex::{ReferenceFrame, Twist};
use armjog::link::interface::{ArmEvent, GuardStatus};
use armjog::link::{ModbusConfig, ModbusLink};
use armjog::sim::{SimConfig, Simulator};

pub const BIN: &str = env!("CARGO_BIN_EXE_armjog");

pub async fn simulator() -> Simulator {
    Simulator::start(SimConfig::ephemeral())
        .await
        .expect("simulator")
}

pub fn modbus_addr(sim: &Simulator) -> String {
    sim.modbus_addr
        .expect("the simulator serves Modbus")
        .to_string()
}

pub fn log_dir() -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("armjog-guard-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// Whether the simulated arm moves, and its tool x in mm.
pub async fn arm_state(sim: &Simulator) -> (bool, f64) {
    sim.arm
        .with(|arm, _| (arm.is_moving(), arm.pose().position.x * 1000.0))
        .await
        .expect("simulated arm")
}

/// Polls until the arm's motion is `moving`; returns how long it took, or `None` after `within`.
pub async fn wait_moving(sim: &Simulator, moving: bool, within: Duration) -> Option<Duration> {
    let started = Instant::now();
    while started.elapsed() < within {
        if arm_state(sim).await.0 == moving {
            return Some(started.elapsed());
        }
        tokio::time::sleep(Duration::from_millis(5)).await;
    }
    None
}

/// Asserts the arm starts moving within 5 s; `what` names the motion.
pub async fn assert_moving(sim: &Simulator, what: &str) {
    assert!(
        wait_moving(sim, true, Duration::from_secs(5))
            .await
            .is_some(),
        "{what}"
    );
}

/// Asserts the tool stays where it is for a while (the stop held, nothing restarted it).
pub async fn assert_still(sim: &Simulator) {
    let (_, x0) = arm_state(sim).await;
    tokio::time::sleep(Duration::from_millis(400)).await;
    let (moving, x1) = arm_state(sim).await;
    assert!(
        !moving && (x1 - x0).abs() < 0.05,
        "the arm keeps still: {x0:.3} -> {x1:.3} mm"
    );
}

/// A client standing in for the console's twist: 20 mm/s +X, far from any limit for seconds.
pub async fn start_twist(sim: &Simulator) -> ModbusLink {
    let mut config = ModbusConfig::new(modbus_addr(sim));
    config.poll_rate_hz = None;
    config.twist_hold = None;
    let (link, _events) = ModbusLink::connect(config).await.expect("connect");
    let twist = Twist {
        x: 0.02,
        ..Twist::default()
    };
    link.jog_twist(ReferenceFrame::Base, twist)
        .await
        .expect("twist");
    assert_moving(sim, "the twist runs").await;
    link
}

/// The guard process, with the pipe a console would hold.
pub struct Guard {
    pub child: Child,
    pub stdin: Option<ChildStdin>,
    lines: Lines<BufReader<ChildStdout>>,
}

impl Guard {
    /// `armjog guard ARGS`, once it says it is ready.
    pub async fn start(args: &[&str]) -> Guard {
        let mut child = Command::new(BIN)
            .arg("guard")
            .args(args)
            .env("ARMJOG_LOG_DIR", log_dir())
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .kill_on_drop(true)
            .spawn()
            .expect("start armjog guard");
        let stdin = child.stdin.take();
        let lines = BufReader::new(child.stdout.take().expect("stdout")).lines();
        let mut guard = Guard {
            child,
            stdin,
            lines,
        };
        let ready = guard.line(Duration::from_secs(10)).await;
        assert_eq!(
            ready.as_deref(),
            Some("ready"),
            "the guard says it is ready"
        );
        guard
    }

    pub async fn beat(&mut self) {
        let stdin = self.stdin.as_mut().expect("pipe open");
        stdin.write_all(b".").await.expect("heartbeat");
        stdin.flush().await.expect("heartbeat");
    }

    /// Heartbeats every 100 ms for `duration`.
    pub async fn beat_for(&mut self, duration: Duration) {
        let until = Instant::now() + duration;
        while Instant::now() < until {
            self.beat().await;
            tokio::time::sleep(Duration::from_millis(100)).await;
        }
    }

    /// What the guard says next (5 s at most), or "" if nothing.
    pub async fn said(&mut self) -> String {
        self.line(Duration::from_secs(5)).await.unwrap_or_default()
    }

    /// Asserts the guard process still runs.
    pub fn assert_watching(&mut self) {
        assert!(
            self.child.try_wait().expect("guard status").is_none(),
            "the guard keeps watching"
        );
    }

    /// Waits (5 s at most) for the guard process to exit; `what` says the exit expected.
    pub async fn exit_status(&mut self, what: &str) -> std::process::ExitStatus {
        tokio::time::timeout(Duration::from_secs(5), self.child.wait())
            .await
            .expect(what)
            .expect("exit status")
    }

    /// The next line other than the guard's periodic `alive`.
    pub async fn line(&mut self, within: Duration) -> Option<String> {
        let until = Instant::now() + within;
        loop {
            let line = tokio::time::timeout_at(until, self.lines.next_line())
                .await
                .ok()
                .and_then(|l| l.ok())
                .flatten()?;
            if line != "alive" {
                return Some(line);
            }
        }
    }
}

/// Drives the driver's events until `done` matches one; panics after `within`.
pub async fn wait_event(
    events: &mut UnboundedReceiver<ArmEvent>,
    within: Duration,
    what: &str,
    mut done: impl FnMut(&ArmEvent) -> bool,
) -> ArmEvent {
    let until = Instant::now() + within;
    loop {
        let event = tokio::time::timeout_at(until, events.recv())
            .await
            .unwrap_or_else(|_| panic!("waited {within:?} for {what}"))
            .expect("driver alive");
        if done(&event) {
            return event;
        }
    }
}

/// Waits for the driver's guard to be ready; its pid.
pub async fn guard_ready(
    events: &mut UnboundedReceiver<ArmEvent>,
    within: Duration,
    what: &str,
) -> u32 {
    let ready = wait_event(events, within, what, |e| {
        matches!(e, ArmEvent::Guard(GuardStatus::Ready { .. }))
    })
    .await;
    let ArmEvent::Guard(GuardStatus::Ready { pid }) = ready else {
        unreachable!()
    };
    pid
}

/// Waits for the driver's guard to go down; the reason it gives.
pub async fn guard_down(events: &mut UnboundedReceiver<ArmEvent>, within: Duration) -> String {
    let down = wait_event(events, within, "the guard down", |e| {
        matches!(e, ArmEvent::Guard(GuardStatus::Down { .. }))
    })
    .await;
    let ArmEvent::Guard(GuardStatus::Down { reason }) = down else {
        unreachable!()
    };
    reason
}

/// Kills the driver's guard `pid` (SIGKILL) while the arm moves: asserts the driver sees it
/// down, the arm stops within 3 s (`stops` says so), and a fresh guard is ready within 15 s.
pub async fn guard_killed_and_replaced(
    sim: &Simulator,
    events: &mut UnboundedReceiver<ArmEvent>,
    pid: u32,
    stops: &str,
) {
    assert!(send_signal(pid, "-9"));
    guard_down(events, Duration::from_secs(5)).await;
    wait_moving(sim, false, Duration::from_secs(3))
        .await
        .expect(stops);
    let again = guard_ready(events, Duration::from_secs(15), "a new guard").await;
    assert_ne!(again, pid, "a fresh guard process");
}

/// `kill SIGNAL PID` (`-9`, `-TERM`, `-STOP`); whether kill(1) succeeded.
pub fn send_signal(pid: u32, signal: &str) -> bool {
    std::process::Command::new("kill")
        .args([signal, &pid.to_string()])
        .status()
        .expect("kill")
        .success()
}

/// A tmux server of our own for the real console, killed on drop.
pub struct Tmux {
    pub socket: String,
}

impl Tmux {
    /// `name` tells apart the servers of tests running at once.
    pub fn start(name: &str, command: &str) -> Tmux {
        let socket = format!("armjog-guard-{name}-{}", std::process::id());
        let status = std::process::Command::new("tmux")
            .args(["-L", &socket, "new-session", "-d", "-s", "console"])
            .args(["-x", "100", "-y", "30", command])
            .status()
            .expect("tmux must be installed (apt-get install -y tmux)");
        assert!(status.success(), "tmux new-session failed");
        Tmux { socket }
    }

    pub fn tmux(&self, args: &[&str]) -> std::process::Output {
        std::process::Command::new("tmux")
            .args(["-L", &self.socket])
            .args(args)
            .output()
            .expect("tmux")
    }

    pub fn key(&self, key: &str) -> bool {
        self.tmux(&["send-keys", "-t", "console", key])
            .status
            .success()
    }

    pub fn screen(&self) -> String {
        let out = self.tmux(&["capture-pane", "-p", "-t", "console"]);
        String::from_utf8_lossy(&out.stdout).into_owned()
    }

    pub fn pane_pid(&self) -> u32 {
        let out = self.tmux(&["display-message", "-p", "-t", "console", "#{pane_pid}"]);
        let text = String::from_utf8_lossy(&out.stdout);
        text.trim().parse().expect("pane pid")
    }

    /// `-` twice, down to 10 % of the cap (25 %, then 10 %), each step seen on the screen.
    pub async fn slow_to_10_percent(&self) {
        for speed in ["25%", "10%"] {
            self.key("-");
            let shown = format!("speed {speed}");
            self.wait_for(Duration::from_secs(5), &shown, |s| s.contains(&shown))
                .await;
        }
    }

    pub async fn wait_for(&self, within: Duration, what: &str, done: impl Fn(&str) -> bool) {
        let until = Instant::now() + within;
        loop {
            let screen = self.screen();
            if done(&screen) {
                return;
            }
            assert!(
                Instant::now() < until,
                "waited {within:?} for {what}; screen:\n{screen}"
            );
            tokio::time::sleep(Duration::from_millis(50)).await;
        }
    }
}

impl Drop for Tmux {
    fn drop(&mut self) {
        let _ = self.tmux(&["kill-server"]);
    }
}

/// Whether any of `pids` still runs.
pub fn any_alive(pids: &[u32]) -> bool {
    pids.iter()
        .any(|pid| std::path::Path::new(&format!("/proc/{pid}")).exists())
}

/// Waits (10 s at most) for the guard processes to exit; ends any left and fails.
pub async fn assert_exit(guards: &[u32], when: &str) {
    let until = Instant::now() + Duration::from_secs(10);
    while any_alive(guards) && Instant::now() < until {
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    let alive = any_alive(guards);
    if alive {
        for pid in guards {
            let _ = std::process::Command::new("kill")
                .arg(pid.to_string())
                .status();
        }
    }
    assert!(!alive, "the guard exits {when}: {guards:?}");
}

/// Pids of running processes whose command line has every one of `words`.
pub fn pids_with(words: &[&str]) -> Vec<u32> {
    let Ok(entries) = std::fs::read_dir("/proc") else {
        return Vec::new();
    };
    entries
        .filter_map(|e| e.ok())
        .filter_map(|e| e.file_name().to_str()?.parse::<u32>().ok())
        .filter(|pid| {
            let cmdline = std::fs::read(format!("/proc/{pid}/cmdline")).unwrap_or_default();
            let args: Vec<String> = cmdline
                .split(|b| *b == 0)
                .map(|a| String::from_utf8_lossy(a).into_owned())
                .collect();
            words.iter().all(|w| args.iter().any(|a| a == w))
        })
        .collect()
}
