//! End to end over real sockets: the console's state machine and arm driver against the
//! in-process simulator over Modbus. Holding an orientation key turns the tool about its point
//! (the point stays within 3 mm) and the release stops it.

use std::time::{Duration, Instant};

use nalgebra::Rotation3;
use tokio::sync::mpsc::UnboundedReceiver;

use armjog::console::app::{App, Input};
use armjog::console::jog::KeyKind;
use armjog::console::positions::PositionBook;
use armjog::link::ModbusConfig;
use armjog::link::driver::{Driver, DriverConfig};
use armjog::link::interface::{ArmEvent, LinkStatus};
use armjog::sim::arm_model::ArmSnapshot;
use armjog::sim::{SimConfig, Simulator};

use crate::event_loop::{self, Drives};

/// Generous for a loaded 2-core CI: the STOP itself takes well under a millisecond.
const STOP_BOUND: Duration = Duration::from_secs(2);

struct Console {
    app: App,
    driver: Driver,
    events: UnboundedReceiver<ArmEvent>,
    sim: Simulator,
}

impl event_loop::Drives for Console {
    fn app(&self) -> &App {
        &self.app
    }
    fn events(&mut self) -> &mut UnboundedReceiver<ArmEvent> {
        &mut self.events
    }
    fn input(&mut self, input: Input) {
        Console::input(self, input);
    }
}

impl Console {
    async fn start() -> Console {
        let sim = Simulator::start(SimConfig::ephemeral())
            .await
            .expect("simulator");
        let modbus = ModbusConfig::new(sim.modbus_addr.expect("modbus").to_string());
        let config = DriverConfig::new(None, Some(modbus));
        let app = event_loop::app_for(&config, PositionBook::new());
        let (driver, events) = Driver::spawn(config);
        let mut console = Console {
            app,
            driver,
            events,
            sim,
        };
        let until = tokio::time::Instant::now() + Duration::from_secs(10);
        while !(matches!(console.app.link(), LinkStatus::Up { .. })
            && console.app.telemetry().is_some())
        {
            assert!(tokio::time::Instant::now() < until, "link up within 10 s");
            console.run_for(Duration::from_millis(10)).await;
        }
        console
    }

    fn input(&mut self, input: Input) {
        event_loop::carry_out(&mut self.app, &self.driver, input);
    }

    async fn snapshot(&self) -> ArmSnapshot {
        self.sim.arm.snapshot().await.expect("sim")
    }
}

/// The tool's orientation from the simulator's extrinsic XYZ Euler angles (deg).
fn rotation(s: &ArmSnapshot) -> Rotation3<f64> {
    let [x, y, z] = s.tcp_orientation.map(f64::to_radians);
    Rotation3::from_euler_angles(x, y, z)
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn holding_the_rx_key_turns_the_tool_about_its_point_and_the_release_stops_it() {
    let mut console = Console::start().await;
    let before = console.snapshot().await;
    console.key("i", KeyKind::Press);
    // About a second of the keyboard's auto-repeat (with release events a hold keeps proving
    // itself), watching the tool point all along.
    let mut strayed: f64 = 0.0;
    let until = Instant::now() + Duration::from_millis(1000);
    while Instant::now() < until {
        console.run_for(Duration::from_millis(33)).await;
        console.key("i", KeyKind::Repeat);
        let now = console.snapshot().await;
        strayed = strayed.max(distance(now.tcp_position, before.tcp_position));
    }
    assert!(console.snapshot().await.moving, "turning while held");
    console.key("i", KeyKind::Release);
    let stop_by = tokio::time::Instant::now() + STOP_BOUND;
    while console.snapshot().await.moving {
        assert!(
            tokio::time::Instant::now() < stop_by,
            "stopped within {STOP_BOUND:?} of the release"
        );
        console.run_for(Duration::from_millis(2)).await;
    }
    let after = console.snapshot().await;
    strayed = strayed.max(distance(after.tcp_position, before.tcp_position));
    assert!(
        strayed <= 0.003,
        "the tool point moved {:.2} mm",
        strayed * 1e3
    );
    // At 50 % (15 deg/s) for about a second, about +X of the base frame.
    let turn = rotation(&after) * rotation(&before).inverse();
    let (axis, angle) = turn.axis_angle().expect("the tool turned");
    let degrees = angle.to_degrees();
    eprintln!(
        "turned {degrees:.1} deg about {axis:?}; the tool point strayed {:.3} mm",
        strayed * 1e3
    );
    assert!(
        (5.0..=40.0).contains(&degrees),
        "turned {degrees:.1} deg in about a second at 15 deg/s"
    );
    assert!(axis.x > 0.98, "turned about {axis:?}, not +X");
    // And it stays stopped: no refresh restarts it.
    console.run_for(Duration::from_millis(300)).await;
    assert!(!console.snapshot().await.moving, "still after the release");
    console.driver.shutdown().await;
}
