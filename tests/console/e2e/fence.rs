//! The fence end to end: the console's state machine and the arm driver over each link against
//! the simulator, a table zone under the tool. The tool is read from the simulator, not the screen.

use std::time::{Duration, Instant};

use tokio::sync::mpsc::UnboundedReceiver;

use armjog::console::app::{App, Input, QUESTION_QUIET};
use armjog::console::jog::KeyKind;
use armjog::console::positions::PositionBook;
use armjog::console::view::View;
use armjog::link::driver::{Driver, DriverConfig};
use armjog::link::fence::{Aabb, Fence, KeepOut};
use armjog::link::interface::{ArmEvent, LinkStatus};
use armjog::link::{Dialect, ModbusConfig, TalosConfig};
use armjog::sim::{SimConfig, Simulator};

use crate::event_loop::{self, Drives};

/// The tool sphere's radius in these tests, mm.
const RADIUS: f64 = 40.0;

struct Console {
    app: App,
    driver: Driver,
    events: UnboundedReceiver<ArmEvent>,
    sim: Simulator,
    /// Every message shown, in order.
    said: Vec<String>,
    /// The keys held: the terminal repeats them while held, as kitty's protocol does.
    held: Vec<String>,
    /// When the held keys were last repeated.
    repeated: tokio::time::Instant,
}

#[derive(Clone, Copy, Debug)]
enum Links {
    Talos,
    Modbus,
    /// The ack dialect with no Modbus: no telemetry at all.
    AckOnly,
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
        if let Some((text, _)) = self.app.message()
            && self.said.last().map(String::as_str) != Some(text)
        {
            self.said.push(text.to_string());
        }
    }
}

/// A table whose top is `gap` mm under the tool point, 600 mm square about it.
fn table_under(tool_mm: [f64; 3], gap: f64) -> Fence {
    let [x, y, z] = tool_mm;
    Fence {
        tool_radius: RADIUS,
        keep_out: vec![KeepOut {
            name: "table".into(),
            zone: Aabb {
                min: [x - 300.0, y - 300.0, z - gap - 200.0],
                max: [x + 300.0, y + 300.0, z - gap],
            },
            enabled: true,
        }],
        ..Fence::default()
    }
}

impl Console {
    /// A console with the fence `fence_at` makes of the tool point (mm) the simulator starts at.
    async fn start(links: Links, fence_at: impl FnOnce([f64; 3]) -> Fence) -> Console {
        let mut sim_config = SimConfig::ephemeral();
        if matches!(links, Links::AckOnly) {
            sim_config.talos.dialect = Dialect::Ack;
        }
        let sim = Simulator::start(sim_config).await.expect("simulator");
        let tool = sim.arm.snapshot().await.expect("sim").tcp_position;
        let fence = fence_at(tool.map(|m| m * 1000.0));
        let talos = TalosConfig::new(sim.talos_addr.to_string());
        let modbus = sim.modbus_addr.map(|a| ModbusConfig::new(a.to_string()));
        let config = match links {
            Links::Talos => DriverConfig::new(Some(talos), None),
            Links::Modbus => DriverConfig::new(None, modbus),
            Links::AckOnly => DriverConfig::new(
                Some(TalosConfig {
                    dialect: Dialect::Ack,
                    ..talos
                }),
                None,
            ),
        };
        let app = event_loop::app_fenced(&config, PositionBook::new(), Some(fence));
        let (driver, events) = Driver::spawn(config);
        let mut console = Console {
            app,
            driver,
            events,
            sim,
            said: Vec::new(),
            held: Vec::new(),
            repeated: tokio::time::Instant::now(),
        };
        let telemetry = !matches!(links, Links::AckOnly);
        console
            .run_until(Duration::from_secs(10), |c| {
                matches!(c.app.link(), LinkStatus::Up { .. })
                    && (c.app.telemetry().is_some() || !telemetry)
            })
            .await;
        console
    }

    fn key(&mut self, name: &str, kind: KeyKind) {
        match kind {
            KeyKind::Press => self.held.push(name.to_string()),
            KeyKind::Release => self.held.retain(|k| k != name),
            KeyKind::Repeat => {}
        }
        Drives::key(self, name, kind);
    }

    async fn tool_mm(&self) -> [f64; 3] {
        let tool = self.sim.arm.snapshot().await.expect("sim").tcp_position;
        tool.map(|m| m * 1000.0)
    }

    /// Runs the loop for `duration`, reading the simulator's tool every few milliseconds; the
    /// lowest z seen and the last tool point.
    async fn watch_for(&mut self, duration: Duration) -> (f64, [f64; 3]) {
        let until = tokio::time::Instant::now() + duration;
        let mut lowest = f64::INFINITY;
        let mut last = self.tool_mm().await;
        while tokio::time::Instant::now() < until {
            self.run_for(Duration::from_millis(3)).await;
            if self.repeated.elapsed() >= Duration::from_millis(50) {
                self.repeated = tokio::time::Instant::now();
                for key in self.held.clone() {
                    Drives::key(self, &key, KeyKind::Repeat);
                }
            }
            last = self.tool_mm().await;
            lowest = lowest.min(last[2]);
        }
        (lowest, last)
    }

    fn status(&self) -> String {
        event_loop::status_line(&View::new(&self.app))
    }
}

/// Criteria 1 and 2 on one link: down onto the table, then along it.
async fn down_onto_the_table_and_along_it(links: Links) {
    let mut console = Console::start(links, |tool| table_under(tool, 150.0)).await;
    let start = console.tool_mm().await;
    let top = start[2] - 150.0;
    console.key("f", KeyKind::Press);
    // 110 mm of clearance at 125 mm/s, the last 60 slowing to 12.5 mm/s: under 2.5 s.
    let (lowest, at_rest) = console.watch_for(Duration::from_secs(4)).await;
    let status = console.status();
    assert!(
        lowest - RADIUS >= top - 0.01,
        "{links:?}: the sphere entered the table: lowest {lowest:.2} mm, top {top:.2} + radius"
    );
    let gap = at_rest[2] - RADIUS - top;
    assert!(
        gap <= 2.0,
        "{links:?}: stopped {gap:.2} mm above the table; said {:?}",
        console.said
    );
    assert!(status.contains("AT FENCE: table"), "{links:?}: {status}");
    assert!(
        !console.sim.arm.snapshot().await.expect("sim").moving,
        "{links:?}: still moving at the fence"
    );

    // Holding -Z still, +X as well: the tool slides along the table.
    console.key("w", KeyKind::Press);
    let (lowest, slid) = console.watch_for(Duration::from_millis(800)).await;
    console.key("w", KeyKind::Release);
    console.key("f", KeyKind::Release);
    assert!(
        slid[0] - at_rest[0] > 20.0,
        "{links:?}: x {:.1} -> {:.1} mm",
        at_rest[0],
        slid[0]
    );
    assert!(
        (slid[2] - at_rest[2]).abs() <= 1.0 && lowest - RADIUS >= top - 0.01,
        "{links:?}: z {:.2} -> {:.2} (lowest {lowest:.2}) mm",
        at_rest[2],
        slid[2]
    );
    console.driver.shutdown().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn held_down_over_talos_the_tool_stops_above_the_table_and_slides_along_it() {
    down_onto_the_table_and_along_it(Links::Talos).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn held_down_over_modbus_the_tool_stops_above_the_table_and_slides_along_it() {
    down_onto_the_table_and_along_it(Links::Modbus).await;
}

/// Criterion 3: a go-to whose target is in the table, and over Modbus a straight move through it.
async fn go_to_into_the_table_is_refused(links: Links, target: impl Fn([f64; 3]) -> [f64; 3]) {
    let mut console = Console::start(links, |tool| table_under(tool, 150.0)).await;
    let start = console.tool_mm().await;
    let tenths = target(start).map(|mm| (mm * 10.0).round() as i32);
    let mut book = PositionBook::new();
    book.get_or_insert("under").cartesian = Some(tenths);
    console
        .app
        .handle(Input::PositionsLoaded(Ok(book)), Instant::now());
    console.key("o", KeyKind::Press);
    console
        .run_for(QUESTION_QUIET + Duration::from_millis(20))
        .await;
    console.key("y", KeyKind::Press);
    console.run_for(Duration::from_millis(600)).await;
    let end = console.tool_mm().await;
    let moved = (0..3)
        .map(|i| (end[i] - start[i]).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!(moved < 0.05, "{links:?}: moved {moved:.2} mm");
    assert!(
        console
            .said
            .iter()
            .any(|s| s.contains("refused") && s.contains("table")),
        "{links:?}: {:?}",
        console.said
    );
    console.driver.shutdown().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_go_to_inside_the_table_is_refused_over_both_links() {
    let inside = |s: [f64; 3]| [s[0], s[1], s[2] - 200.0];
    go_to_into_the_table_is_refused(Links::Talos, inside).await;
    go_to_into_the_table_is_refused(Links::Modbus, inside).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_straight_move_through_the_table_is_refused_over_modbus() {
    // Under the table's far side: clear of it there, but the straight line passes through it.
    let through = |s: [f64; 3]| [s[0] + 400.0, s[1], s[2] - 250.0];
    go_to_into_the_table_is_refused(Links::Modbus, through).await;
}

/// Criterion 5: a fence taught around the tool; deeper refused, out at the slow speed.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn inside_a_zone_deeper_is_refused_and_out_goes_at_the_slow_speed() {
    // The table's top 30 mm above the tool point: the sphere is 70 mm in.
    let mut console = Console::start(Links::Modbus, |tool| table_under(tool, -30.0)).await;
    console.run_for(Duration::from_millis(200)).await;
    assert!(
        console.status().contains("OUTSIDE FENCE: table, 70 mm in"),
        "{}",
        console.status()
    );
    let start = console.tool_mm().await;
    console.key("f", KeyKind::Press);
    let (_, deeper) = console.watch_for(Duration::from_millis(500)).await;
    console.key("f", KeyKind::Release);
    assert!(
        (deeper[2] - start[2]).abs() < 0.05,
        "deeper moved {:.2} mm",
        deeper[2] - start[2]
    );
    console.run_for(Duration::from_millis(200)).await;
    console.key("r", KeyKind::Press);
    let (_, out) = console.watch_for(Duration::from_millis(1000)).await;
    console.key("r", KeyKind::Release);
    let rose = out[2] - deeper[2];
    // 10 % of 125 mm/s for a second, less the start: well under the 125 mm unslowed.
    assert!((3.0..=20.0).contains(&rose), "rose {rose:.1} mm in 1 s");
    console.driver.shutdown().await;
}

/// Criterion 7: no telemetry (the ack dialect, no Modbus): motion refused with the reason.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn with_a_fence_and_no_telemetry_motion_is_refused_with_the_reason() {
    let mut console = Console::start(Links::AckOnly, |tool| table_under(tool, 150.0)).await;
    console.run_for(Duration::from_millis(300)).await;
    let start = console.tool_mm().await;
    console.key("f", KeyKind::Press);
    console.watch_for(Duration::from_millis(400)).await;
    console.key("f", KeyKind::Release);
    let end = console.tool_mm().await;
    assert!(
        (end[2] - start[2]).abs() < 0.05,
        "moved {:?} -> {:?}",
        start,
        end
    );
    assert!(
        console
            .said
            .iter()
            .any(|s| s.contains("the fence needs telemetry")),
        "{:?} {}",
        console.said,
        console.status()
    );
    console.driver.shutdown().await;
}

/// Criterion 4: a joint jog toward a soft limit stops within 1° of it (over Talos: Modbus has no
/// joint jog).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_joint_jog_toward_a_soft_limit_stops_within_a_degree_of_it() {
    let mut console = Console::start(Links::Talos, |_| {
        let mut joints = [None; 7];
        // J2 starts at 15 degrees (home).
        joints[1] = Some([-120.0, 30.0]);
        Fence {
            joints,
            ..Fence::default()
        }
    })
    .await;
    let j2 = |s: &armjog::sim::arm_model::ArmSnapshot| {
        let deg = s.joint_position[1].rem_euclid(360.0);
        if deg > 180.0 { deg - 360.0 } else { deg }
    };
    console.key("]", KeyKind::Press);
    console.key("]", KeyKind::Release);
    console.key("k", KeyKind::Press);
    let until = tokio::time::Instant::now() + Duration::from_secs(6);
    let mut highest = f64::NEG_INFINITY;
    while tokio::time::Instant::now() < until {
        console.watch_for(Duration::from_millis(20)).await;
        highest = highest.max(j2(&console.sim.arm.snapshot().await.expect("sim")));
    }
    let status = console.status();
    console.key("k", KeyKind::Release);
    let end = j2(&console.sim.arm.snapshot().await.expect("sim"));
    assert!(
        highest <= 30.0 + 1e-6,
        "J2 passed its soft limit: {highest:.3}"
    );
    assert!(
        end >= 29.0,
        "J2 stopped at {end:.3}, short of 29; said {:?}",
        console.said
    );
    assert!(status.contains("AT FENCE: J2 soft limit"), "{status}");
    console.driver.shutdown().await;
}

/// Criterion 4: a polar pan toward a side of the box stops outside it, on each link.
async fn a_pan_stops_at_a_side_of_the_box(links: Links) {
    let mut console = Console::start(links, |tool| {
        let [x, y, z] = tool;
        // A side 80 mm from the sphere either way the pan goes.
        let side = RADIUS + 80.0;
        Fence {
            tool_radius: RADIUS,
            inside: Some(Aabb {
                min: [x - 2000.0, y - side, z - 2000.0],
                max: [x + 2000.0, y + side, z + 2000.0],
            }),
            ..Fence::default()
        }
    })
    .await;
    let start = console.tool_mm().await;
    console.key("right", KeyKind::Press);
    let until = tokio::time::Instant::now() + Duration::from_secs(5);
    let mut widest: f64 = 0.0;
    while tokio::time::Instant::now() < until {
        console.watch_for(Duration::from_millis(20)).await;
        widest = widest.max((console.tool_mm().await[1] - start[1]).abs());
    }
    let status = console.status();
    console.key("right", KeyKind::Release);
    assert!(
        widest > 40.0,
        "{links:?}: the pan moved y only {widest:.1} mm"
    );
    assert!(
        widest <= 80.0 + 0.01,
        "{links:?}: the sphere crossed the side: {widest:.2} mm"
    );
    assert!(
        status.contains("AT FENCE"),
        "{links:?}: {status}; said {:?}",
        console.said
    );
    console.driver.shutdown().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_polar_pan_toward_a_side_of_the_box_stops_outside_it_over_both_links() {
    a_pan_stops_at_a_side_of_the_box(Links::Talos).await;
    a_pan_stops_at_a_side_of_the_box(Links::Modbus).await;
}

/// A move the arm plans (home) is watched: heading into a zone, it is stopped at the fence.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn home_heading_into_a_zone_is_stopped_at_the_fence() {
    // A wall 20 mm thick, 60 mm on from home in +X, up to 100 mm over home's tool point.
    let mut console = Console::start(Links::Modbus, |tool| {
        let [x, y, z] = tool;
        Fence {
            tool_radius: RADIUS,
            keep_out: vec![KeepOut {
                name: "wall".into(),
                zone: Aabb {
                    min: [x + 100.0, y - 500.0, z - 500.0],
                    max: [x + 120.0, y + 500.0, z + 100.0],
                },
                enabled: true,
            }],
            ..Fence::default()
        }
    })
    .await;
    let home = console.tool_mm().await;
    // Up 180 mm, then over the wall 200 mm in +X.
    for (key, mm, axis) in [("r", 180.0, 2), ("w", 200.0, 0)] {
        let from = console.tool_mm().await[axis];
        console.key(key, KeyKind::Press);
        let until = tokio::time::Instant::now() + Duration::from_secs(6);
        while console.tool_mm().await[axis] - from < mm && tokio::time::Instant::now() < until {
            console.watch_for(Duration::from_millis(20)).await;
        }
        console.key(key, KeyKind::Release);
        console.watch_for(Duration::from_millis(300)).await;
    }
    let over = console.tool_mm().await;
    assert!(
        over[0] - home[0] > 190.0 && over[2] - home[2] > 160.0,
        "{over:?}"
    );
    console.said.clear();
    console.key("h", KeyKind::Press);
    console.key("h", KeyKind::Release);
    console
        .run_for(QUESTION_QUIET + Duration::from_millis(20))
        .await;
    console.key("y", KeyKind::Press);
    console.key("y", KeyKind::Release);
    let (_, end) = console.watch_for(Duration::from_secs(4)).await;
    let stopped = console
        .said
        .iter()
        .any(|s| s.contains("stopped: AT FENCE: wall"));
    assert!(stopped, "said {:?}", console.said);
    assert!(
        end[0] - RADIUS >= home[0] + 120.0 - 3.0,
        "home went {:.1} mm past the wall's far face",
        home[0] + 120.0 - (end[0] - RADIUS)
    );
    console.driver.shutdown().await;
}
