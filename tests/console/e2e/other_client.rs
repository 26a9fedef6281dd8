//! Two consoles on one simulated arm, end to end over real sockets (each its own state machine
//! and arm driver, over Modbus): B's STOP stops A's jog or pan, A's held key is latched (its
//! next refresh does not restart the arm) and A says `stopped by another client`; B's motion
//! while A is idle is `MOVED BY ANOTHER CLIENT` on A's screen.
//!
//! The two event loops run in turns of 10 ms (each takes the events that came in meanwhile),
//! as two processes would on a loaded machine. Bounds are generous for a 2-core CI.

use std::time::Duration;

use tokio::sync::mpsc::UnboundedReceiver;

use armjog::console::app::{App, Input, MotionShown};
use armjog::console::jog::KeyKind;
use armjog::console::positions::PositionBook;
use armjog::link::ModbusConfig;
use armjog::link::driver::{Driver, DriverConfig};
use armjog::link::interface::{ArmEvent, LinkStatus};
use armjog::sim::{SimConfig, Simulator};

use crate::event_loop::{self, Drives};

struct Console {
    app: App,
    driver: Driver,
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
        event_loop::carry_out(&mut self.app, &self.driver, input);
    }
}

impl Console {
    fn start(sim: &Simulator) -> Console {
        let modbus = ModbusConfig::new(sim.modbus_addr.expect("modbus").to_string());
        let config = DriverConfig::new(None, Some(modbus));
        let app = event_loop::app_for(&config, PositionBook::new());
        let (driver, events) = Driver::spawn(config);
        Console {
            app,
            driver,
            events,
        }
    }

    fn message(&self) -> String {
        crate::app_support::message(&self.app)
    }
}

/// The arm and both consoles.
struct Bench {
    sim: Simulator,
    a: Console,
    b: Console,
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
        };
        let until = tokio::time::Instant::now() + Duration::from_secs(10);
        while ![&bench.a, &bench.b]
            .iter()
            .all(|c| matches!(c.app.link(), LinkStatus::Up { .. }) && c.app.telemetry().is_some())
        {
            assert!(tokio::time::Instant::now() < until, "both up within 10 s");
            bench.run(Duration::from_millis(20), None).await;
        }
        bench
    }

    /// Runs both consoles for `duration`; `a_holds` is a key A holds meanwhile (a repeat every
    /// 100 ms, as a keyboard sends). Returns how long the arm was seen moving.
    async fn run(&mut self, duration: Duration, a_holds: Option<&str>) -> Duration {
        let until = tokio::time::Instant::now() + duration;
        let mut last_repeat = tokio::time::Instant::now();
        let mut moving = Duration::ZERO;
        while tokio::time::Instant::now() < until {
            self.a.run_for(Duration::from_millis(10)).await;
            self.b.run_for(Duration::from_millis(10)).await;
            if let Some(key) = a_holds
                && last_repeat.elapsed() >= Duration::from_millis(100)
            {
                self.a.key(key, KeyKind::Repeat);
                last_repeat = tokio::time::Instant::now();
            }
            if self.sim.arm.snapshot().await.expect("sim").moving {
                moving += Duration::from_millis(20);
            }
        }
        moving
    }

    async fn moving(&self) -> bool {
        self.sim.arm.snapshot().await.expect("sim").moving
    }
}

/// A holds `key`; B presses space. A's jog stops and stays stopped while A still holds it.
async fn b_stops_a(key: &str) {
    let mut bench = Bench::start().await;
    bench.a.key(key, KeyKind::Press);
    bench.run(Duration::from_millis(1000), Some(key)).await;
    assert!(bench.moving().await, "{key}: A's jog moves the arm");
    assert!(bench.a.app.jog().is_jogging());

    bench.b.key("space", KeyKind::Press);
    bench.b.key("space", KeyKind::Release);
    // A keeps holding its key: its refreshes and repeats go on.
    let settle = bench.run(Duration::from_millis(1000), Some(key)).await;
    let after = bench.run(Duration::from_millis(2000), Some(key)).await;
    eprintln!(
        "{key}: after B's STOP the arm was seen moving {settle:?} in the first second and \
         {after:?} in the next two; A says: {}",
        bench.a.message()
    );
    assert_eq!(
        after,
        Duration::ZERO,
        "{key}: A's refresh restarted the arm"
    );
    assert!(!bench.moving().await, "{key}");
    assert!(!bench.a.app.jog().is_jogging(), "{key}: A's key is latched");
    assert!(
        !matches!(bench.a.app.motion_shown(), MotionShown::Jog(_)),
        "{key}: A shows what it sees, not the jog it sent"
    );
    assert!(
        bench.a.message().contains("stopped by another client"),
        "{key}: {}",
        bench.a.message()
    );
    // Released and pressed anew, A moves again.
    bench.a.key(key, KeyKind::Release);
    bench.run(Duration::from_millis(200), None).await;
    bench.a.key(key, KeyKind::Press);
    let moved = bench.run(Duration::from_millis(800), Some(key)).await;
    assert!(moved > Duration::ZERO, "{key}: a new press moves");
    bench.a.key(key, KeyKind::Release);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn b_s_stop_latches_a_s_jog_and_a_does_not_restart_on_its_refresh() {
    b_stops_a("a").await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn b_s_stop_latches_a_s_pan_whose_twist_is_rewritten_every_poll() {
    b_stops_a("right").await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn b_s_jog_while_a_is_idle_is_moved_by_another_client_on_a_s_screen() {
    let mut bench = Bench::start().await;
    bench.run(Duration::from_millis(300), None).await;
    assert_eq!(bench.a.app.motion_shown(), MotionShown::Idle);
    bench.b.key("r", KeyKind::Press);
    let until = tokio::time::Instant::now() + Duration::from_secs(5);
    while bench.a.app.motion_shown() != MotionShown::MovedByAnotherClient {
        assert!(
            tokio::time::Instant::now() < until,
            "A shows {:?}",
            bench.a.app.motion_shown()
        );
        bench.run(Duration::from_millis(20), None).await;
        bench.b.key("r", KeyKind::Repeat);
    }
    let status = event_loop::status_line(&armjog::console::view::View::new(&bench.a.app));
    assert!(status.contains("MOVED BY ANOTHER CLIENT"), "{status}");
    assert!(!status.contains(" idle "), "{status}");
    bench.b.key("r", KeyKind::Release);
    // B's release stops the arm: A is idle again.
    let until = tokio::time::Instant::now() + Duration::from_secs(5);
    while bench.a.app.motion_shown() != MotionShown::Idle {
        assert!(tokio::time::Instant::now() < until, "A idle again");
        bench.run(Duration::from_millis(20), None).await;
    }
}
