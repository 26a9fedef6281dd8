//! Tours of named positions in the state machine, on a fake clock: made from the positions
//! list and checked against the book, confirmed once, played one leg at a time or straight
//! through on the go-to path, each next leg only after the last one's end at rest and the
//! motion gate. What ends a tour is in `tour_ends.rs`, edits to the positions a tour visits in
//! `tour_position_edits.rs`; `Bench` here serves them (and `goto_end.rs`, `guard_stops.rs`).

use std::time::{Duration, Instant};

use armjog::console::app::{
    App, AppConfig, Effect, Input, KeyInput, MotionShown, Overlay, QUESTION_QUIET,
};
use armjog::console::form::Confirm;
use armjog::console::jog::KeyKind;
use armjog::console::keymap::KeyName;
use armjog::console::positions::{PositionBook, Tour};
use armjog::kortex::{ActionState, ActionStatus, Coded, MoveType, Pose, Telemetry};
use armjog::link::interface::{ArmCommand, ArmEvent, LinkStatus, TelemetrySource};

use crate::app_support::{self, ms, no_motion};

const HOME: [f32; 7] = [0.0, 15.0, 180.0, 230.0, 0.0, 55.0, 90.0];

/// The arm with its tool at `tool`, its action status `status` of a `move_type`.
fn telemetry(velocity: f32, status: ActionStatus, move_type: MoveType, tool: Pose) -> Telemetry {
    let action = ActionState {
        status: Coded::Known(status),
        id: 0,
        move_type: Coded::Known(move_type),
    };
    let mut t = crate::app_support::arm_telemetry(HOME, velocity, action);
    t.tcp.pose = tool;
    t
}

/// A console over Modbus (`on_operator` false) or a Talos operator with hardware telemetry,
/// its book holding bench, pick and place and the tour `rounds` of the three.
pub(crate) struct Bench {
    pub(crate) app: App,
    pub(crate) now: Instant,
    /// Where the telemetry has the tool (home at first; a leg's target once it arrived).
    pub(crate) tool: Pose,
    /// The move type the telemetry reports: a go-to's, a cartesian trajectory.
    pub(crate) move_type: MoveType,
}

impl Bench {
    pub(crate) fn new(on_operator: bool) -> Bench {
        Bench::with(on_operator, None, &["bench", "pick", "place"])
    }

    /// A console as [`Bench::new`], opened as the profile `arm`, whose tour `rounds` visits
    /// `names` (each saved in the book).
    pub(crate) fn with(on_operator: bool, arm: Option<&str>, names: &[&str]) -> Bench {
        let config = AppConfig {
            positions_on_operator: on_operator,
            frames: !on_operator,
            arm_name: arm.map(str::to_string),
            ..app_support::config()
        };
        let mut app = App::new(config, PositionBook::new());
        let now = Instant::now();
        let source = if on_operator {
            TelemetrySource::TalosHardware
        } else {
            TelemetrySource::Modbus
        };
        app.handle(Input::Arm(ArmEvent::TelemetrySource(source)), now);
        app.handle(
            Input::Arm(ArmEvent::Status(LinkStatus::Up {
                description: "test".into(),
            })),
            now,
        );
        let mut bench = Bench {
            app,
            now,
            tool: crate::common::home_tcp(),
            move_type: MoveType::CartesianTrajectory,
        };
        bench.feed(0.0, ActionStatus::Completed);
        let mut book = PositionBook::new();
        for (i, name) in names.iter().enumerate() {
            let entry = book.get_or_insert(name);
            entry.cartesian = Some([4000 + 100 * i as i32, 1000, 3000]);
            entry.orientation = Some([90.0, 0.0, 90.0]);
        }
        book.set_tour(Tour {
            name: "rounds".into(),
            positions: names.iter().map(|n| n.to_string()).collect(),
        });
        bench
            .app
            .handle(Input::PositionsLoaded(Ok(book)), bench.now);
        bench
    }

    pub(crate) fn at(&mut self, after: Duration) -> Instant {
        self.now += after;
        self.now
    }

    pub(crate) fn press(&mut self, name: &str) -> Vec<Effect> {
        let now = self.at(ms(20));
        let key: KeyName = name.parse().expect("key name");
        let text = name.chars().next().filter(|_| name.chars().count() == 1);
        self.app.handle(
            Input::Key(KeyInput {
                key,
                text,
                kind: KeyKind::Press,
            }),
            now,
        )
    }

    pub(crate) fn type_text(&mut self, text: &str) {
        for c in text.chars() {
            self.press(&c.to_string());
        }
    }

    pub(crate) fn feed(&mut self, velocity: f32, status: ActionStatus) -> Vec<Effect> {
        let now = self.at(ms(100));
        let t = telemetry(velocity, status, self.move_type, self.tool);
        self.app
            .handle(Input::Arm(ArmEvent::Telemetry(Box::new(t))), now)
    }

    pub(crate) fn event(&mut self, event: ArmEvent) -> Vec<Effect> {
        let now = self.at(ms(5));
        self.app.handle(Input::Arm(event), now)
    }

    /// Opens the play form (`O` or `N`), takes the tour offered and says yes.
    pub(crate) fn play(&mut self, key: &str) -> Vec<Effect> {
        self.press(key);
        assert!(
            matches!(self.app.overlay(), Overlay::Form(_)),
            "{:?}",
            self.app.overlay()
        );
        self.press("enter");
        assert!(matches!(
            self.app.overlay(),
            Overlay::Confirm(Confirm::Tour(_))
        ));
        self.at(QUESTION_QUIET);
        self.press("y")
    }

    /// The arm takes the leg's command and reports it moving, the tool still where it was.
    pub(crate) fn leg_started(&mut self, command: ArmCommand) {
        self.event(ArmEvent::Done { command });
        self.feed(12.0, ActionStatus::Started);
    }

    /// The arm takes the leg's command, moves and reports it completed at rest where it was
    /// sent.
    pub(crate) fn finish_leg(&mut self, command: ArmCommand) -> Vec<Effect> {
        self.leg_started(command.clone());
        self.arrive(&command);
        self.feed(0.0, ActionStatus::Completed)
    }

    /// The tool is now where `command` sends it: the pose moved to, or the position the book
    /// has for a Go To.
    pub(crate) fn arrive(&mut self, command: &ArmCommand) {
        self.tool = match command {
            ArmCommand::MoveToPose(pose) => *pose,
            ArmCommand::GoToPosition { name } => {
                let entry = self.app.positions().get(name).expect("in the book");
                let [x, y, z] = entry
                    .cartesian
                    .expect("coordinates")
                    .map(|v| v as f32 / 1e4);
                let [theta_x, theta_y, theta_z] = entry.orientation.expect("orientation");
                Pose {
                    x,
                    y,
                    z,
                    theta_x,
                    theta_y,
                    theta_z,
                }
            }
            other => panic!("not a leg: {other:?}"),
        };
    }

    pub(crate) fn message(&self) -> String {
        crate::app_support::message(&self.app)
    }

    pub(crate) fn tour_label(&self) -> Option<String> {
        self.app.view().tour.map(|t| {
            format!(
                "TOUR {}/{} → {}{}",
                t.leg,
                t.legs,
                t.to,
                if t.waiting { " (waiting)" } else { "" }
            )
        })
    }
}

/// The one motion command in `effects`, which must be a leg's.
pub(crate) fn leg(effects: &[Effect]) -> ArmCommand {
    let legs: Vec<&ArmCommand> = effects
        .iter()
        .filter_map(|e| match e {
            Effect::Arm(c @ (ArmCommand::MoveToPose(_) | ArmCommand::GoToPosition { .. })) => {
                Some(c)
            }
            _ => None,
        })
        .collect();
    match legs.as_slice() {
        [one] => (*one).clone(),
        other => panic!("expected one leg's command, got {other:?} in {effects:?}"),
    }
}

pub(crate) fn pose_x(command: &ArmCommand) -> f32 {
    match command {
        ArmCommand::MoveToPose(pose) => pose.x,
        other => panic!("not a move to pose: {other:?}"),
    }
}

#[test]
fn a_tour_is_made_from_the_list_in_order_and_an_unknown_name_is_refused_by_name() {
    let mut b = Bench::new(false);
    b.press("M");
    let Overlay::Form(form) = b.app.overlay().clone() else {
        panic!("no form: {:?}", b.app.overlay());
    };
    assert_eq!(
        form.fields[1].value, "bench, pick, place",
        "the list, in order"
    );
    b.type_text("loop");
    b.press("tab");
    for _ in 0..30 {
        b.press("backspace");
    }
    b.type_text("place,nowhere,bench");
    let effects = b.press("enter");
    assert!(effects.is_empty(), "nothing saved: {effects:?}");
    let Overlay::Form(form) = b.app.overlay().clone() else {
        panic!("the form closed on an unknown name");
    };
    assert_eq!(
        form.error.as_deref(),
        Some("position 2 'nowhere' is not in the book")
    );
    for _ in 0..13 {
        b.press("backspace");
    }
    b.type_text("pick");
    let effects = b.press("enter");
    let saved = effects.iter().find_map(|e| match e {
        Effect::SavePositions(book) => Some(book.clone()),
        _ => None,
    });
    let saved = saved.expect("the book is written");
    assert_eq!(
        saved.tour("loop").map(|t| t.positions.clone()),
        Some(vec!["place".to_string(), "pick".to_string()])
    );
    assert_eq!(b.app.overlay(), &Overlay::None);
    assert_eq!(b.message(), "tour 'loop' saved: 2 leg(s)");
}

#[test]
fn straight_through_over_modbus_each_leg_starts_only_after_the_last_ended_at_rest() {
    let mut b = Bench::new(false);
    b.press("O");
    b.press("enter");
    let Overlay::Confirm(question) = b.app.overlay().clone() else {
        panic!("no question");
    };
    assert_eq!(
        question.question(),
        "Play tour 'rounds' straight through, 3 legs: bench → pick → place?"
    );
    // The question guard: a key typed as it opens answers nothing.
    let early = b.press("y");
    assert!(no_motion(&early), "{early:?}");
    assert!(matches!(b.app.overlay(), Overlay::Confirm(_)));
    b.at(QUESTION_QUIET);
    let first = leg(&b.press("y"));
    assert_eq!(pose_x(&first), 0.4);
    assert_eq!(b.tour_label().as_deref(), Some("TOUR 1/3 → bench"));
    assert_eq!(
        b.app.motion_shown(),
        MotionShown::Action {
            label: "GOTO bench".into(),
            confirmed: true
        }
    );
    // Moving, and not yet at rest: no second leg.
    b.event(ArmEvent::Done {
        command: first.clone(),
    });
    assert!(no_motion(&b.feed(12.0, ActionStatus::Started)));
    b.arrive(&first);
    let second = leg(&b.feed(0.0, ActionStatus::Completed));
    assert!((pose_x(&second) - 0.41).abs() < 1e-6);
    assert_eq!(b.tour_label().as_deref(), Some("TOUR 2/3 → pick"));
    let third = leg(&b.finish_leg(second));
    assert_eq!(b.tour_label().as_deref(), Some("TOUR 3/3 → place"));
    let end = b.finish_leg(third);
    assert!(no_motion(&end), "{end:?}");
    assert_eq!(b.tour_label(), None);
    assert_eq!(b.message(), "tour 'rounds' leg 3/3 → place: tour done");
    assert!(no_motion(&b.feed(0.0, ActionStatus::Completed)));
}

#[test]
fn one_leg_at_a_time_waits_for_the_next_leg_key_and_any_other_key_ends_it() {
    let mut b = Bench::new(false);
    let first = leg(&b.play("N"));
    let waiting = b.finish_leg(first);
    assert!(no_motion(&waiting), "nothing starts by itself: {waiting:?}");
    assert_eq!(
        b.tour_label().as_deref(),
        Some("TOUR 1/3 → bench (waiting)")
    );
    // The message names the next-leg key of the keymap in use.
    let said = b.message();
    assert!(said.contains("done: N for the next leg"), "{said}");
    assert!(no_motion(&b.feed(0.0, ActionStatus::Completed)));
    let second = leg(&b.press("N"));
    assert!((pose_x(&second) - 0.41).abs() < 1e-6);
    assert_eq!(b.tour_label().as_deref(), Some("TOUR 2/3 → pick"));
    b.finish_leg(second);
    // Waiting for leg 3: another key ends the tour, with no STOP needed (nothing moves).
    let effects = b.press("v");
    assert!(no_motion(&effects));
    assert_eq!(b.tour_label(), None);
    assert!(b.message().contains("leg 2/3 → pick"), "{}", b.message());
    // The next-leg key now asks which tour to play: it does not go on.
    let effects = b.press("N");
    assert!(no_motion(&effects));
    assert!(matches!(b.app.overlay(), Overlay::Form(_)));
}

#[test]
fn the_gate_is_asked_before_each_leg() {
    let mut b = Bench::new(false);
    let first = leg(&b.play("N"));
    b.finish_leg(first);
    // The guard goes down between legs: the next-leg key starts nothing.
    b.event(ArmEvent::Guard(
        armjog::link::interface::GuardStatus::Starting,
    ));
    let effects = b.press("N");
    assert!(no_motion(&effects), "{effects:?}");
    assert_eq!(b.tour_label(), None);
}
