//! Stored actions and sequences by id (`A`): the form's validation, the question before it
//! moves, the command sent, `MOVING: ACTION 5` through to the end the arm reports, any key
//! stopping it, an id the arm does not take failing within 2 s, the refusal without Modbus, and
//! nothing started after a cancel. Fake clock, no sockets.

use std::time::{Duration, Instant};

use armjog::console::app::{
    App, AppConfig, Effect, Input, MotionShown, Overlay, QUESTION_QUIET, STORED_REFUSAL, Severity,
};
use armjog::console::form::{Confirm, FormKind};
use armjog::console::view::View;
use armjog::console::{keymap::Keymap, positions::PositionBook, ui};
use armjog::kortex::{
    ActionState, ActionStatus, Coded, FlagSet, MoveType, RobotState, Stored, StoredMotion,
    Telemetry,
};
use armjog::link::interface::{ArmCommand, ArmEvent, LinkStatus, TelemetrySource};

use crate::app_support::{config, message, ms, press, row, screen};

const STOP: Effect = Effect::Arm(ArmCommand::Stop);

pub(crate) const ACTION_5: Stored = Stored {
    motion: StoredMotion::Action,
    id: 5,
};
const SEQUENCE_1: Stored = Stored {
    motion: StoredMotion::Sequence,
    id: 1,
};

/// A console on a 100x30 terminal whose driver said which telemetry comes, link up, at `t0`,
/// and (with telemetry) a ready arm at rest that last completed action 2 (home).
pub(crate) fn console(source: TelemetrySource) -> (App, Instant) {
    let modbus = source == TelemetrySource::Modbus;
    let config = AppConfig {
        keymap: Keymap::builtin("default").expect("default keymap").into(),
        positions_on_operator: !modbus,
        frames: modbus,
        ..config()
    };
    console_with(config, source)
}

/// [`console`] with `config`.
pub(crate) fn console_with(config: AppConfig, source: TelemetrySource) -> (App, Instant) {
    let mut app = App::new(config, PositionBook::new());
    let t0 = Instant::now();
    for event in [
        ArmEvent::TelemetrySource(source),
        ArmEvent::Status(LinkStatus::Up {
            description: "modbus 127.0.0.1:502 unit 1".into(),
        }),
        ArmEvent::Speed(50),
    ] {
        app.handle(Input::Arm(event), t0);
    }
    app.handle(
        Input::Resize {
            width: 100,
            height: 30,
        },
        t0,
    );
    if source != TelemetrySource::None {
        feed(
            &mut app,
            last_run(2, MoveType::Action, ActionStatus::Completed, 0.0),
            t0,
        );
    }
    (app, t0)
}

/// The arm at rest (or turning every joint at `velocity` deg/s), its status registers
/// reporting run `id` of `move_type` as `status`.
pub(crate) fn last_run(
    id: u16,
    move_type: MoveType,
    status: ActionStatus,
    velocity: f32,
) -> Telemetry {
    let action = ActionState {
        status: Coded::Known(status),
        id,
        move_type: Coded::Known(move_type),
    };
    crate::app_support::arm_telemetry(crate::app_support::HOME_JOINTS, velocity, action)
}

pub(crate) fn running(stored: Stored, velocity: f32) -> Telemetry {
    last_run(
        stored.id,
        move_type(stored),
        ActionStatus::Started,
        velocity,
    )
}

fn move_type(stored: Stored) -> MoveType {
    match stored.motion {
        StoredMotion::Action => MoveType::Action,
        StoredMotion::Sequence => MoveType::Sequence,
    }
}

pub(crate) fn feed(app: &mut App, t: Telemetry, now: Instant) -> Vec<Effect> {
    app.handle(Input::Arm(ArmEvent::Telemetry(Box::new(t))), now)
}

fn typed(app: &mut App, text: &str, now: Instant) {
    for c in text.chars() {
        press(app, &c.to_string(), now);
    }
}

fn form_error(app: &App) -> Option<String> {
    match app.overlay() {
        Overlay::Form(form) => form.error.clone(),
        other => panic!("no form open: {other:?}"),
    }
}

pub(crate) fn moving(label: &str) -> MotionShown {
    MotionShown::Action {
        label: label.into(),
        confirmed: true,
    }
}

/// `A`, the id typed, enter: the question, answered yes once it may be. Returns the effects of
/// the yes; the link then reports the writes done.
pub(crate) fn start(app: &mut App, id: &str, now: Instant) -> Vec<Effect> {
    press(app, "A", now - QUESTION_QUIET - ms(10));
    typed(app, id, now - QUESTION_QUIET - ms(10));
    press(app, "enter", now - QUESTION_QUIET);
    let effects = press(app, "y", now);
    for effect in &effects {
        if let Effect::Arm(command @ ArmCommand::StartStored(_)) = effect {
            app.handle(
                Input::Arm(ArmEvent::Done {
                    command: command.clone(),
                }),
                now + ms(5),
            );
        }
    }
    effects
}

#[test]
fn the_form_refuses_a_bad_id_or_kind_naming_it_and_asks_before_it_moves() {
    let (mut app, t0) = console(TelemetrySource::Modbus);
    assert_eq!(press(&mut app, "A", t0), []);
    let Overlay::Form(form) = app.overlay() else {
        panic!("the form opens: {:?}", app.overlay());
    };
    assert_eq!(form.kind, FormKind::Stored);
    assert_eq!(form.fields[0].value, "action", "the kind is prefilled");
    assert_eq!(form.focus, 1, "the id is where typing goes");
    for (id, said) in [
        ("", "id is empty: type a whole number from 1 to 65535"),
        ("0", "id: 0 is outside 1 to 65535"),
        ("70000", "id: 70000 is outside 1 to 65535"),
        ("x5", "id: 'x5' is not a whole number from 1 to 65535"),
    ] {
        typed(&mut app, id, t0);
        assert_eq!(press(&mut app, "enter", t0), [], "{id}: nothing sent");
        assert_eq!(form_error(&app).as_deref(), Some(said));
        for _ in id.chars() {
            press(&mut app, "backspace", t0);
        }
    }
    // The kind: up to it, a wrong word, then the right one.
    press(&mut app, "up", t0);
    for _ in "action".chars() {
        press(&mut app, "backspace", t0);
    }
    typed(&mut app, "tour", t0);
    press(&mut app, "down", t0);
    typed(&mut app, "1", t0);
    assert_eq!(press(&mut app, "enter", t0), []);
    assert_eq!(
        form_error(&app).as_deref(),
        Some("kind: 'tour' is neither action nor sequence")
    );
    for _ in "tour".chars() {
        press(&mut app, "backspace", t0);
    }
    typed(&mut app, "sequence", t0);
    assert_eq!(press(&mut app, "enter", t0), [], "asks first");
    assert_eq!(
        *app.overlay(),
        Overlay::Confirm(Confirm::Stored(SEQUENCE_1))
    );
    assert_eq!(
        Confirm::Stored(ACTION_5).question(),
        "Run action 5 on the arm?"
    );
    assert_eq!(
        Confirm::Stored(SEQUENCE_1).question(),
        "Run sequence 1 on the arm?"
    );
    // The question guard: a yes typed as it opens does not count.
    assert_eq!(press(&mut app, "y", t0 + ms(10)), []);
    assert_eq!(
        message(&app),
        "key ignored: the question has only just opened"
    );
    let yes = press(&mut app, "y", t0 + QUESTION_QUIET + ms(20));
    assert_eq!(yes, [Effect::Arm(ArmCommand::StartStored(SEQUENCE_1))]);
    assert_eq!(app.motion_shown(), moving("SEQUENCE 1"));
}

#[test]
fn action_5_shows_moving_until_the_arm_reports_it_completed_at_rest() {
    let (mut app, t0) = console(TelemetrySource::Modbus);
    let effects = start(&mut app, "5", t0);
    assert_eq!(effects, [Effect::Arm(ArmCommand::StartStored(ACTION_5))]);
    assert_eq!(app.motion_shown(), moving("ACTION 5"));
    // The status registers still describe home's last run: not this one's end.
    let before = last_run(2, MoveType::Action, ActionStatus::Completed, 0.0);
    feed(&mut app, before, t0 + ms(40));
    assert_eq!(app.motion_shown(), moving("ACTION 5"));
    for n in 1..30 {
        feed(&mut app, running(ACTION_5, 10.0), t0 + ms(40 + 100 * n));
        assert_eq!(app.motion_shown(), moving("ACTION 5"), "poll {n}");
    }
    let done = last_run(5, MoveType::Action, ActionStatus::Completed, 0.0);
    assert_eq!(feed(&mut app, done, t0 + ms(3100)), []);
    assert_eq!(app.motion_shown(), MotionShown::Idle);
    assert_eq!(message(&app), "action 5 done");
}

#[test]
fn an_abort_or_a_fault_is_a_failure_naming_the_kind_and_id() {
    let (mut app, t0) = console(TelemetrySource::Modbus);
    start(&mut app, "5", t0);
    feed(&mut app, running(ACTION_5, 10.0), t0 + ms(50));
    let aborted = last_run(5, MoveType::Action, ActionStatus::Aborted, 0.0);
    assert_eq!(feed(&mut app, aborted, t0 + ms(90)), [STOP]);
    assert_eq!(
        app.message(),
        Some(("action 5 failed: aborted", Severity::Error))
    );
    assert!(app.motion_truth().action().is_none());

    let (mut second, t0) = console(TelemetrySource::Modbus);
    start(&mut second, "5", t0);
    let mut fault = running(ACTION_5, 0.0);
    fault.robot_state = Coded::Known(RobotState::InFault);
    fault.faults = FlagSet::from_bits(armjog::kortex::Flag::EmergencyStop.bit());
    assert_eq!(feed(&mut second, fault, t0 + ms(40)), [STOP]);
    assert_eq!(
        message(&second),
        "action 5 failed: the arm is in fault: emergency_stop"
    );
}

#[test]
fn an_id_the_arm_does_not_take_fails_within_2_s_naming_it() {
    let (mut app, t0) = console(TelemetrySource::Modbus);
    start(&mut app, "99", t0);
    assert_eq!(app.motion_shown(), moving("ACTION 99"));
    // The arm goes on reporting home's last run: not taken, but not said before 2 s.
    let other = last_run(2, MoveType::Action, ActionStatus::Completed, 0.0);
    for n in 1..=19 {
        let effects = feed(&mut app, other.clone(), t0 + ms(5 + 100 * n));
        assert_eq!(effects, [], "poll {n}");
        assert_eq!(app.motion_shown(), moving("ACTION 99"), "poll {n}");
    }
    let effects = feed(&mut app, other, t0 + ms(5) + Duration::from_secs(2));
    assert_eq!(effects, [STOP], "a STOP settles the doubt");
    let (text, severity) = app.message().expect("said");
    assert_eq!(severity, Severity::Error);
    assert!(
        text.starts_with("action 99 failed: the arm did not take action 99 within 2 s"),
        "{text}"
    );
    assert!(text.contains("Web App, Actions page"), "{text}");
    assert!(app.motion_truth().action().is_none());
}

#[test]
fn any_key_stops_a_stored_run_and_does_nothing_else() {
    for key in ["v", "w", "?", "A", "q"] {
        let (mut app, t0) = console(TelemetrySource::Modbus);
        start(&mut app, "5", t0);
        feed(&mut app, running(ACTION_5, 10.0), t0 + ms(50));
        let effects = press(&mut app, key, t0 + ms(100));
        assert_eq!(effects, [STOP], "{key}");
        assert_eq!(message(&app), "action 5 stopped", "{key}");
        assert_eq!(*app.overlay(), Overlay::None, "{key}: nothing opened");
        assert!(app.motion_truth().action().is_none(), "{key}");
        assert!(!app.quitting(), "{key}");
    }
    // Home is a stored run too.
    let (mut app, t0) = console(TelemetrySource::Modbus);
    press(&mut app, "h", t0);
    let yes = press(&mut app, "y", t0 + QUESTION_QUIET);
    assert_eq!(yes, [Effect::Arm(ArmCommand::Home)]);
    assert_eq!(app.motion_shown(), moving("HOME"));
    assert_eq!(press(&mut app, "p", t0 + ms(400)), [STOP]);
    assert_eq!(message(&app), "home stopped");
    assert_eq!(*app.overlay(), Overlay::None, "the save form did not open");
}

#[test]
fn over_a_talos_only_link_the_key_says_why_and_the_footer_leaves_it_out() {
    for source in [TelemetrySource::TalosHardware, TelemetrySource::None] {
        let (mut app, t0) = console(source);
        assert!(!app.can_run_stored());
        assert_eq!(press(&mut app, "A", t0), []);
        assert_eq!(*app.overlay(), Overlay::None, "no form");
        assert_eq!(app.message(), Some((STORED_REFUSAL, Severity::Warning)));
        assert!(STORED_REFUSAL.contains("Modbus"), "{STORED_REFUSAL}");
        assert!(!footer(&app).contains("A stored"), "{}", footer(&app));
        assert!(
            footer(&app).contains("h home"),
            "home still runs over Talos"
        );
    }
    let (app, _) = console(TelemetrySource::Modbus);
    assert!(app.can_run_stored());
    assert!(
        footer(&app).contains("h home  A stored"),
        "{}",
        footer(&app)
    );
}

/// The footer as the view offers it, at 200 columns.
fn footer(app: &App) -> String {
    let view = View::new(app);
    ui::hints::footer(&view.session.keymap, view.session.link_actions, 200)
}

#[test]
fn nothing_starts_after_the_form_is_cancelled_or_the_question_answered_no() {
    let (mut app, t0) = console(TelemetrySource::Modbus);
    press(&mut app, "A", t0);
    typed(&mut app, "5", t0);
    assert_eq!(press(&mut app, "esc", t0), []);
    assert_eq!(*app.overlay(), Overlay::None);
    assert_eq!(message(&app), "cancelled");
    // Fresh telemetry: a stale link would refuse the key.
    let t = last_run(2, MoveType::Action, ActionStatus::Completed, 0.0);
    feed(&mut app, t, t0 + ms(450));
    press(&mut app, "A", t0 + ms(500));
    typed(&mut app, "5", t0 + ms(500));
    press(&mut app, "enter", t0 + ms(500));
    assert_eq!(*app.overlay(), Overlay::Confirm(Confirm::Stored(ACTION_5)));
    assert_eq!(press(&mut app, "n", t0 + ms(800)), []);
    assert_eq!(message(&app), "cancelled");
    // Time passing and telemetry coming start nothing either.
    for n in 1..20 {
        let t = last_run(2, MoveType::Action, ActionStatus::Completed, 0.0);
        assert_eq!(feed(&mut app, t, t0 + ms(800 + 100 * n)), []);
        assert_eq!(app.handle(Input::Tick, t0 + ms(850 + 100 * n)), []);
    }
    assert_eq!(app.motion_shown(), MotionShown::Idle);
}

#[test]
fn the_motion_gate_refuses_a_stored_run_on_an_arm_in_fault() {
    let (mut app, t0) = console(TelemetrySource::Modbus);
    press(&mut app, "A", t0);
    typed(&mut app, "5", t0);
    press(&mut app, "enter", t0);
    // The arm faults while the question is open: the yes starts nothing.
    let mut fault = last_run(2, MoveType::Action, ActionStatus::Completed, 0.0);
    fault.robot_state = Coded::Known(RobotState::InFault);
    fault.faults = FlagSet::from_bits(armjog::kortex::Flag::EmergencyStop.bit());
    feed(&mut app, fault, t0 + ms(50));
    assert_eq!(press(&mut app, "y", t0 + QUESTION_QUIET + ms(20)), []);
    assert_eq!(message(&app), "refused: the arm reports emergency_stop");
    // And the key itself does not open the form.
    assert_eq!(press(&mut app, "A", t0 + ms(600)), []);
    assert_eq!(*app.overlay(), Overlay::None);
}

#[test]
fn the_dialog_and_the_status_bar_while_it_moves() {
    let (mut app, t0) = console(TelemetrySource::Modbus);
    press(&mut app, "A", t0);
    typed(&mut app, "0", t0);
    press(&mut app, "enter", t0);
    insta::assert_snapshot!("stored_form_with_an_error", screen(&app, 100, 30).backend());
    press(&mut app, "backspace", t0);
    typed(&mut app, "5", t0);
    press(&mut app, "enter", t0);
    insta::assert_snapshot!("stored_question", screen(&app, 100, 30).backend());
    press(&mut app, "y", t0 + QUESTION_QUIET);
    feed(
        &mut app,
        running(ACTION_5, 10.0),
        t0 + QUESTION_QUIET + ms(40),
    );
    let terminal = screen(&app, 100, 30);
    let status = [row(&terminal, 0), row(&terminal, 1)].join("\n");
    assert!(status.contains("MOVING: ACTION 5"), "{status}");
    insta::assert_snapshot!("stored_status_bar_moving", status);
}
