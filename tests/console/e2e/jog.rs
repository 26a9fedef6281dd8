//! The console's state machine and arm driver against the in-process simulator over real
//! sockets: keys move the simulated tool the right way, releases stop it, link loss stops it and
//! nothing moves after a reconnect. No terminal involved: inputs go straight to the state
//! machine, as the runtime would deliver them.

use armjog::console::app::QUESTION_QUIET;
use std::time::{Duration, Instant};

use crossterm::event::{KeyCode, KeyEvent, KeyEventKind, KeyModifiers};
use tokio::sync::mpsc::UnboundedReceiver;

use armjog::console::app::{App, Input, KeyInput};
use armjog::console::jog::KeyKind;
use armjog::console::positions::PositionBook;
use armjog::console::run::key_input;
use armjog::link::driver::{Driver, DriverConfig};
use armjog::link::interface::{ArmEvent, LinkStatus};
use armjog::link::{ModbusConfig, TalosConfig};
use armjog::sim::arm_model::WATCHDOG;
use armjog::sim::talos_server::NetworkFaults;
use armjog::sim::{SimConfig, Simulator};

use crate::event_loop::{self, Drives};

struct Console {
    app: App,
    driver: Driver,
    events: UnboundedReceiver<ArmEvent>,
    sim: Simulator,
}

enum Links {
    Talos,
    Modbus,
    Both,
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
    /// A console on a simulator whose watchdog is [`LONG_WATCHDOG_S`].
    async fn start(links: Links) -> Console {
        Console::start_with_watchdog(links, LONG_WATCHDOG_S).await
    }

    /// A console on a simulator whose operator stops an unrefreshed continuous motion after
    /// `watchdog` seconds.
    async fn start_with_watchdog(links: Links, watchdog: f64) -> Console {
        let mut sim_config = SimConfig::ephemeral();
        sim_config.arm.set_watchdog_period(watchdog);
        let sim = Simulator::start(sim_config).await.expect("simulator");
        let talos = TalosConfig::new(sim.talos_addr.to_string());
        let modbus = sim.modbus_addr.map(|a| ModbusConfig::new(a.to_string()));
        let config = match links {
            Links::Talos => DriverConfig::new(Some(talos), None),
            Links::Modbus => DriverConfig::new(None, modbus),
            Links::Both => DriverConfig::new(Some(talos), modbus),
        };
        let mut book = PositionBook::new();
        // A name remembered from an earlier run that this (fresh) operator does not know.
        book.get_or_insert("ghost");
        let app = event_loop::app_for(&config, book);
        let (driver, events) = Driver::spawn(config);
        let mut console = Console {
            app,
            driver,
            events,
            sim,
        };
        // Every link here sends telemetry: a link silent since it came up would soon be stale
        // and refuse to jog.
        console
            .run_until(Duration::from_secs(5), |c| {
                matches!(c.app.link(), LinkStatus::Up { .. }) && c.app.telemetry().is_some()
            })
            .await;
        console
    }

    fn input(&mut self, input: Input) {
        event_loop::carry_out(&mut self.app, &self.driver, input);
    }

    async fn tcp(&self) -> [f64; 3] {
        self.sim.arm.snapshot().await.expect("sim").tcp_position
    }

    async fn moving(&self) -> bool {
        self.sim.arm.snapshot().await.expect("sim").moving
    }

    /// Runs the loop until the simulated arm stands still; false if it still moves after
    /// `within` (a release must stop it within one console tick plus the wire).
    async fn stops_within(&mut self, within: Duration) -> bool {
        let until = tokio::time::Instant::now() + within;
        loop {
            if !self.moving().await {
                return true;
            }
            if tokio::time::Instant::now() >= until {
                return false;
            }
            self.run_for(Duration::from_millis(2)).await;
        }
    }
}

/// How soon after a release the simulated arm must stand still. The STOP itself takes well
/// under a millisecond; the bound is generous for a loaded 2-core CI, where this process may
/// wait its turn for a good part of a second.
const STOP_BOUND: Duration = Duration::from_secs(2);

/// The operator's watchdog in the tests that time a stop, seconds: ten times the real one and
/// well past [`STOP_BOUND`] after the last START (which went out at most 100 ms before the
/// release), so that a pass proves the console's STOP, never the watchdog.
const LONG_WATCHDOG_S: f64 = 5.0;

/// Holds `key` for `hold`, releases it, and returns the TCP displacement (m).
async fn jog(console: &mut Console, key: &str, hold: Duration) -> [f64; 3] {
    let before = console.tcp().await;
    console.key(key, KeyKind::Press);
    console.run_for(hold).await;
    console.key(key, KeyKind::Release);
    assert!(
        console.stops_within(STOP_BOUND).await,
        "{key}: stopped within a tick of the release"
    );
    let after = console.tcp().await;
    [0, 1, 2].map(|k| after[k] - before[k])
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn each_cartesian_key_moves_the_tool_its_way_over_talos() {
    let mut console = Console::start(Links::Talos).await;
    for (key, axis, sign) in [
        ("w", 0, 1.0),
        ("s", 0, -1.0),
        ("a", 1, 1.0),
        ("d", 1, -1.0),
        ("r", 2, 1.0),
        ("f", 2, -1.0),
    ] {
        let d = jog(&mut console, key, Duration::from_millis(300)).await;
        assert!(d[axis] * sign > 0.02, "{key}: moved {d:?}");
        for other in (0..3).filter(|k| *k != axis) {
            assert!(d[other].abs() < 0.005, "{key}: off-axis motion {d:?}");
        }
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn arrows_pan_the_tool_right_and_up() {
    let mut console = Console::start(Links::Talos).await;
    let before = console.tcp().await;
    jog(&mut console, "right", Duration::from_millis(400)).await;
    let after = console.tcp().await;
    let azimuth = |p: [f64; 3]| p[1].atan2(p[0]);
    assert!(
        azimuth(after) > azimuth(before) + 0.01,
        "right turns azimuth +"
    );
    let elevation = |p: [f64; 3]| p[2].atan2(p[0].hypot(p[1]));
    let before = console.tcp().await;
    jog(&mut console, "up", Duration::from_millis(400)).await;
    assert!(
        elevation(console.tcp().await) > elevation(before) + 0.01,
        "up raises altitude"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn holding_a_key_past_the_watchdog_keeps_moving() {
    // A 1 s watchdog (twice the real one) held for 2.5 s: only the console's refreshes keep the
    // arm moving, and a loaded machine would have to stall the console a whole second to stop it.
    let mut console = Console::start_with_watchdog(Links::Talos, 1.0).await;
    console.key("w", KeyKind::Press);
    // The keyboard's auto-repeat: with release events a hold must keep proving itself (a key
    // silent for 1 s is stopped).
    let until = Instant::now() + Duration::from_millis(2500);
    while Instant::now() < until {
        console.run_for(Duration::from_millis(33)).await;
        console.key("w", KeyKind::Repeat);
    }
    assert!(
        console.moving().await,
        "refreshed well inside the 1 s watchdog"
    );
    console.key("w", KeyKind::Release);
    assert!(console.stops_within(STOP_BOUND).await);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn modbus_twist_jog_moves_and_stops() {
    let mut console = Console::start(Links::Modbus).await;
    let d = jog(&mut console, "r", Duration::from_millis(400)).await;
    assert!(d[2] > 0.02, "r raises the tool over Modbus: {d:?}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn jogging_through_talos_shows_in_modbus_telemetry() {
    let mut console = Console::start(Links::Both).await;
    console
        .run_until(Duration::from_secs(2), |c| c.app.telemetry().is_some())
        .await;
    let before = console.app.telemetry().map(|t| t.tcp.pose.y).unwrap_or(0.0);
    console.key("a", KeyKind::Press);
    console.run_for(Duration::from_millis(400)).await;
    console.key("a", KeyKind::Release);
    console.run_for(Duration::from_millis(200)).await;
    let after = console.app.telemetry().map(|t| t.tcp.pose.y).unwrap_or(0.0);
    assert!(after > before + 0.02, "panel y {before} -> {after}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn link_loss_mid_jog_stops_the_arm_and_nothing_moves_after_reconnect() {
    let mut console = Console::start_with_watchdog(Links::Talos, WATCHDOG).await;
    console.key("w", KeyKind::Press);
    console.run_for(Duration::from_millis(200)).await;
    assert!(console.moving().await);
    // The operator hangs up on the next frame (the next START refresh).
    console.sim.set_faults(NetworkFaults {
        close_after_frames: Some(1),
        ..NetworkFaults::default()
    });
    console
        .run_until(Duration::from_secs(1), |c| {
            matches!(c.app.link(), LinkStatus::Down { .. })
        })
        .await;
    assert!(
        console.app.jog().active().is_none(),
        "the console forgot the held key"
    );
    tokio::time::sleep(Duration::from_millis(600)).await;
    assert!(
        !console.moving().await,
        "the operator's watchdog stopped the arm"
    );
    // The link comes back; the key is (as far as the console knows) still down.
    console.sim.set_faults(NetworkFaults::default());
    console
        .run_until(Duration::from_secs(4), |c| {
            matches!(c.app.link(), LinkStatus::Up { .. })
        })
        .await;
    console.key("w", KeyKind::Repeat);
    console.run_for(Duration::from_millis(500)).await;
    assert!(
        !console.moving().await,
        "no motion starts by itself after a reconnect"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn crossterm_press_and_release_events_drive_the_jog() {
    let mut console = Console::start(Links::Talos).await;
    let press =
        KeyEvent::new_with_kind(KeyCode::Char('w'), KeyModifiers::NONE, KeyEventKind::Press);
    let release = KeyEvent::new_with_kind(
        KeyCode::Char('w'),
        KeyModifiers::NONE,
        KeyEventKind::Release,
    );
    console.input(Input::Key(key_input(&press).expect("w maps")));
    console.run_for(Duration::from_millis(150)).await;
    assert!(console.moving().await);
    console.input(Input::Key(key_input(&release).expect("w release maps")));
    assert!(console.stops_within(STOP_BOUND).await);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn focus_loss_and_space_stop_the_arm() {
    let mut console = Console::start(Links::Both).await;
    console.key("d", KeyKind::Press);
    console.run_for(Duration::from_millis(150)).await;
    console.input(Input::FocusLost);
    assert!(console.stops_within(STOP_BOUND).await);
    console.key("f", KeyKind::Press);
    console.run_for(Duration::from_millis(150)).await;
    console.key("space", KeyKind::Press);
    assert!(console.stops_within(STOP_BOUND).await);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn save_and_recall_a_named_position_on_the_operator() {
    let mut console = Console::start(Links::Talos).await;
    console.key("p", KeyKind::Press);
    for c in "bench".chars() {
        console.input(Input::Key(KeyInput {
            key: c.to_string().parse().expect("letter"),
            text: Some(c),
            kind: KeyKind::Press,
        }));
    }
    console.key("enter", KeyKind::Press);
    console
        .run_until(Duration::from_secs(1), |c| {
            c.app.positions().get("bench").is_some()
        })
        .await;
    let home = console.tcp().await;
    jog(&mut console, "a", Duration::from_millis(400)).await;
    console.key("o", KeyKind::Press);
    // A question ignores keys for its first moments.
    console
        .run_for(QUESTION_QUIET + Duration::from_millis(20))
        .await;
    console.key("y", KeyKind::Press);
    console.run_for(Duration::from_millis(3000)).await;
    let back = console.tcp().await;
    for k in 0..3 {
        assert!(
            (back[k] - home[k]).abs() < 0.002,
            "back at bench: {back:?} vs {home:?}"
        );
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn names_the_operator_does_not_know_are_marked() {
    let mut console = Console::start(Links::Talos).await;
    console
        .run_until(Duration::from_secs(2), |c| {
            c.app
                .positions()
                .get("ghost")
                .is_some_and(|e| e.unknown_to_operator)
        })
        .await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_joint_jog_turns_the_selected_joint_over_talos() {
    let mut console = Console::start(Links::Talos).await;
    // The jog command carries the joint's reported position: wait for telemetry first.
    console
        .run_until(Duration::from_secs(2), |c| c.app.telemetry().is_some())
        .await;
    console.key("]", KeyKind::Press); // J1 -> J2
    console.key("]", KeyKind::Press); // J2 -> J3
    let before = console
        .sim
        .arm
        .snapshot()
        .await
        .expect("sim")
        .joint_position[2];
    console.key("k", KeyKind::Press);
    console.run_for(Duration::from_millis(400)).await;
    console.key("k", KeyKind::Release);
    assert!(console.stops_within(STOP_BOUND).await);
    let after = console
        .sim
        .arm
        .snapshot()
        .await
        .expect("sim")
        .joint_position[2];
    // 20 deg/s at 50 % for about 0.4 s.
    assert!((after - before - 4.0).abs() < 1.5, "J3 {before} -> {after}");
}
