//! What the built-in simulator costs, as a plain bench binary (`harness = false`):
//!
//! (a) CPU at rest and while moving: the `Simulator` runs in-process on a tokio runtime like the
//!     one `armjog` builds (multi-thread, one worker per core); each window measures the process
//!     CPU time (utime + stime from `/proc/self/stat`, in clock ticks of `getconf CLK_TCK`,
//!     assumed 100 when that cannot be run) over wall time, as a percentage of one core.
//!     Target: under 3 %. The "moving" windows include the few requests that keep the motion
//!     going (and, in the last, armjog's Modbus link polling telemetry), so they slightly overstate the
//!     simulator's own share.
//! (b) Talos requests per second on loopback: sequential GetSpeed request/reply on one
//!     `TalosLink`; 8 links (8 clients) each sequential; and 8 requests in flight on one link.
//!
//! Run: `cargo bench --bench sim_cost`. Figures are printed; nothing is asserted.

use std::process::Command;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use tokio_modbus::client::{Writer, tcp};
use tokio_modbus::{Slave, client::Context};

use armjog::kortex::PollPlan;
use armjog::link::{ModbusConfig, ModbusLink, TalosConfig, TalosLink};
use armjog::sim::{SimConfig, Simulator};
use armjog::talos::Request;

const CPU_WINDOW: Duration = Duration::from_secs(3);
const RATE_WINDOW: Duration = Duration::from_secs(2);
const TARGET_PERCENT: f64 = 3.0;

/// Clock ticks per second for /proc times: `getconf CLK_TCK`, else the usual 100.
fn clock_ticks() -> (f64, &'static str) {
    let out = Command::new("getconf").arg("CLK_TCK").output().ok();
    let parsed = out
        .filter(|o| o.status.success())
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .and_then(|s| s.trim().parse::<f64>().ok())
        .filter(|t| *t > 0.0);
    match parsed {
        Some(t) => (t, "getconf CLK_TCK"),
        None => (100.0, "assumed"),
    }
}

/// utime + stime of this process, in clock ticks.
fn cpu_ticks() -> u64 {
    let stat = std::fs::read_to_string("/proc/self/stat").expect("/proc/self/stat");
    // The command name is in parentheses and may hold spaces: count fields after the last ')'.
    let after = &stat[stat.rfind(')').expect("stat format") + 1..];
    let fields: Vec<&str> = after.split_whitespace().collect();
    // Field 3 (state) is fields[0]; utime is field 14, stime field 15.
    let utime: u64 = fields[11].parse().expect("utime");
    let stime: u64 = fields[12].parse().expect("stime");
    utime + stime
}

/// CPU time of every live thread of this process, nanoseconds: the first field of
/// `/proc/self/task/*/schedstat`. Finer than the 10 ms ticks of `/proc/self/stat`, which a 3 s
/// window at well under 1 % can hardly resolve. (A thread that ends inside a window takes its
/// time with it; the runtime's threads live throughout.)
fn cpu_ns() -> Option<u64> {
    let mut total = 0;
    for task in std::fs::read_dir("/proc/self/task").ok()? {
        let path = task.ok()?.path().join("schedstat");
        if let Ok(text) = std::fs::read_to_string(path) {
            total += text.split_whitespace().next()?.parse::<u64>().ok()?;
        }
    }
    Some(total)
}

/// One measured window.
struct Cpu {
    /// % of one core from utime + stime ticks.
    ticks_percent: f64,
    ticks_s: f64,
    /// % of one core from the threads' nanosecond run time, when readable.
    ns_percent: Option<f64>,
}

impl Cpu {
    /// The best figure: nanosecond based when available.
    fn percent(&self) -> f64 {
        self.ns_percent.unwrap_or(self.ticks_percent)
    }

    fn show(&self) -> String {
        let precise = match self.ns_percent {
            Some(p) => format!("{p:6.2} %"),
            None => "   n/a  ".into(),
        };
        format!(
            "{precise}  | /proc/self/stat {:5.2} % ({:.2} s CPU)",
            self.ticks_percent, self.ticks_s
        )
    }
}

/// CPU time used while `work` runs for `window`, as % of one core.
async fn cpu_percent<F, Fut>(ticks_per_s: f64, window: Duration, work: F) -> Cpu
where
    F: FnOnce(Duration) -> Fut,
    Fut: std::future::Future<Output = ()>,
{
    let t0 = Instant::now();
    let c0 = cpu_ticks();
    let n0 = cpu_ns();
    work(window).await;
    let c1 = cpu_ticks();
    let n1 = cpu_ns();
    let wall = t0.elapsed().as_secs_f64();
    let ticks_s = (c1 - c0) as f64 / ticks_per_s;
    let ns_percent = match (n0, n1) {
        (Some(a), Some(b)) if b >= a => Some(100.0 * (b - a) as f64 / 1e9 / wall),
        _ => None,
    };
    Cpu {
        ticks_percent: 100.0 * ticks_s / wall,
        ticks_s,
        ns_percent,
    }
}

async fn modbus(sim: &Simulator) -> Context {
    tcp::connect_slave(sim.modbus_addr.expect("modbus runs"), Slave(1))
        .await
        .expect("modbus connect")
}

fn words(v: f32) -> [u16; 2] {
    let b = v.to_bits();
    [(b & 0xFFFF) as u16, (b >> 16) as u16]
}

/// Starts a base-frame twist over Modbus (no watchdog: it runs until stopped).
async fn modbus_twist(ctx: &mut Context, linear: [f32; 3]) {
    let mut block = vec![3u16, 3];
    for v in [linear[0], linear[1], linear[2], 0.0, 0.0, 0.0] {
        block.extend_from_slice(&words(v));
    }
    ctx.write_single_register(200, 0).await.unwrap().unwrap();
    ctx.write_multiple_registers(202, &block)
        .await
        .unwrap()
        .unwrap();
    ctx.write_single_register(200, 1).await.unwrap().unwrap();
}

async fn talos(sim: &Simulator) -> TalosLink {
    TalosLink::connect(TalosConfig::new(sim.talos_addr.to_string()))
        .await
        .expect("talos connect")
        .0
}

async fn tcp_mm(sim: &Simulator) -> [f64; 3] {
    sim.arm
        .snapshot()
        .await
        .expect("arm")
        .tcp_position
        .map(|v| v * 1000.0)
}

fn moved_mm(a: [f64; 3], b: [f64; 3]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).powi(2))
        .sum::<f64>()
        .sqrt()
}

fn verdict(percent: f64) -> &'static str {
    if percent < TARGET_PERCENT {
        "ok"
    } else {
        "OVER TARGET"
    }
}

/// A Talos continuous polar pan (+azimuth) START refreshed every 100 ms for `window`, like a
/// held key: the operator's 500 ms watchdog never fires.
async fn refreshed_pan(link: TalosLink, window: Duration) {
    let end = Instant::now() + window;
    let mut refresh = tokio::time::interval(Duration::from_millis(100));
    while Instant::now() < end {
        refresh.tick().await;
        link.request(Request::PolarPanStart {
            moving_azimuth: 1,
            moving_altitude: 0,
        })
        .await
        .expect("START");
    }
}

fn line(label: &str, cpu: &Cpu, note: &str) {
    println!(
        "    {label:<40} {}  {:<11} {note}",
        cpu.show(),
        verdict(cpu.percent())
    );
}

async fn cpu_figures(ticks_per_s: f64) {
    println!(
        "(a) simulator CPU, {} s windows, % of one core (target < {TARGET_PERCENT} %)",
        CPU_WINDOW.as_secs()
    );
    println!("    {:<40} threads' run time (ns)", "");

    // Idle process baseline: the runtime alone, no simulator.
    let base = cpu_percent(ticks_per_s, CPU_WINDOW, tokio::time::sleep).await;
    line("runtime alone, no simulator", &base, "");

    let sim = Simulator::start(SimConfig::ephemeral())
        .await
        .expect("simulator starts");
    // Let start-up settle.
    tokio::time::sleep(Duration::from_millis(200)).await;

    let rest = cpu_percent(ticks_per_s, CPU_WINDOW, tokio::time::sleep).await;
    let snap = sim.arm.snapshot().await.expect("arm");
    assert!(!snap.moving, "at rest");
    line("at rest, no client", &rest, "");

    // A Modbus twist, started once (the Kinova arm has no twist watchdog): the simulator alone.
    let mut ctx = modbus(&sim).await;
    let before = tcp_mm(&sim).await;
    modbus_twist(&mut ctx, [0.02, 0.0, 0.0]).await;
    let twist = cpu_percent(ticks_per_s, CPU_WINDOW, tokio::time::sleep).await;
    let after = tcp_mm(&sim).await;
    let still = sim.arm.snapshot().await.expect("arm").moving;
    ctx.write_single_register(200, 2).await.unwrap().unwrap();
    drop(ctx);
    let note = format!(
        "[moved {:.0} mm, moving to the end: {still}]",
        moved_mm(before, after)
    );
    line("moving: Modbus twist 20 mm/s", &twist, &note);

    // A Talos continuous pan refreshed every 100 ms (client side included).
    let link = talos(&sim).await;
    let before = tcp_mm(&sim).await;
    let pan = cpu_percent(ticks_per_s, CPU_WINDOW, |w| refreshed_pan(link.clone(), w)).await;
    let after = tcp_mm(&sim).await;
    let still = sim.arm.snapshot().await.expect("arm").moving;
    link.request(Request::PolarPanStop).await.expect("STOP");
    let note = format!(
        "[moved {:.0} mm, moving to the end: {still}]",
        moved_mm(before, after)
    );
    line("moving: Talos pan, START at 10 Hz", &pan, &note);

    // The same while armjog's own Modbus link polls the full telemetry at its default rate (the
    // ICD's nine blocks per poll): the console's load on the simulator while jogging, client
    // side included.
    let mut config = ModbusConfig::new(sim.modbus_addr.expect("modbus runs").to_string());
    config.plan = PollPlan::IcdBlocks;
    let hz = config.poll_rate_hz.unwrap_or(0.0);
    let (poller, _events) = ModbusLink::connect(config).await.expect("modbus link");
    poller.read_telemetry().await.expect("telemetry");
    let before = tcp_mm(&sim).await;
    let polled = cpu_percent(ticks_per_s, CPU_WINDOW, |w| refreshed_pan(link.clone(), w)).await;
    let after = tcp_mm(&sim).await;
    let still = sim.arm.snapshot().await.expect("arm").moving;
    link.request(Request::PolarPanStop).await.expect("STOP");
    drop(poller);
    let note = format!(
        "[moved {:.0} mm, moving to the end: {still}]",
        moved_mm(before, after)
    );
    let label = format!("moving: as above + ModbusLink at {hz:.0} Hz");
    line(&label, &polled, &note);
}

/// Runs `clients` concurrent sequential loops of GetSpeed, each on `links[i % links.len()]`,
/// for `window`; returns requests per second and the CPU share.
async fn talos_rate(
    links: &[TalosLink],
    clients: usize,
    window: Duration,
    ticks_per_s: f64,
) -> (f64, f64) {
    let count = Arc::new(AtomicU64::new(0));
    let done = Arc::new(AtomicBool::new(false));
    // Warm-up.
    for link in links {
        link.request(Request::GetSpeed).await.expect("GetSpeed");
    }
    let c0 = cpu_ticks();
    let t0 = Instant::now();
    let tasks: Vec<_> = (0..clients)
        .map(|i| {
            let link = links[i % links.len()].clone();
            let (count, done) = (count.clone(), done.clone());
            tokio::spawn(async move {
                while !done.load(Ordering::Relaxed) {
                    link.request(Request::GetSpeed).await.expect("GetSpeed");
                    count.fetch_add(1, Ordering::Relaxed);
                }
            })
        })
        .collect();
    tokio::time::sleep(window).await;
    done.store(true, Ordering::Relaxed);
    for task in tasks {
        task.await.expect("client task");
    }
    let wall = t0.elapsed().as_secs_f64();
    let cpu = (cpu_ticks() - c0) as f64 / ticks_per_s;
    (
        count.load(Ordering::Relaxed) as f64 / wall,
        100.0 * cpu / wall,
    )
}

async fn rate_figures(ticks_per_s: f64) {
    println!(
        "(b) Talos GetSpeed request/reply on loopback, {} s each (client and server in-process)",
        RATE_WINDOW.as_secs()
    );
    let sim = Simulator::start(SimConfig::ephemeral())
        .await
        .expect("simulator starts");
    let one = vec![talos(&sim).await];
    let (rate, cpu) = talos_rate(&one, 1, RATE_WINDOW, ticks_per_s).await;
    println!("    1 link, sequential                   {rate:9.0} req/s  (process CPU {cpu:.0} %)");

    let mut eight = Vec::new();
    for _ in 0..8 {
        eight.push(talos(&sim).await);
    }
    let (rate, cpu) = talos_rate(&eight, 8, RATE_WINDOW, ticks_per_s).await;
    println!("    8 links, each sequential             {rate:9.0} req/s  (process CPU {cpu:.0} %)");

    let (rate, cpu) = talos_rate(&one, 8, RATE_WINDOW, ticks_per_s).await;
    println!("    1 link, 8 requests in flight         {rate:9.0} req/s  (process CPU {cpu:.0} %)");
}

fn main() {
    // `cargo bench` passes `--bench`; a filter argument that names neither part skips it.
    let filter: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    let wanted = |name: &str| filter.is_empty() || filter.iter().any(|f| name.contains(f));
    let (ticks_per_s, source) = clock_ticks();
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    println!(
        "sim_cost: {cores} core(s), tokio multi-thread runtime with {cores} worker(s), CLK_TCK = {ticks_per_s} ({source})"
    );
    let runtime = tokio::runtime::Runtime::new().expect("runtime");
    runtime.block_on(async {
        if wanted("cpu") {
            cpu_figures(ticks_per_s).await;
        }
        if wanted("talos_rate") {
            rate_figures(ticks_per_s).await;
        }
    });
}
