//! Two consoles on one simulated arm over the DEFAULT link shape (`armjog` with no arguments:
//! Talos jogs and pans, Modbus telemetry; see `src/cli/console.rs`): B's STOP during A's jog or
//! pan, many times over, latches A, and A's refresh overtakes it only where no telemetry can
//! show it (at most [`UNSEEN_RESTARTS_AT_MOST`] of 30; the Talos ICD cannot tell a refresh from
//! a new START); B quitting while A jogs leaves A neither jogging nor showing `JOG`.
//!
//! The two event loops run in turns of 10 ms (each takes the events that came in meanwhile),
//! as two processes would on a loaded machine. Bounds are generous for a 2-core CI.

use std::time::Duration;

use tokio::sync::mpsc::UnboundedReceiver;
use tokio::time::Instant;

use armjog::console::app::{App, Input, MotionShown};
use armjog::console::jog::KeyKind;
use armjog::console::positions::PositionBook;
use armjog::kortex::PollPlan;
use armjog::link::ModbusConfig;
use armjog::link::driver::{Driver, DriverConfig};
use armjog::link::interface::{ArmEvent, LinkStatus};
use armjog::link::talos::TalosConfig;
use armjog::sim::{SimConfig, Simulator};

use crate::event_loop::{self, Drives};

struct Console {
    app: App,
    driver: Option<Driver>,
    events: UnboundedReceiver<ArmEvent>,
}

impl Drives for Console {
    fn app(&self) -> &App {
        &self.app
    }
    fn events(&mut self) -> &mut UnboundedReceiver<ArmEvent> {
        &mut self.events
    }
    fn input(&mut self, input: Input) {
        let driver = self.driver.as_ref().expect("console running");
        event_loop::carry_out(&mut self.app, driver, input);
    }
}

impl Console {
    /// A console as `armjog` with no arguments sets one up on its built-in simulator.
    fn start(sim: &Simulator) -> Console {
        let talos = TalosConfig::new(sim.talos_addr.to_string());
        let mut modbus = ModbusConfig::new(sim.modbus_addr.expect("modbus").to_string());
        modbus.plan = PollPlan::IcdBlocks;
        let config = DriverConfig::new(Some(talos), Some(modbus));
        let app = event_loop::app_for(&config, PositionBook::new());
        let (driver, events) = Driver::spawn(config);
        Console {
            app,
            driver: Some(driver),
            events,
        }
    }

    fn message(&self) -> String {
        crate::app_support::message(&self.app)
    }
}

/// What the arm did in one turn of the bench.
#[derive(Debug, Clone, Copy)]
struct Seen {
    at: Instant,
    moving: bool,
    position: [f64; 3],
}

struct Bench {
    sim: Simulator,
    a: Console,
    b: Console,
    /// When A's held key last repeated.
    last_repeat: Instant,
}

impl Bench {
    async fn start() -> Bench {
        let sim = Simulator::start(SimConfig::ephemeral())
            .await
            .expect("simulator");
        let mut bench = Bench {
            a: Console::start(&sim),
            b: Console::start(&sim),
            sim,
            last_repeat: Instant::now(),
        };
        let until = Instant::now() + Duration::from_secs(10);
        while ![&bench.a, &bench.b]
            .iter()
            .all(|c| matches!(c.app.link(), LinkStatus::Up { .. }) && c.app.telemetry().is_some())
        {
            assert!(Instant::now() < until, "both up within 10 s");
            bench.run(Duration::from_millis(20), None).await;
        }
        bench
    }

    async fn seen(&self) -> Seen {
        let snapshot = self.sim.arm.snapshot().await.expect("sim");
        Seen {
            at: Instant::now(),
            moving: snapshot.moving,
            position: snapshot.tcp_position,
        }
    }

    /// Runs both consoles (B only while it runs) for `duration`; `a_holds` is a key A holds
    /// meanwhile (a repeat every 100 ms, as a keyboard sends). What the arm did, turn by turn.
    async fn run(&mut self, duration: Duration, a_holds: Option<&str>) -> Vec<Seen> {
        let until = Instant::now() + duration;
        let mut seen = Vec::new();
        while Instant::now() < until {
            self.a.run_for(Duration::from_millis(10)).await;
            if self.b.driver.is_some() {
                self.b.run_for(Duration::from_millis(10)).await;
            } else {
                tokio::time::sleep(Duration::from_millis(10)).await;
            }
            if let Some(key) = a_holds
                && self.last_repeat.elapsed() >= Duration::from_millis(100)
            {
                self.a.key(key, KeyKind::Repeat);
                self.last_repeat = Instant::now();
            }
            seen.push(self.seen().await);
        }
        seen
    }

    /// Runs until the arm has stood still for 300 ms (at most 5 s).
    async fn settle(&mut self) {
        let until = Instant::now() + Duration::from_secs(5);
        let mut still_since = Instant::now();
        while Instant::now() - still_since < Duration::from_millis(300) {
            assert!(Instant::now() < until, "the arm stands within 5 s");
            if self
                .run(Duration::from_millis(20), None)
                .await
                .iter()
                .any(|s| s.moving)
            {
                still_since = Instant::now();
            }
        }
    }
}

/// Path length over `seen`, mm.
fn travel_mm(seen: &[Seen]) -> f64 {
    seen.windows(2)
        .map(|w| {
            let d: f64 = (0..3)
                .map(|i| (w[1].position[i] - w[0].position[i]).powi(2))
                .sum();
            d.sqrt() * 1000.0
        })
        .sum()
}

/// Travel after B's STOP that is a restart, mm: B's STOP stops the simulated arm at once, and
/// 20 mm is 160 ms of A's 125 mm/s jog (a restarted jog runs on until A notices or lets go).
const RESTART_MM: f64 = 20.0;

/// Restarts of 30 the console cannot see (see `repeated`): a bound, not the goal of 0.
const UNSEEN_RESTARTS_AT_MOST: usize = 6;

/// One trial's figures.
#[derive(Debug)]
struct Trial {
    /// From B's STOP to A's own stop and latch.
    a_confirmed_after: Option<Duration>,
    /// The arm's travel from B's STOP until A confirmed, mm.
    before_confirm_mm: f64,
    /// The arm's travel from A's confirmation to the trial's end (1.5 s after B's STOP), mm.
    after_confirm_mm: f64,
    /// More than [`RESTART_MM`] of travel after B's STOP, the arm moving 1 s or more after it, or
    /// A still jogging at the end: a restart.
    restarted: bool,
}

/// A holds `key` for `hold`; B presses space; A keeps holding it for 1.5 s.
async fn b_stops_a(bench: &mut Bench, key: &str, hold: Duration) -> Trial {
    bench.a.key(key, KeyKind::Press);
    bench.last_repeat = Instant::now();
    bench.run(hold, Some(key)).await;
    assert!(bench.seen().await.moving, "{key}: A's jog moves the arm");
    assert!(
        bench.a.app.jog().is_jogging(),
        "{key}: {}",
        bench.a.message()
    );
    let stop_at = Instant::now();
    let mut seen = vec![bench.seen().await];
    bench.b.key("space", KeyKind::Press);
    bench.b.key("space", KeyKind::Release);
    let mut confirmed = None;
    while Instant::now() - stop_at < Duration::from_millis(1500) {
        seen.extend(bench.run(Duration::from_millis(20), Some(key)).await);
        if confirmed.is_none() && !bench.a.app.jog().is_jogging() {
            confirmed = Some((Instant::now(), seen.len() - 1));
        }
    }
    let late = seen
        .iter()
        .any(|s| s.moving && s.at - stop_at >= Duration::from_secs(1));
    let split = confirmed.map_or(seen.len() - 1, |(_, i)| i);
    let trial = Trial {
        a_confirmed_after: confirmed.map(|(at, _)| at - stop_at),
        before_confirm_mm: travel_mm(&seen[..=split]),
        after_confirm_mm: travel_mm(&seen[split..]),
        restarted: late || bench.a.app.jog().is_jogging() || travel_mm(&seen) > RESTART_MM,
    };
    if trial.restarted || confirmed.is_none() {
        eprintln!("{key}: {trial:?}; A says: {}", bench.a.message());
    }
    bench.a.key(key, KeyKind::Release);
    bench.settle().await;
    trial
}

/// B's STOP during A's hold of `keys` (taken in turn, so the arm goes back and forth),
/// `trials` times, B's STOP at a different point of A's 100 ms refresh each time.
async fn repeated(keys: [&str; 2], trials: u32) {
    let mut bench = Bench::start().await;
    let mut results = Vec::new();
    for n in 0..trials {
        let key = keys[n as usize % 2];
        // 700-799 ms: past the 500 ms grace, at every phase of the refresh.
        let hold = Duration::from_millis(700 + u64::from(n * 37 % 100));
        results.push(b_stops_a(&mut bench, key, hold).await);
    }
    let restarts = results.iter().filter(|t| t.restarted).count();
    let unconfirmed = results
        .iter()
        .filter(|t| t.a_confirmed_after.is_none())
        .count();
    let confirm_ms: Vec<u128> = results
        .iter()
        .filter_map(|t| t.a_confirmed_after.map(|d| d.as_millis()))
        .collect();
    let worst_after = results
        .iter()
        .map(|t| t.after_confirm_mm)
        .fold(0.0, f64::max);
    let over_1mm = results.iter().filter(|t| t.after_confirm_mm > 1.0).count();
    let worst_before = results
        .iter()
        .map(|t| t.before_confirm_mm)
        .fold(0.0, f64::max);
    eprintln!(
        "{keys:?} x{trials}: {restarts} restarts, {unconfirmed} not confirmed by A; A confirmed \
         after {:?} ms (min {:?}, max {:?}); travel after A confirmed: {over_1mm} trials over \
         1 mm, worst {worst_after:.2} mm; travel from B's STOP to A's confirmation worst \
         {worst_before:.1} mm",
        confirm_ms,
        confirm_ms.iter().min(),
        confirm_ms.iter().max(),
    );
    // A bound, not 0: the simulated arm stops and restarts at once, so a STOP that reaches it
    // in the few ms between the sample A's refresh goes out on and the refresh leaves A no
    // trace; B's held STOP (sent again while B sees the arm move) catches it, but a restart
    // caught late may still travel past RESTART_MM on a loaded machine. Measured: 0 of 30 with
    // the hold, 0-3 of 30 without it, 6 of 30 before refreshes waited for telemetry.
    assert!(
        restarts <= UNSEEN_RESTARTS_AT_MOST,
        "{keys:?}: A's refresh restarted the arm {restarts} times"
    );
    assert!(
        unconfirmed <= restarts,
        "{keys:?}: A saw every stop it could see"
    );
    assert_eq!(over_1mm, 0, "{keys:?}: the arm moved on after A confirmed");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn b_s_stop_during_a_s_jog_latches_a_and_is_rarely_overtaken_by_its_refresh_30_trials() {
    repeated(["a", "d"], 30).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn b_s_stop_during_a_s_pan_latches_a_and_is_rarely_overtaken_by_its_refresh_30_trials() {
    repeated(["right", "left"], 30).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn b_quitting_while_a_jogs_leaves_a_neither_jogging_nor_showing_jog() {
    let mut bench = Bench::start().await;
    bench.a.key("a", KeyKind::Press);
    bench.run(Duration::from_millis(800), Some("a")).await;
    assert!(bench.a.app.jog().is_jogging());
    // B quits as the console does: STOP and gone (its connections close).
    bench.b.key("q", KeyKind::Press);
    let b_driver = bench.b.driver.take().expect("B runs");
    b_driver.shutdown().await;
    let seen = bench.run(Duration::from_millis(2000), Some("a")).await;
    let late = seen.iter().rfind(|s| s.moving).map(|s| s.at);
    eprintln!(
        "B quit: the arm last seen moving {:?} after; A says: {}",
        late.map(|at| at - seen[0].at),
        bench.a.message()
    );
    assert!(!seen.last().expect("turns").moving, "the arm stands");
    assert!(!bench.a.app.jog().is_jogging(), "A's key is latched");
    assert!(
        !matches!(bench.a.app.motion_shown(), MotionShown::Jog(_)),
        "A shows what it sees: {:?}",
        bench.a.app.motion_shown()
    );
    assert!(
        bench.a.message().contains("stopped by another client"),
        "{}",
        bench.a.message()
    );
}
