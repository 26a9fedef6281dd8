//! One speed cap, enforced by command and by watching, end to end: the console (state machine
//! and arm driver) jogs through Talos with telemetry over Modbus, against a simulator whose
//! operator runs 500 mm/s at its 100 %, over real sockets. Told the operator's full speed, the
//! console's Set Speed keeps the tool under its 50 mm/s cap; told a wrong one, the operator
//! runs over the cap and the watch stops the jog and says why.
//!
//! Speeds are the telemetry's (the tool twist the Modbus server reports), as the console sees
//! them; the bounds are generous for a loaded 2-core CI.

use std::time::Duration;

use tokio::sync::mpsc::UnboundedReceiver;

use armjog::console::app::{App, Input};
use armjog::console::jog::KeyKind;
use armjog::console::positions::PositionBook;
use armjog::link::driver::{Driver, DriverConfig};
use armjog::link::interface::{ArmCommand, ArmEvent, LinkStatus};
use armjog::link::{ModbusConfig, TalosConfig};
use armjog::sim::{SimConfig, Simulator};

use crate::event_loop::{self, Drives};

/// The console's cap, m/s.
const CAP: f64 = 0.05;
/// The simulated operator's 100 %, m/s.
const OPERATOR_FULL: f64 = 0.5;

struct Console {
    app: App,
    driver: Driver,
    events: UnboundedReceiver<ArmEvent>,
    sim: Simulator,
    /// The highest tool speed the telemetry reported, mm/s.
    peak_mm_s: f64,
}

impl Drives for Console {
    fn app(&self) -> &App {
        &self.app
    }
    fn events(&mut self) -> &mut UnboundedReceiver<ArmEvent> {
        &mut self.events
    }
    fn input(&mut self, input: Input) {
        if let Input::Arm(ArmEvent::Telemetry(t)) = &input {
            let v = &t.tcp.twist;
            let mm_s = f64::from(v.x.hypot(v.y).hypot(v.z)) * 1000.0;
            if mm_s.is_finite() {
                self.peak_mm_s = self.peak_mm_s.max(mm_s);
            }
        }
        event_loop::carry_out(&mut self.app, &self.driver, input);
    }
}

impl Console {
    /// A console with a 50 mm/s cap that believes the operator's 100 % is
    /// `operator_full_speed`, at 100 % speed.
    async fn start(operator_full_speed: f64) -> Console {
        let sim = Simulator::start(SimConfig {
            max_jog_speed: OPERATOR_FULL,
            ..SimConfig::ephemeral()
        })
        .await
        .expect("simulator");
        let talos = TalosConfig::new(sim.talos_addr.to_string());
        let modbus = ModbusConfig::new(sim.modbus_addr.expect("modbus").to_string());
        let mut config = DriverConfig::new(Some(talos), Some(modbus));
        config.max_jog_speed = CAP;
        config.operator_full_speed = operator_full_speed;
        let app = event_loop::app_for(&config, PositionBook::new());
        let (driver, events) = Driver::spawn(config);
        let mut console = Console {
            app,
            driver,
            events,
            sim,
            peak_mm_s: 0.0,
        };
        console
            .run_until(Duration::from_secs(10), |c| {
                matches!(c.app.link(), LinkStatus::Up { .. }) && c.app.telemetry().is_some()
            })
            .await;
        assert!(console.driver.send(ArmCommand::SetSpeed(100)));
        console
            .run_until(Duration::from_secs(10), |c| c.app.speed() == Some(100))
            .await;
        console
    }

    /// Holds `key` for up to `seconds` (a repeat every 100 ms, as a keyboard sends), or until
    /// the jog stops by itself; then releases it and waits for the arm to stand.
    async fn hold(&mut self, key: &str, seconds: f64) {
        self.key(key, KeyKind::Press);
        let until = tokio::time::Instant::now() + Duration::from_secs_f64(seconds);
        while tokio::time::Instant::now() < until && self.app.jog().is_jogging() {
            self.run_for(Duration::from_millis(100)).await;
            self.key(key, KeyKind::Repeat);
        }
        self.key(key, KeyKind::Release);
        let rest = tokio::time::Instant::now() + Duration::from_secs(5);
        while self.sim.arm.snapshot().await.expect("sim").moving {
            assert!(tokio::time::Instant::now() < rest, "still moving 5 s on");
            self.run_for(Duration::from_millis(20)).await;
        }
    }

    fn message(&self) -> String {
        crate::app_support::message(&self.app)
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn told_the_operators_full_speed_the_tool_stays_under_the_cap() {
    for (key, what) in [("w", "cartesian"), ("right", "polar")] {
        let mut console = Console::start(OPERATOR_FULL).await;
        console.hold(key, 2.0).await;
        eprintln!(
            "{what} jog, cap 50 mm/s, operator 500 mm/s told 500: peak {:.1} mm/s",
            console.peak_mm_s
        );
        assert!(
            console.peak_mm_s < 55.0,
            "{what}: {:.1} mm/s over the 50 mm/s cap",
            console.peak_mm_s
        );
        // It did move (not refused). A polar pan turns at the operator's angular rate times the
        // speed, under the cap at this reach.
        assert!(
            console.peak_mm_s > 10.0,
            "{what}: only {:.1} mm/s",
            console.peak_mm_s
        );
        assert_eq!(console.app.cap_watch().stops().0, 0, "{what}");
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn told_a_wrong_full_speed_the_watch_stops_the_jog_and_names_the_option() {
    // Told 250 mm/s, 100 % of the cap goes out as 20 %: a cartesian jog at 100 mm/s on this
    // operator. Its polar pan at 20 % stays under the cap (its angular rate is scaled too), so
    // the polar case is told 100 mm/s: 50 %, a pan well over the cap.
    for (key, what, told) in [("w", "cartesian", 0.25), ("right", "polar", 0.1)] {
        let mut console = Console::start(told).await;
        console.hold(key, 5.0).await;
        eprintln!(
            "{what} jog, cap 50 mm/s, operator 500 mm/s told {:.0}: peak {:.1} mm/s, then: {}",
            told * 1000.0,
            console.peak_mm_s,
            console.message()
        );
        assert_eq!(console.app.cap_watch().stops().0, 1, "{what}");
        let message = console.message();
        assert!(
            message.contains("over the 50 mm/s cap") && message.contains("--operator-full-speed"),
            "{what}: {message}"
        );
        assert!(console.peak_mm_s > 55.0, "{what}: {:.1}", console.peak_mm_s);
    }
}
