//! Live console figures (a bench binary, not criterion):
//! - press-to-START and release-to-STOP latency through the real Talos link to the simulator on
//!   loopback, p50 and p99 (target: p99 under 1 ms);
//! - CPU at rest with telemetry at 30 Hz (target: under 1 % of one core) and resident memory
//!   (target: under 30 MB) of the real console binary, running in tmux against `armjog sim` in
//!   another process: once against a strict arm (the simulator's default, 5 reads a snapshot)
//!   and once against one that answers reads over unlisted addresses (4 reads a snapshot).
//!
//! Run with `cargo bench --bench console_live` (`-- idle` for the second part only). Needs tmux
//! for the second part. `ARMJOG_BIN=/path/to/armjog` measures another build of the console at
//! rest (before/after), `ARMJOG_BENCH_SIZE=COLSxROWS` another terminal (160x48 by default).
//! Wake-ups are context switches (voluntary and not) of all the console's threads, per second.

// The tests' app helpers, shared by path as the test binaries share them.
#[path = "../tests/app_support/mod.rs"]
mod app_support;
#[path = "../tests/common/mod.rs"]
mod common;

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use armjog::console::app::{App, Effect, Input, KeyInput};
use armjog::console::jog::KeyKind;
use armjog::console::positions::PositionBook;
use armjog::link::TalosConfig;
use armjog::link::driver::{Driver, DriverConfig};
use armjog::link::interface::{ArmCommand, ArmEvent, LinkStatus};
use armjog::sim::{SimConfig, Simulator};

fn percentile(sorted: &[Duration], p: f64) -> Duration {
    let i = ((sorted.len() as f64 - 1.0) * p).round() as usize;
    sorted[i.min(sorted.len() - 1)]
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1000.0
}

/// Waits for the driver's `Done` of the command `wanted` picks; false if it did not come
/// within a second (the command failed or was never sent). Every event goes on to the app, as
/// the console's runtime does: an app that never hears its STOPs confirmed stops jogging.
async fn wait_done(
    events: &mut tokio::sync::mpsc::UnboundedReceiver<ArmEvent>,
    app: &mut App,
    wanted: impl Fn(&ArmCommand) -> bool,
) -> bool {
    let done = async {
        while let Some(event) = events.recv().await {
            let found = matches!(&event, ArmEvent::Done { command } if wanted(command));
            app.handle(Input::Arm(event), Instant::now());
            if found {
                return true;
            }
        }
        false
    };
    tokio::time::timeout(Duration::from_secs(1), done)
        .await
        .unwrap_or(false)
}

async fn press_release_latency() {
    let sim = Simulator::start(SimConfig::ephemeral()).await.expect("sim");
    let config = DriverConfig::new(Some(TalosConfig::new(sim.talos_addr.to_string())), None);
    let (driver, mut events) = Driver::spawn(config);
    // The tests' session (`tests/app_support`): releases reported, a 100 ms refresh.
    let mut app = App::new(app_support::config(), PositionBook::new());
    loop {
        let Some(event) = events.recv().await else {
            return;
        };
        let up = matches!(event, ArmEvent::Status(LinkStatus::Up { .. }));
        app.handle(Input::Arm(event), Instant::now());
        if up {
            break;
        }
    }
    let key = |kind| {
        Input::Key(KeyInput {
            key: "w".parse().expect("w"),
            text: Some('w'),
            kind,
        })
    };
    let (mut press, mut release) = (Vec::new(), Vec::new());
    for _ in 0..300 {
        let t = Instant::now();
        for effect in app.handle(key(KeyKind::Press), t) {
            if let Effect::Arm(c) = effect {
                driver.send(c);
            }
        }
        if !wait_done(&mut events, &mut app, |c| matches!(c, ArmCommand::Jog(_))).await {
            println!(
                "press {}: no jog acknowledged within 1 s; latency figures cut short",
                press.len()
            );
            break;
        }
        press.push(t.elapsed());
        tokio::time::sleep(Duration::from_millis(5)).await;
        let t = Instant::now();
        for effect in app.handle(key(KeyKind::Release), t) {
            if let Effect::Arm(c) = effect {
                driver.send(c);
            }
        }
        if !wait_done(&mut events, &mut app, |c| matches!(c, ArmCommand::Stop)).await {
            println!(
                "release {}: no STOP acknowledged within 1 s; latency figures cut short",
                release.len()
            );
            break;
        }
        release.push(t.elapsed());
        tokio::time::sleep(Duration::from_millis(5)).await;
    }
    if press.is_empty() || release.is_empty() {
        return;
    }
    press.sort();
    release.sort();
    println!(
        "press-to-START acknowledged:   p50 {:.3} ms  p99 {:.3} ms  (n={})",
        ms(percentile(&press, 0.5)),
        ms(percentile(&press, 0.99)),
        press.len()
    );
    println!(
        "release-to-STOP acknowledged:  p50 {:.3} ms  p99 {:.3} ms  (n={}, 3 stop frames)",
        ms(percentile(&release, 0.5)),
        ms(percentile(&release, 0.99)),
        release.len()
    );
}

/// utime + stime of a process, in clock ticks (USER_HZ = 100 on Linux).
fn cpu_ticks(pid: u32) -> Option<u64> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    let after = stat.rsplit_once(')')?.1;
    let fields: Vec<&str> = after.split_whitespace().collect();
    // Fields after the command: state is [0], utime is [11], stime is [12].
    Some(fields.get(11)?.parse::<u64>().ok()? + fields.get(12)?.parse::<u64>().ok()?)
}

/// One counter of each of a process's threads so far, by thread id and name: `read` takes the
/// thread's `/proc/PID/task/TID` folder.
fn per_thread(pid: u32, read: fn(&std::path::Path) -> Option<u64>) -> Vec<(String, String, u64)> {
    let Ok(tasks) = std::fs::read_dir(format!("/proc/{pid}/task")) else {
        return Vec::new();
    };
    let mut threads: Vec<_> = tasks
        .flatten()
        .filter_map(|task| {
            let tid = task.file_name().to_string_lossy().into_owned();
            let name = std::fs::read_to_string(task.path().join("comm")).ok()?;
            Some((tid, name.trim().to_string(), read(&task.path())?))
        })
        .collect();
    threads.sort();
    threads
}

/// CPU time of each thread so far, ns (`schedstat`: finer than the 10 ms ticks of `stat`, which
/// make a 10 s window's figure move in steps of 0.1 %).
fn thread_ns(pid: u32) -> Vec<(String, String, u64)> {
    per_thread(pid, |task| {
        let schedstat = std::fs::read_to_string(task.join("schedstat")).ok()?;
        schedstat.split_whitespace().next()?.parse::<u64>().ok()
    })
}

/// Each thread's context switches so far (voluntary + involuntary: each one a wake-up).
fn thread_switches(pid: u32) -> Vec<(String, String, u64)> {
    per_thread(pid, |task| {
        let status = std::fs::read_to_string(task.join("status")).ok()?;
        Some(
            status
                .lines()
                .filter(|l| l.contains("ctxt_switches:"))
                .filter_map(|l| l.split_whitespace().nth(1)?.parse::<u64>().ok())
                .sum(),
        )
    })
}

/// How much of each counter a window added, per second, busiest thread first.
fn rates(
    before: &[(String, String, u64)],
    after: &[(String, String, u64)],
    window: Duration,
) -> Vec<(String, f64)> {
    let mut rates: Vec<(String, f64)> = after
        .iter()
        .map(|(tid, name, n)| {
            let start = before
                .iter()
                .find(|(t, _, _)| t == tid)
                .map_or(0, |(_, _, b)| *b);
            let rate = (n - start.min(*n)) as f64 / window.as_secs_f64();
            (format!("{name}[{tid}]"), rate)
        })
        .filter(|(_, rate)| *rate > 0.0)
        .collect();
    rates.sort_by(|a, b| b.1.total_cmp(&a.1));
    rates
}

/// Where a process's CPU went over a window: each thread's share of one core, busiest first.
fn thread_shares(
    before: &[(String, String, u64)],
    after: &[(String, String, u64)],
    window: Duration,
) -> Vec<(String, f64)> {
    let mut shares = rates(before, after, window);
    // ns per second, as a percentage of one core.
    for (_, share) in &mut shares {
        *share /= 1e7;
    }
    shares
}

/// Wake-ups per second over a window, in all and by thread (busiest first).
fn wakeups(
    before: &[(String, String, u64)],
    after: &[(String, String, u64)],
    window: Duration,
) -> (f64, Vec<(String, f64)>) {
    let rates = rates(before, after, window);
    (rates.iter().map(|(_, r)| r).sum(), rates)
}

fn status_kb(pid: u32, key: &str) -> Option<u64> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let line = status.lines().find(|l| l.starts_with(key))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

fn cpu_percent(pid: u32, window: Duration) -> Option<f64> {
    let before = cpu_ticks(pid)?;
    std::thread::sleep(window);
    let after = cpu_ticks(pid)?;
    Some((after - before) as f64 / 100.0 / window.as_secs_f64() * 100.0)
}

/// How long the console runs before the window: past the history's 30 s, whose sparklines
/// grow (and are redrawn) until the window is full.
const SETTLE: Duration = Duration::from_secs(35);

/// The console at rest against `armjog sim` started with `sim_args`, described as `arm`.
fn console_at_rest(sim_args: &[&str], arm: &str) -> Result<(), String> {
    let bin = std::env::var("ARMJOG_BIN").unwrap_or_else(|_| env!("CARGO_BIN_EXE_armjog").into());
    let size = std::env::var("ARMJOG_BENCH_SIZE").unwrap_or_else(|_| "160x48".into());
    let (cols, rows) = size
        .split_once('x')
        .ok_or("ARMJOG_BENCH_SIZE is COLSxROWS")?;
    let dir = std::env::temp_dir().join(format!("armjog-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    // The simulator is this build's, whichever console is measured.
    let mut sim = Command::new(env!("CARGO_BIN_EXE_armjog"))
        .args([
            "sim",
            "--talos-listen",
            "127.0.0.1:0",
            "--modbus-listen",
            "127.0.0.1:0",
        ])
        .args(sim_args)
        .env("ARMJOG_LOG_DIR", &dir)
        .stdout(Stdio::piped())
        .spawn()
        .map_err(|e| format!("armjog sim: {e}"))?;
    let stdout = sim.stdout.take().ok_or("no sim stdout")?;
    let mut addrs = Vec::new();
    for line in BufReader::new(stdout).lines().take(4) {
        let line = line.map_err(|e| e.to_string())?;
        if let Some(addr) = line
            .split_whitespace()
            .find(|w| w.starts_with("127.0.0.1:"))
        {
            addrs.push(addr.to_string());
        }
    }
    let [talos, modbus] = addrs.as_slice() else {
        let _ = sim.kill();
        return Err(format!("could not read the sim's addresses: {addrs:?}"));
    };
    let socket = format!("armjog-bench-{}", std::process::id());
    let command = format!(
        "ARMJOG_DATA_DIR={d} ARMJOG_LOG_DIR={d} exec {bin} --talos {talos} --modbus {modbus} --telemetry-hz 30",
        d = dir.display()
    );
    let started = Command::new("tmux")
        .args([
            "-L",
            &socket,
            "new-session",
            "-d",
            "-s",
            "b",
            "-x",
            cols,
            "-y",
            rows,
            &command,
        ])
        .status()
        .map_err(|e| format!("tmux is needed for this part: {e}"))?;
    if !started.success() {
        let _ = sim.kill();
        return Err("tmux new-session failed".into());
    }
    let result = (|| {
        let out = Command::new("tmux")
            .args(["-L", &socket, "display", "-p", "-t", "b", "#{pane_pid}"])
            .output()
            .map_err(|e| e.to_string())?;
        let pid: u32 = String::from_utf8_lossy(&out.stdout)
            .trim()
            .parse()
            .map_err(|_| "no console pid".to_string())?;
        std::thread::sleep(SETTLE);
        let window = Duration::from_secs(20);
        let sim_pid = sim.id();
        let sim_thread = std::thread::spawn(move || cpu_percent(sim_pid, window));
        let threads_before = thread_ns(pid);
        let switches_before = thread_switches(pid);
        let console = cpu_percent(pid, window).ok_or("console exited early")?;
        let threads = thread_shares(&threads_before, &thread_ns(pid), window);
        let (wakeups_total, wakeups_by_thread) =
            wakeups(&switches_before, &thread_switches(pid), window);
        let precise: f64 = threads.iter().map(|(_, share)| share).sum();
        let sim_cpu = sim_thread.join().ok().flatten();
        let rss = status_kb(pid, "VmRSS:").unwrap_or(0);
        let hwm = status_kb(pid, "VmHWM:").unwrap_or(0);
        println!(
            "console at rest ({arm}), telemetry 30 Hz over Modbus + Talos link: CPU {precise:.2} % of one core over {window:?} after {SETTLE:?} (by ticks {console:.1} %)"
        );
        let threads: Vec<String> = threads
            .iter()
            .map(|(name, share)| format!("{name} {share:.2} %"))
            .collect();
        println!("  by thread: {}", threads.join(", "));
        let wakeups_by_thread: Vec<String> = wakeups_by_thread
            .iter()
            .map(|(name, rate)| format!("{name} {rate:.1}"))
            .collect();
        println!(
            "  wake-ups: {wakeups_total:.1}/s ({bin}, {size}); by thread: {}",
            wakeups_by_thread.join(", ")
        );
        println!(
            "console resident memory: {:.1} MB (peak {:.1} MB)",
            rss as f64 / 1024.0,
            hwm as f64 / 1024.0
        );
        if let Some(s) = sim_cpu {
            println!("armjog sim serving that console: CPU {s:.2} % of one core");
        }
        Ok(())
    })();
    let _ = Command::new("tmux")
        .args(["-L", &socket, "kill-server"])
        .status();
    let _ = sim.kill();
    result
}

fn main() {
    // `cargo bench` passes flags such as --bench; `-- idle` measures only the console at rest.
    if !std::env::args().any(|a| a == "idle") {
        latency();
    }
    let arms: [(&[&str], &str); 2] = [
        (&[], "a strict arm: 5 reads a snapshot, 9 once a second"),
        (
            &["--answer-unlisted-reads"],
            "an arm that answers unlisted reads: 4 reads a snapshot",
        ),
    ];
    for (sim_args, arm) in arms {
        if let Err(e) = console_at_rest(sim_args, arm) {
            eprintln!("console_live: {e}");
            std::process::exit(1);
        }
    }
}

fn latency() {
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .expect("runtime");
    runtime.block_on(press_release_latency());
}
