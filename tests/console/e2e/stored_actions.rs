//! Stored actions and sequences by id end to end: the console (state machine and arm driver)
//! against the simulator over Modbus on real sockets. `A`, the form, yes: Zero (action 5) and
//! sequence 1 (Retract, then Home) show `MOVING: ...` until the arm reports them completed at
//! rest, under the console's speed cap; an id the arm does not have fails within 2 s naming it;
//! a key stops a run mid-way; another client's action under our home or action (a second Modbus
//! client, as `armjog modbus action` is) stops the arm and is never said done. Bounds are
//! generous for a loaded 2-core CI.

use std::time::{Duration, Instant};

use tokio::sync::mpsc::UnboundedReceiver;

use armjog::console::app::{App, Input, KeyInput, MotionShown, Overlay, QUESTION_QUIET};
use armjog::console::jog::KeyKind;
use armjog::console::positions::PositionBook;
use armjog::kortex::StoredMotion;
use armjog::link::driver::{Driver, DriverConfig, tool_speed_at};
use armjog::link::interface::{ArmEvent, LinkStatus};
use armjog::link::{ModbusConfig, ModbusLink};
use armjog::sim::arm_model::Arm;
use armjog::sim::kinematics::to_radians;
use armjog::sim::{SimConfig, Simulator};

use crate::event_loop::{self, Drives};

struct Console {
    app: App,
    driver: Driver,
    events: UnboundedReceiver<ArmEvent>,
    sim: Simulator,
    /// Every motion shown since the start, without repeats.
    seen: Vec<MotionShown>,
    /// The highest tool speed the telemetry reported, m/s.
    peak_m_s: f64,
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
        if let Input::Arm(ArmEvent::Telemetry(t)) = &input {
            let v = &t.tcp.twist;
            let speed = f64::from(v.x.hypot(v.y).hypot(v.z));
            if speed.is_finite() {
                self.peak_m_s = self.peak_m_s.max(speed);
            }
        }
        event_loop::carry_out(&mut self.app, &self.driver, input);
        let shown = self.app.motion_shown();
        if self.seen.last() != Some(&shown) {
            self.seen.push(shown);
        }
        if let Some((text, _)) = self.app.message()
            && self.said.last().map(String::as_str) != Some(text)
        {
            self.said.push(text.to_string());
        }
    }
}

impl Console {
    /// Over Modbus to a simulated `arm`, link up and telemetry in.
    async fn start(arm: Arm) -> Console {
        let mut sim_config = SimConfig::ephemeral();
        sim_config.arm = arm;
        let sim = Simulator::start(sim_config).await.expect("simulator");
        let modbus = ModbusConfig::new(sim.modbus_addr.expect("modbus server").to_string());
        let config = DriverConfig::new(None, Some(modbus));
        let app = event_loop::app_for(&config, PositionBook::new());
        let (driver, events) = Driver::spawn(config);
        let mut console = Console {
            app,
            driver,
            events,
            sim,
            seen: Vec::new(),
            peak_m_s: 0.0,
            said: Vec::new(),
        };
        console
            .run_until(Duration::from_secs(10), |c| {
                matches!(c.app.link(), LinkStatus::Up { .. }) && c.app.telemetry().is_some()
            })
            .await;
        console
    }

    /// `A`, the kind and id typed into the form, enter, and yes once the question may take it.
    async fn run_stored(&mut self, kind: &str, id: &str) {
        self.key("A", KeyKind::Press);
        if kind != "action" {
            self.key("up", KeyKind::Press);
            for _ in "action".chars() {
                self.key("backspace", KeyKind::Press);
            }
            type_text(self, kind);
            self.key("down", KeyKind::Press);
        }
        type_text(self, id);
        self.key("enter", KeyKind::Press);
        assert!(
            matches!(self.app.overlay(), Overlay::Confirm(_)),
            "{:?} {:?}",
            self.app.overlay(),
            self.app.message()
        );
        self.run_for(QUESTION_QUIET + Duration::from_millis(20))
            .await;
        self.seen.clear();
        self.peak_m_s = 0.0;
        self.key("y", KeyKind::Press);
    }

    async fn moving(&self) -> bool {
        self.sim.arm.snapshot().await.expect("sim").moving
    }
}

/// Typed into the open form: keys with their text, as the terminal reader delivers them.
fn type_text(console: &mut Console, text: &str) {
    for c in text.chars() {
        console.input(Input::Key(KeyInput {
            key: c.to_string().parse().expect("key name"),
            text: Some(c),
            kind: KeyKind::Press,
        }));
    }
}

fn message(c: &Console) -> String {
    crate::app_support::message(&c.app)
}

fn shown(label: &str) -> MotionShown {
    MotionShown::Action {
        label: label.into(),
        confirmed: true,
    }
}

/// The cap the console's speed in force puts on the tool, m/s, with the tolerance the cap
/// watch allows.
fn cap() -> f64 {
    let config = DriverConfig::new(None, None);
    tool_speed_at(config.max_jog_speed, armjog::link::driver::INITIAL_SPEED) * 1.05
}

/// Joints a few degrees from Zero (all at 0): the action has little to do.
fn near_zero() -> Arm {
    Arm::at(to_radians(&[0.0, 8.0, 0.0, 10.0, 0.0, 8.0, 0.0]))
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn zero_action_5_shows_moving_until_it_completes_at_rest_under_the_cap() {
    let mut console = Console::start(near_zero()).await;
    console.run_stored("action", "5").await;
    assert_eq!(console.app.motion_shown(), shown("ACTION 5"));
    console
        .run_until(Duration::from_secs(60), |c| message(c) == "action 5 done")
        .await;
    let before_done = &console.seen[..console.seen.len() - 1];
    assert!(
        before_done.iter().all(|s| *s == shown("ACTION 5")),
        "{:?}",
        console.seen
    );
    assert_eq!(console.app.motion_shown(), MotionShown::Idle);
    assert!(!console.moving().await, "done means at rest");
    let joints = console.app.telemetry().expect("telemetry").joints;
    for (i, joint) in joints.iter().enumerate() {
        let off = joint.position.rem_euclid(360.0);
        assert!(
            off.min(360.0 - off) < 1.0,
            "J{} at {}",
            i + 1,
            joint.position
        );
    }
    assert!(console.peak_m_s > 0.0, "it moved");
    assert!(
        console.peak_m_s <= cap(),
        "tool at {} m/s, cap {} m/s",
        console.peak_m_s,
        cap()
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn sequence_1_shows_moving_through_its_steps_until_it_completes() {
    // At Retract already: the sequence's first step has little to do, its second goes home.
    let retract = armjog::sim::stored::RETRACT_DEG;
    let mut console = Console::start(Arm::at(to_radians(&retract))).await;
    console.run_stored("sequence", "1").await;
    assert_eq!(console.app.motion_shown(), shown("SEQUENCE 1"));
    console
        .run_until(Duration::from_secs(90), |c| message(c) == "sequence 1 done")
        .await;
    let before_done = &console.seen[..console.seen.len() - 1];
    assert!(
        before_done.iter().all(|s| *s == shown("SEQUENCE 1")),
        "one MOVING from the first step to the end: {:?}",
        console.seen
    );
    assert!(!console.moving().await, "done means at rest");
    assert!(
        console.peak_m_s <= cap(),
        "tool at {} m/s",
        console.peak_m_s
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_id_the_arm_does_not_have_fails_within_2_s_naming_it() {
    let mut console = Console::start(Arm::default()).await;
    let started = Instant::now();
    console.run_stored("action", "99").await;
    assert_eq!(console.app.motion_shown(), shown("ACTION 99"));
    console
        .run_until(Duration::from_secs(10), |c| {
            message(c).starts_with("action 99 failed")
        })
        .await;
    let text = message(&console);
    assert!(text.contains("did not take action 99"), "{text}");
    // 2 s after the writes, plus a poll; generous for a loaded machine.
    assert!(
        started.elapsed() < Duration::from_secs(6),
        "{:?}",
        started.elapsed()
    );
    assert!(console.app.motion_truth().action().is_none());
    assert!(!console.moving().await, "nothing moved");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_key_stops_a_stored_action_mid_way() {
    // Far from Zero: the action runs for seconds.
    let mut console = Console::start(Arm::default()).await;
    console.run_stored("action", "5").await;
    console
        .run_until(Duration::from_secs(10), |c| {
            c.app.telemetry().is_some_and(|t| {
                t.joints
                    .iter()
                    .any(|j| j.velocity.is_finite() && j.velocity.abs() > 1.0)
            })
        })
        .await;
    assert!(console.moving().await, "under way");
    console.key("v", KeyKind::Press);
    assert_eq!(message(&console), "action 5 stopped");
    console
        .run_until(Duration::from_secs(10), |c| {
            c.app.motion_shown() == MotionShown::Idle
        })
        .await;
    assert!(!console.moving().await, "stopped on the arm");
    assert_eq!(*console.app.overlay(), Overlay::None);
}

/// Another client's action under ours: `h` (home, over Modbus alone the action of the home id,
/// 2) or `A` action 5, from Zero's far side so it runs for seconds; once it is seen moving, a
/// second Modbus client starts Retract (action 3), as `armjog modbus action --id 3` would. The
/// console stops the arm and says so, naming both moves, and never says done.
async fn another_clients_action_under(start: &str, ours: &str) {
    let mut console = Console::start(Arm::at(to_radians(&[
        40.0, 30.0, 40.0, 30.0, 40.0, 30.0, 40.0,
    ])))
    .await;
    match start {
        "h" => {
            console.key("h", KeyKind::Press);
            console
                .run_for(QUESTION_QUIET + Duration::from_millis(20))
                .await;
            console.key("y", KeyKind::Press);
        }
        _ => console.run_stored("action", "5").await,
    }
    console
        .run_until(Duration::from_secs(10), |c| {
            matches!(c.app.motion_shown(), MotionShown::Action { .. })
                && c.app
                    .telemetry()
                    .is_some_and(|t| t.joints.iter().any(|j| j.velocity.abs() > 1.0))
        })
        .await;
    let addr = console.sim.modbus_addr.expect("modbus").to_string();
    let (other, _events) = ModbusLink::connect(ModbusConfig::new(addr))
        .await
        .expect("second client");
    other
        .start_stored(
            armjog::kortex::Stored {
                motion: StoredMotion::Action,
                id: 3,
            },
            None,
        )
        .await
        .expect("action 3 started");
    let not_done =
        format!("{ours} not done: MOVED BY ANOTHER CLIENT: the arm runs action 3, not our ");
    console
        .run_until(Duration::from_secs(10), |c| {
            message(c).starts_with(&not_done)
        })
        .await;
    console
        .run_until(Duration::from_secs(10), |c| {
            c.app.motion_shown() == MotionShown::Idle
        })
        .await;
    console.run_for(Duration::from_millis(500)).await;
    assert!(!console.moving().await, "the arm stopped");
    assert!(
        !console.said.iter().any(|m| m.ends_with("done")),
        "said done: {:?}",
        console.said
    );
    drop(other);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn another_clients_action_under_our_home_stops_the_arm_and_is_never_home_done() {
    another_clients_action_under("h", "home").await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn another_clients_action_under_our_action_stops_the_arm_and_is_never_done() {
    another_clients_action_under("A", "action 5").await;
}
