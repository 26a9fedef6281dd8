//! Positions across runs and operators, over real sockets: the built-in simulator starts with
//! the positions a console saved in an earlier run (none reads "unknown to operator", and going
//! there works), and a scripted operator that has lost a name gets it re-saved before the
//! Go To, never a Go To first.

use armjog::console::app::QUESTION_QUIET;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use tokio::sync::mpsc::UnboundedReceiver;

use armjog::console::app::{App, Effect, Input, KeyInput, Overlay};
use armjog::console::form::Confirm;
use armjog::console::jog::KeyKind;
use armjog::console::keymap::KeyName;
use armjog::console::positions::PositionBook;
use armjog::link::TalosConfig;
use armjog::link::driver::{Driver, DriverConfig};
use armjog::link::interface::{ArmEvent, LinkStatus};
use armjog::sim::arm_model::Arm;
use armjog::sim::kinematics::{HOME_DEG, to_radians};
use armjog::sim::operator::Operator;
use armjog::sim::{SimConfig, Simulator};
use armjog::talos::{Checksum, CommandValue, Reply, Request, ReturnCode};

use crate::common::{self, Action, TestOperator};
use crate::event_loop;

/// The console's state machine and a driver on one Talos operator, with the loop the runtime
/// runs (arm events and ticks), as in `console_e2e`.
struct Session {
    app: App,
    driver: Driver,
    events: UnboundedReceiver<ArmEvent>,
    /// The book as last handed to be written.
    written: Option<PositionBook>,
    /// Names the operator answered for, and names it said it does not know.
    known: Vec<String>,
    unknown: Vec<String>,
}

impl event_loop::Drives for Session {
    fn app(&self) -> &App {
        &self.app
    }
    fn events(&mut self) -> &mut UnboundedReceiver<ArmEvent> {
        &mut self.events
    }
    fn input(&mut self, input: Input) {
        Session::input(self, input);
    }
}

impl Session {
    fn start(talos_addr: String, book: PositionBook) -> Session {
        let config = DriverConfig::new(Some(TalosConfig::new(talos_addr)), None);
        let app = event_loop::app_for(&config, book);
        let (driver, events) = Driver::spawn(config);
        Session {
            app,
            driver,
            events,
            written: None,
            known: Vec::new(),
            unknown: Vec::new(),
        }
    }

    fn input(&mut self, input: Input) {
        if let Input::Arm(event) = &input {
            match event {
                ArmEvent::Position { name, .. } => self.known.push(name.clone()),
                ArmEvent::UnknownPosition { name } => self.unknown.push(name.clone()),
                _ => {}
            }
        }
        for effect in self.app.handle(input, Instant::now()) {
            match effect {
                Effect::Arm(command) => assert!(self.driver.send(command), "driver alive"),
                Effect::SavePositions(save) => self.written = Some(save.book),
                Effect::SaveFence(_) | Effect::Quit => {}
            }
        }
    }

    /// Presses (and releases) a key, typing its character.
    fn key(&mut self, name: &str) {
        let key: KeyName = name.parse().expect("key name");
        let text = (name.chars().count() == 1)
            .then(|| name.chars().next())
            .flatten();
        for kind in [KeyKind::Press, KeyKind::Release] {
            self.input(Input::Key(KeyInput { key, text, kind }));
        }
    }

    fn select(&mut self, name: &str) {
        for _ in 0..self.app.positions().len() {
            if self.app.selected_name() == Some(name) {
                return;
            }
            self.key("pagedown");
        }
        assert_eq!(self.app.selected_name(), Some(name));
    }

    /// Runs the event loop until `done` holds; panics after `within`.
    async fn run_until(&mut self, within: Duration, what: &str, done: impl Fn(&Session) -> bool) {
        let until = tokio::time::Instant::now() + within;
        let met = event_loop::run_until_instant(self, until, done).await;
        assert!(
            met,
            "{what}: not within {within:?}; link {:?}, message {:?}",
            self.app.link(),
            self.app.message()
        );
    }

    /// Runs the event loop for `duration`.
    async fn run_for(&mut self, duration: Duration) {
        let until = tokio::time::Instant::now() + duration;
        event_loop::run_until_instant(self, until, |_| false).await;
    }

    async fn until_up(&mut self) {
        self.run_until(Duration::from_secs(5), "link up", |s| {
            matches!(s.app.link(), LinkStatus::Up { .. })
        })
        .await;
    }
}

const WITHIN: Duration = Duration::from_secs(10);

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn positions_saved_in_an_earlier_run_are_known_to_the_built_in_simulator_at_start() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("simulator.json");
    // J1 a little below zero: reported as 340 degrees.
    let mut bench_deg = HOME_DEG;
    bench_deg[0] = -20.0;
    bench_deg[3] = 220.0;

    // The earlier run: the arm at the bench pose, saved as "bench", the book written.
    {
        let sim = Simulator::start(SimConfig {
            arm: Arm::at(to_radians(&bench_deg)),
            ..SimConfig::ephemeral()
        })
        .await
        .expect("simulator");
        let mut first = Session::start(sim.talos_addr.to_string(), PositionBook::new());
        first.until_up().await;
        first
            .run_until(WITHIN, "telemetry", |s| s.app.telemetry().is_some())
            .await;
        first.key("p");
        for c in "bench".chars() {
            first.key(&c.to_string());
        }
        first.key("enter");
        first
            .run_until(WITHIN, "bench saved", |s| {
                s.written.as_ref().is_some_and(|b| b.get("bench").is_some())
            })
            .await;
        let mut book = first.written.take().expect("written");
        // And one from an older armjog: coordinates only.
        book.get_or_insert("table").cartesian = Some([5000, 1000, 3000]);
        book.save(&file).expect("book written");
    }
    let book = PositionBook::load(&file).expect("book read");
    let bench = book.get("bench").expect("bench").clone();
    assert!(
        bench.joints.is_some() && bench.orientation.is_some(),
        "{bench:?}"
    );

    // This run: the simulator starts at home with the book's positions.
    let sim = Simulator::start(SimConfig {
        positions: armjog::cli::console::remembered_from_read(
            &armjog::console::book_io::read(&file).await,
        ),
        ..SimConfig::ephemeral()
    })
    .await
    .expect("simulator");
    let mut console = Session::start(sim.talos_addr.to_string(), book);
    console.until_up().await;
    console
        .run_until(WITHIN, "every name answered", |s| {
            ["bench", "table"]
                .iter()
                .all(|n| s.known.iter().any(|k| k == n))
        })
        .await;
    assert!(console.unknown.is_empty(), "unknown: {:?}", console.unknown);
    assert!(
        console
            .app
            .positions()
            .entries()
            .all(|(_, e)| !e.unknown_to_operator),
        "nothing reads unknown to operator"
    );
    assert_eq!(
        console
            .app
            .positions()
            .get("table")
            .and_then(|e| e.cartesian),
        Some([5000, 1000, 3000])
    );

    // Going to the bench is a joint move back to the angles it was saved at, the short way.
    console.select("bench");
    console.key("o");
    assert_eq!(
        console.app.overlay(),
        &Overlay::Confirm(Confirm::GoTo("bench".into()))
    );
    // A question ignores keys for its first moments.
    console
        .run_for(QUESTION_QUIET + Duration::from_millis(20))
        .await;
    console.key("y");
    let target = to_radians(&bench_deg);
    let deadline = tokio::time::Instant::now() + Duration::from_secs(20);
    loop {
        let snapshot = sim.arm.snapshot().await.expect("sim");
        let q = sim.arm.with(|arm, _| arm.joints()).await.expect("sim");
        let off = q
            .iter()
            .zip(target)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        if !snapshot.moving && off < 0.01 {
            break;
        }
        assert!(
            tokio::time::Instant::now() < deadline,
            "not at the bench: joints {q:?}, want {target:?}"
        );
        console.run_for(Duration::from_millis(100)).await;
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_operator_that_lost_a_name_gets_it_back_before_the_go_to() {
    // A real operator that knows no names (restarted), answering each frame as the ICD says.
    let operator = Arc::new(Mutex::new((Arm::default(), Operator::default())));
    let state = operator.clone();
    let script: common::Script = Arc::new(move |frame| {
        let reply = match Request::from_frame(frame) {
            Ok(request) => {
                let mut guard = state.lock().expect("operator");
                let (arm, operator) = &mut *guard;
                operator.handle(arm, request)
            }
            Err(e) => panic!("undecodable request: {e}"),
        };
        vec![Action::Write(common::reply_bytes(
            &reply,
            frame.id,
            Checksum::Crc16,
        ))]
    });
    let mut talos = TestOperator::start(Checksum::Crc16, script).await;
    let mut book = PositionBook::new();
    book.get_or_insert("pick").cartesian = Some([5000, -1205, 2500]);
    let mut console = Session::start(talos.addr.clone(), book);
    console.until_up().await;
    console
        .run_until(WITHIN, "pick marked unknown", |s| {
            s.app
                .positions()
                .get("pick")
                .is_some_and(|e| e.unknown_to_operator)
        })
        .await;
    console.select("pick");
    console.key("o");
    assert_eq!(
        console.app.overlay(),
        &Overlay::Confirm(Confirm::Resave("pick".into()))
    );
    // A question ignores keys for its first moments.
    console
        .run_for(QUESTION_QUIET + Duration::from_millis(20))
        .await;
    console.key("y");
    let state = operator.clone();
    console
        .run_until(WITHIN, "gone to pick", move |_| {
            state
                .lock()
                .map(|guard| !guard.0.motion().is_idle())
                .unwrap_or(false)
        })
        .await;
    // In order: the re-save, accepted, then the Go To; never a Go To before.
    let mut commands = Vec::new();
    while let Ok(item) = talos.received.try_recv() {
        if let armjog::talos::frame::Decoded::TalosFrame(f) = item {
            commands.push(CommandValue::from_request_value(f.command));
        }
    }
    let first = |c: CommandValue| commands.iter().position(|&x| x == Some(c));
    let resave = first(CommandValue::SetCartesianPosition).expect("a Set Cartesian Position");
    let goto = first(CommandValue::GoToPosition).expect("a Go To");
    assert!(resave < goto, "{commands:?}");
    let reply = {
        let mut guard = operator.lock().expect("operator");
        let (arm, operator) = &mut *guard;
        operator.handle(
            arm,
            Request::GetCartesianPosition {
                name: "pick".into(),
            },
        )
    };
    assert_eq!(
        reply,
        Reply::GetCartesianPosition {
            return_code: ReturnCode::OK,
            x: 5000,
            y: -1205,
            z: 2500
        }
    );
    assert!(
        !console
            .app
            .positions()
            .get("pick")
            .is_some_and(|e| e.unknown_to_operator)
    );
}
