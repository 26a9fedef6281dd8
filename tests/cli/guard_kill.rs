//! `kill -9` of the real console mid-move, on every link: the stop guard stops the arm within
//! 1 s. Every part is a process of its own, as in the field: `armjog sim`, the console in tmux
//! (`.ci/run` installs it), the guard it starts, and `armjog status --json --watch` reading the
//! arm over the simulator's Modbus server. The cases: a go-to over Talos alone, over Modbus
//! alone and over both; and Home over an operator that serves one client at a time, in the
//! deployed operator's dialect (ack, XOR checksum), where the guard is served only once the
//! kernel has closed the dead console's connection. Neither a go-to nor Home has an operator
//! watchdog: without the guard each runs to its end.
//!
//! Each prints the time from `kill` returning to the first sample at rest (samples every 20 ms).

use crate::guard_support;
use crate::log_files;
use crate::sim_process::SimProcess;

use std::io::{BufRead, BufReader};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use armjog::kortex::{ReferenceFrame, Twist};
use armjog::link::{ModbusConfig, ModbusLink};
use guard_support::{BIN, Tmux, assert_exit, pids_with, send_signal};

/// The tool at rest, mm/s: the simulator reports exact zeros at rest.
const AT_REST: f64 = 0.5;
/// How far the arm is moved from the go-to's target (or from home) before the move, mm.
const AWAY_MM: f64 = 150.0;

/// One `armjog status --json` sample, stamped when it was read.
#[derive(Debug, Clone, Copy)]
struct Sample {
    at: Instant,
    /// The tool, mm.
    position: [f64; 3],
    /// The tool's linear speed, mm/s.
    speed: f64,
}

/// `armjog status --json --watch 50` on the simulator's Modbus server; killed on drop.
struct Watch {
    child: std::process::Child,
    samples: mpsc::Receiver<Sample>,
}

impl Watch {
    fn start(sim: &SimProcess) -> Watch {
        let mut child = std::process::Command::new(BIN)
            .args(["status", "--modbus", &sim.modbus.to_string(), "--unit", "1"])
            .args(["--json", "--watch", "50"])
            .env("ARMJOG_LOG_DIR", &sim.log_dir)
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::null())
            .spawn()
            .expect("armjog status");
        let stdout = child.stdout.take().expect("status stdout");
        let (tx, samples) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines().map_while(Result::ok) {
                let at = Instant::now();
                let Ok(json) = serde_json::from_str::<serde_json::Value>(&line) else {
                    continue;
                };
                let tcp = &json["tcp"];
                let mm = |v: &serde_json::Value| v.as_f64().unwrap_or(f64::NAN) * 1000.0;
                let position = ["x", "y", "z"].map(|axis| mm(&tcp["pose"][axis]));
                let twist = ["x", "y", "z"].map(|axis| mm(&tcp["twist"][axis]));
                let speed = twist.iter().map(|v| v * v).sum::<f64>().sqrt();
                if tx
                    .send(Sample {
                        at,
                        position,
                        speed,
                    })
                    .is_err()
                {
                    break;
                }
            }
        });
        Watch { child, samples }
    }

    /// The first sample from now on that `done` accepts; panics after `within`.
    fn until(&self, within: Duration, what: &str, done: impl Fn(&Sample) -> bool) -> Sample {
        self.first(within, done)
            .unwrap_or_else(|| panic!("waited {within:?} for {what}"))
    }

    /// The first sample from now on that `done` accepts, or `None` after `within`.
    fn first(&self, within: Duration, done: impl Fn(&Sample) -> bool) -> Option<Sample> {
        let until = Instant::now() + within;
        loop {
            let left = until.saturating_duration_since(Instant::now());
            match self.samples.recv_timeout(left) {
                Ok(sample) if done(&sample) => return Some(sample),
                Ok(_) => {}
                Err(_) => return None,
            }
        }
    }

    /// Every sample from now for `duration`.
    fn during(&self, duration: Duration) -> Vec<Sample> {
        let until = Instant::now() + duration;
        let mut samples = Vec::new();
        while let Ok(sample) = self
            .samples
            .recv_timeout(until.saturating_duration_since(Instant::now()))
        {
            samples.push(sample);
        }
        samples
    }
}

impl Drop for Watch {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(a, b)| (a - b).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// Another client's twist moves the tool `AWAY_MM` along +Y, then stops it.
async fn move_away(sim: &SimProcess, watch: &Watch) {
    let mut config = ModbusConfig::new(sim.modbus.to_string());
    config.poll_rate_hz = None;
    config.twist_hold = None;
    let (link, _events) = ModbusLink::connect(config).await.expect("connect");
    let start = watch.until(Duration::from_secs(5), "a sample", |_| true);
    let twist = Twist {
        y: 0.05,
        ..Twist::default()
    };
    link.jog_twist(ReferenceFrame::Base, twist)
        .await
        .expect("twist");
    watch.until(Duration::from_secs(10), "the tool moved away", |s| {
        distance(s.position, start.position) >= AWAY_MM
    });
    link.stop().await.expect("stop");
    watch.until(Duration::from_secs(5), "the arm at rest", |s| {
        s.speed < AT_REST
    });
    let _ = link.close().await;
}

/// What the console is killed in the middle of.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Move {
    /// Save `start` where the arm is, move it away, go to `start`.
    GoTo,
    /// Move the arm away from home, send it home.
    Home,
}

struct Case<'a> {
    name: &'a str,
    /// `armjog sim`'s options beyond the ports.
    sim: &'a [&'a str],
    /// The console's links, `{talos}` and `{modbus}` for the simulator's addresses.
    links: &'a str,
    motion: Move,
    /// What the guard's log says it did, in its line of the stop.
    guard_said: &'a [&'a str],
}

/// Runs one case; returns the milliseconds from the kill to the arm at rest.
async fn kill_mid_move(case: Case<'_>) -> f64 {
    let sim = SimProcess::spawn_with(None, case.sim);
    let dir = sim.log_dir.join("console");
    std::fs::create_dir_all(&dir).expect("console dir");
    let links = case
        .links
        .replace("{talos}", &sim.talos.to_string())
        .replace("{modbus}", &sim.modbus.to_string());
    let command = format!(
        "exec env ARMJOG_DATA_DIR={d} ARMJOG_LOG_DIR={d} ARMJOG_STATE_DIR={d} {BIN} {links} \
         --key-release repeat --positions {d}/book.json",
        d = dir.display(),
    );
    let tmux = Tmux::start(&format!("kill-{}", case.name), &command);
    tmux.wait_for(Duration::from_secs(20), "the link and the guard", |s| {
        s.contains("LINK UP") && s.contains("GUARD OK")
    })
    .await;
    let console_pid = tmux.pane_pid();
    let guards = pids_with(&["guard"])
        .into_iter()
        .filter(|pid| parent_of(*pid) == Some(console_pid))
        .collect::<Vec<_>>();
    assert_eq!(guards.len(), 1, "the console runs one guard: {guards:?}");
    let watch = Watch::start(&sim);

    let target = match case.motion {
        Move::GoTo => {
            // 10 % of 250 mm/s: the 150 mm go-to takes 6 s.
            tmux.slow_to_10_percent().await;
            let here = watch.until(Duration::from_secs(5), "a sample", |_| true);
            tmux.key("p");
            tmux.wait_for(Duration::from_secs(5), "the save form", |s| {
                s.contains("Save current pose")
            })
            .await;
            tmux.key("start");
            tmux.key("Enter");
            tmux.wait_for(Duration::from_secs(5), "saved", |s| {
                s.contains("saved 'start'")
            })
            .await;
            move_away(&sim, &watch).await;
            tmux.key("o");
            tmux.wait_for(Duration::from_secs(5), "the question", |s| {
                s.contains("Move the arm to 'start'?")
            })
            .await;
            here.position
        }
        Move::Home => {
            let home = watch.until(Duration::from_secs(5), "a sample", |_| true);
            move_away(&sim, &watch).await;
            tmux.key("h");
            tmux.wait_for(Duration::from_secs(5), "the question", |s| {
                s.contains("Move the arm to its home pose?")
            })
            .await;
            home.position
        }
    };
    // A new question ignores keys for its first 150 ms (`QUESTION_QUIET`).
    tokio::time::sleep(Duration::from_millis(400)).await;
    tmux.key("y");
    if watch
        .first(Duration::from_secs(10), |s| s.speed > 5.0)
        .is_none()
    {
        panic!("{}: no move; the console:\n{}", case.name, tmux.screen());
    }
    let moving = watch.during(Duration::from_millis(500));
    let before = *moving.last().expect("samples while moving");
    assert!(
        before.speed > 5.0,
        "still moving before the kill: {before:?}"
    );

    let killed = send_signal(console_pid, "-9");
    // `kill` has returned: the signal is delivered.
    let killed_at = Instant::now();
    assert!(killed, "kill -9 {console_pid}");
    let rest = watch.until(Duration::from_secs(5), "the arm at rest", |s| {
        s.speed < AT_REST
    });
    let took = rest.at.saturating_duration_since(killed_at);
    let ms = took.as_secs_f64() * 1000.0;
    let still = watch.during(Duration::from_millis(500));
    let drift = still
        .iter()
        .map(|s| distance(s.position, rest.position))
        .fold(0.0, f64::max);
    let short = distance(rest.position, target);
    eprintln!(
        "{}: console SIGKILLed -> arm at rest in {ms:.0} ms, {:.1} mm after the kill, \
         {short:.0} mm short of the target",
        case.name,
        distance(rest.position, before.position)
    );
    assert!(
        took < Duration::from_secs(1),
        "{}: the arm stops within 1 s of the kill, not {ms:.0} ms",
        case.name
    );
    assert!(
        still.iter().all(|s| s.speed < AT_REST) && drift < 0.5,
        "{}: the stop holds (drift {drift:.2} mm)",
        case.name
    );
    assert!(
        short > 20.0,
        "{}: the move was stopped, not finished ({short:.1} mm short)",
        case.name
    );
    assert_exit(&guards, "after its stop").await;
    let log = log_files::read_logs(&dir, "armjog-guard");
    let line = log
        .lines()
        .find(|l| l.contains("arm stopped"))
        .unwrap_or_else(|| panic!("{}: the guard logs its stop:\n{log}", case.name));
    for part in case.guard_said {
        assert!(line.contains(part), "{}: {part:?} in {line}", case.name);
    }
    ms
}

/// The parent pid of `pid`, from /proc.
fn parent_of(pid: u32) -> Option<u32> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // The command name, in parentheses, may hold spaces: count from its end.
    let after = &stat[stat.rfind(')')? + 1..];
    after.split_whitespace().nth(1)?.parse().ok()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn killing_the_console_mid_go_to_over_talos_alone_stops_the_arm_within_1_s() {
    kill_mid_move(Case {
        name: "talos",
        sim: &[],
        links: "--talos {talos}",
        motion: Move::GoTo,
        guard_said: &["talos: stop set of 3"],
    })
    .await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn killing_the_console_mid_go_to_over_modbus_alone_stops_the_arm_within_1_s() {
    kill_mid_move(Case {
        name: "modbus",
        sim: &[],
        links: "--modbus {modbus} --unit 1",
        motion: Move::GoTo,
        guard_said: &["modbus: "],
    })
    .await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn killing_the_console_mid_go_to_over_both_links_stops_the_arm_on_both_within_1_s() {
    kill_mid_move(Case {
        name: "both",
        sim: &[],
        links: "--talos {talos} --modbus {modbus} --unit 1",
        motion: Move::GoTo,
        guard_said: &["modbus: ", "talos: stop set of 3"],
    })
    .await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn killing_the_console_mid_home_over_an_operator_that_serves_one_client_stops_the_arm() {
    kill_mid_move(Case {
        name: "one-client",
        // The ack dialect has no Set Speed: the operator's own 50 % of 50 mm/s is the speed.
        sim: &[
            "--one-client",
            "--dialect",
            "ack",
            "--checksum",
            "xor8",
            "--max-jog-speed",
            "50",
        ],
        links: "--talos {talos} --dialect ack --checksum xor8",
        motion: Move::Home,
        guard_said: &["talos: stop set of 1"],
    })
    .await;
}
