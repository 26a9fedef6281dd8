//! A tour of three positions against the simulator over both links, in real time: over Modbus
//! each leg a cartesian move to the stored pose, over Talos a Go To; each next leg only once the
//! last is seen done at rest; a key mid-leg stops the arm and ends the tour, and nothing of it
//! goes on afterwards. Another client's move under a leg (a stored action, or a cartesian move
//! elsewhere, from a second Modbus client) is never the leg done: the tour ends saying so.

use std::time::Duration;

use tokio::sync::mpsc::UnboundedReceiver;

use armjog::console::app::{App, Input, MotionShown, Overlay, QUESTION_QUIET};
use armjog::console::form::Confirm;
use armjog::console::jog::KeyKind;
use armjog::console::positions::{PositionBook, Tour};
use armjog::kortex::{Pose, ReferenceFrame, StoredMotion};
use armjog::link::driver::{Driver, DriverConfig};
use armjog::link::interface::{ArmCommand, ArmEvent, LinkStatus};
use armjog::link::{ModbusConfig, ModbusLink, TalosConfig};
use armjog::sim::{SimConfig, Simulator};

use crate::event_loop::{self, Drives};

struct Console {
    app: App,
    driver: Driver,
    events: UnboundedReceiver<ArmEvent>,
    sim: Simulator,
    /// Every tour label shown, in order (`2/3 pick`).
    legs_seen: Vec<String>,
    /// Every bottom-line message shown, in order.
    said: Vec<String>,
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
        if let Some(t) = self.app.view().tour {
            let label = format!("{}/{} {}", t.leg, t.legs, t.to);
            if self.legs_seen.last() != Some(&label) {
                self.legs_seen.push(label);
            }
        }
        if let Some((text, _)) = self.app.message()
            && self.said.last().map(String::as_str) != Some(text)
        {
            self.said.push(text.to_string());
        }
    }
}

/// Three places a few centimetres from home (tenths of mm), the tool as at home.
const PLACES: [(&str, [i32; 3]); 3] = [
    ("bench", [4866, 10, 4338]),
    ("pick", [4566, 400, 4338]),
    ("place", [4566, 10, 4038]),
];

impl Console {
    async fn start(talos: bool) -> Console {
        Console::start_capped(talos, None).await
    }

    /// A console whose cap is `max_jog_speed` (m/s) rather than the default.
    async fn start_capped(talos: bool, max_jog_speed: Option<f64>) -> Console {
        Console::start_over(talos, !talos, max_jog_speed).await
    }

    /// A console over Talos, Modbus or both (Talos moves, Modbus telemetry).
    async fn start_over(talos: bool, modbus: bool, max_jog_speed: Option<f64>) -> Console {
        let sim = Simulator::start(SimConfig::ephemeral())
            .await
            .expect("simulator");
        let mut config = DriverConfig::new(
            talos.then(|| TalosConfig::new(sim.talos_addr.to_string())),
            modbus.then(|| ModbusConfig::new(sim.modbus_addr.expect("modbus").to_string())),
        );
        if let Some(cap) = max_jog_speed {
            config.max_jog_speed = cap;
        }
        let app = event_loop::app_for(&config, PositionBook::new());
        let (driver, events) = Driver::spawn(config);
        let mut console = Console {
            app,
            driver,
            events,
            sim,
            legs_seen: Vec::new(),
            said: Vec::new(),
        };
        console
            .run_until(Duration::from_secs(10), |c| {
                matches!(c.app.link(), LinkStatus::Up { .. }) && c.app.telemetry().is_some()
            })
            .await;
        let mut book = PositionBook::new();
        for (name, [x, y, z]) in PLACES {
            if talos {
                // The operator keeps the positions: it is given them as a console would.
                let name = name.to_string();
                assert!(
                    console
                        .driver
                        .send(ArmCommand::SetCartesianPosition { name, x, y, z })
                );
            }
            let entry = book.get_or_insert(name);
            entry.cartesian = Some([x, y, z]);
            let home = console.app.telemetry().expect("telemetry").tcp.pose;
            entry.orientation = Some([home.theta_x, home.theta_y, home.theta_z]);
        }
        book.set_tour(Tour {
            name: "rounds".into(),
            positions: PLACES.iter().map(|(n, _)| n.to_string()).collect(),
        });
        console.input(Input::PositionsLoaded(Ok(book)));
        console.run_for(Duration::from_millis(300)).await;
        console
    }

    fn press(&mut self, name: &str) {
        self.key(name, KeyKind::Press);
        self.key(name, KeyKind::Release);
    }

    async fn play(&mut self) {
        self.press("O");
        self.press("enter");
        assert!(
            matches!(self.app.overlay(), Overlay::Confirm(Confirm::Tour(_))),
            "{:?} {:?}",
            self.app.overlay(),
            self.app.message()
        );
        self.run_for(QUESTION_QUIET + Duration::from_millis(50))
            .await;
        self.press("y");
    }

    async fn tool_mm(&self) -> [f64; 3] {
        let t = self.app.telemetry().expect("telemetry").tcp.pose;
        [t.x, t.y, t.z].map(|v| f64::from(v) * 1000.0)
    }

    async fn sim_moving(&self) -> bool {
        self.sim.arm.snapshot().await.expect("sim").moving
    }
}

fn near(mm: [f64; 3], tenths: [i32; 3], within_mm: f64) -> bool {
    mm.iter()
        .zip(tenths)
        .all(|(a, b)| (a - f64::from(b) / 10.0).abs() <= within_mm)
}

async fn full_tour(talos: bool) {
    full_tour_over(talos, !talos).await;
}

async fn full_tour_over(talos: bool, modbus: bool) {
    let mut c = Console::start_over(talos, modbus, None).await;
    c.play().await;
    c.run_until(Duration::from_secs(60), |c| {
        c.app.view().tour.is_none() && c.app.motion_shown() == MotionShown::Idle
    })
    .await;
    assert_eq!(c.legs_seen, ["1/3 bench", "2/3 pick", "3/3 place"]);
    let said = c
        .app
        .message()
        .map(|(t, _)| t.to_string())
        .unwrap_or_default();
    assert_eq!(said, "tour 'rounds' leg 3/3 → place: tour done");
    let at = c.tool_mm().await;
    assert!(near(at, PLACES[2].1, 3.0), "ended at place: {at:?}");
}

async fn stopped_mid_leg(talos: bool) {
    let mut c = Console::start(talos).await;
    c.play().await;
    c.run_until(Duration::from_secs(30), |c| {
        c.legs_seen.last().map(String::as_str) == Some("2/3 pick")
            && matches!(c.app.motion_shown(), MotionShown::Action { .. })
    })
    .await;
    c.run_for(Duration::from_millis(150)).await;
    assert!(c.sim_moving().await, "leg 2 under way");
    c.press("v");
    let said = c
        .app
        .message()
        .map(|(t, _)| t.to_string())
        .unwrap_or_default();
    assert_eq!(
        said,
        "tour 'rounds' leg 2/3 → pick: stopped by a key; play it again to go on"
    );
    assert!(c.app.view().tour.is_none());
    c.run_until(Duration::from_secs(10), |c| {
        c.app.motion_shown() == MotionShown::Idle
    })
    .await;
    assert!(!c.sim_moving().await, "the arm stopped");
    let stopped_at = c.tool_mm().await;
    assert!(!near(stopped_at, PLACES[1].1, 1.0), "stopped short of pick");
    // Nothing goes on by itself.
    c.run_for(Duration::from_secs(2)).await;
    assert!(!c.sim_moving().await);
    assert_eq!(c.legs_seen, ["1/3 bench", "2/3 pick"]);
    let still = c.tool_mm().await;
    let drift = still
        .iter()
        .zip(stopped_at)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(drift <= 1.5, "{still:?} vs {stopped_at:?}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_tour_of_three_positions_over_modbus_visits_each_in_order() {
    full_tour(false).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_tour_of_three_positions_over_talos_visits_each_in_order() {
    full_tour(true).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_tour_over_talos_with_modbus_telemetry_is_never_taken_for_another_clients_move() {
    // The simulator shows each Go To as a cartesian trajectory under the last move's id: each
    // leg is ours, done at its place.
    full_tour_over(true, true).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_key_mid_leg_over_modbus_stops_the_arm_and_the_tour() {
    stopped_mid_leg(false).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_key_mid_leg_over_talos_stops_the_arm_and_the_tour() {
    stopped_mid_leg(true).await;
}

/// Another client on the simulator's Modbus server, as `armjog modbus` is.
async fn other_client(sim: &Simulator) -> ModbusLink {
    let addr = sim.modbus_addr.expect("modbus").to_string();
    let (link, _events) = ModbusLink::connect(ModbusConfig::new(addr))
        .await
        .expect("second client");
    link
}

/// A tour at a 20 mm/s cap (10 mm/s at the speed in force), so its first leg runs a few
/// seconds; returns once the leg is seen moving the arm.
async fn leg_under_way(talos: bool) -> Console {
    leg_under_way_over(talos, !talos).await
}

/// [`leg_under_way`] over Talos, Modbus or both.
async fn leg_under_way_over(talos: bool, modbus: bool) -> Console {
    let mut c = Console::start_over(talos, modbus, Some(0.02)).await;
    c.play().await;
    c.run_until(Duration::from_secs(10), |c| {
        c.legs_seen.last().map(String::as_str) == Some("1/3 bench")
            && matches!(c.app.motion_shown(), MotionShown::Action { .. })
    })
    .await;
    c.run_for(Duration::from_millis(300)).await;
    assert!(c.sim_moving().await, "leg 1 under way");
    c
}

/// The tour ended on leg 1 saying another client moved the arm, the arm stopped, and no leg
/// was ever said done. Returns what ended the tour.
async fn moved_by_another_client(mut c: Console) -> String {
    c.run_until(Duration::from_secs(20), |c| c.app.view().tour.is_none())
        .await;
    let said = c.said.last().cloned().unwrap_or_default();
    assert!(
        said.starts_with(
            "tour 'rounds' leg 1/3 → bench ended the tour: go to 'bench' not done: \
                          MOVED BY ANOTHER CLIENT: "
        ),
        "{said}"
    );
    c.run_until(Duration::from_secs(10), |c| {
        c.app.motion_shown() == MotionShown::Idle
    })
    .await;
    c.run_for(Duration::from_millis(500)).await;
    assert!(!c.sim_moving().await, "the arm stopped");
    assert_eq!(c.legs_seen, ["1/3 bench"], "no next leg");
    assert!(
        !c.said.iter().any(|m| m.ends_with("done")),
        "said done: {:?}",
        c.said
    );
    said
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn another_clients_action_under_a_modbus_leg_ends_the_tour_and_stops_the_arm() {
    let c = leg_under_way(false).await;
    // `armjog modbus action --id 5 --no-wait`: the simulator's Zero action.
    let other = other_client(&c.sim).await;
    other
        .start_stored(
            armjog::kortex::Stored {
                motion: StoredMotion::Action,
                id: 5,
            },
            None,
        )
        .await
        .expect("action 5 started");
    moved_by_another_client(c).await;
    drop(other);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn another_clients_move_elsewhere_under_a_leg_is_never_the_leg_done() {
    for talos in [false, true] {
        let c = leg_under_way(talos).await;
        // A second console's go-to takes over: a cartesian move 20 mm short of bench.
        let other = other_client(&c.sim).await;
        let [x, y, z] = PLACES[0].1.map(|v| v as f32 / 10_000.0);
        let home = c.app.telemetry().expect("telemetry").tcp.pose;
        let elsewhere = Pose {
            x: x - 0.02,
            y,
            z,
            ..home
        };
        other
            .go_to_pose(ReferenceFrame::Base, elsewhere, None)
            .await
            .expect("the other move started");
        moved_by_another_client(c).await;
        drop(other);
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn another_clients_action_under_a_talos_leg_is_named_from_the_modbus_status() {
    // Talos moves, Modbus reads the arm's action status: the Go To is not named there, action 5
    // started from a shell is.
    let c = leg_under_way_over(true, true).await;
    let other = other_client(&c.sim).await;
    other
        .start_stored(
            armjog::kortex::Stored {
                motion: StoredMotion::Action,
                id: 5,
            },
            None,
        )
        .await
        .expect("action 5 started");
    let said = moved_by_another_client(c).await;
    assert!(said.contains("the arm runs action 5"), "{said}");
    drop(other);
}
