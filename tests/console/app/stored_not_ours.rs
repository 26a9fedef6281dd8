//! Another client's move under our Modbus home (`h`) or our stored action (`A`): once ours was
//! seen started, an action status naming another id or move type (registers 100-102) is not
//! ours. The console stops, says `MOVED BY ANOTHER CLIENT`, and never says done. Fake clock.

use armjog::console::app::{AppConfig, Effect, MotionShown, QUESTION_QUIET};
use armjog::kortex::{ActionStatus, MoveType, Stored, StoredMotion};
use armjog::link::interface::{ArmCommand, ArmEvent, TelemetrySource};

use super::stored_actions::{
    ACTION_5, console, console_with, feed, last_run, moving, running, start,
};
use crate::app_support::{STOP, config, message, ms, no_motion, press};
use armjog::console::app::Input;

const HOME_ACTION: Stored = Stored {
    motion: StoredMotion::Action,
    id: 2,
};

#[test]
fn another_clients_move_under_our_stored_action_stops_it_and_is_never_done() {
    for (move_type, id, theirs) in [
        // `armjog modbus action --id 3` from elsewhere: the arm runs Retract instead.
        (MoveType::Action, 3, "action 3"),
        // The same id as a sequence is another run.
        (MoveType::Sequence, 5, "sequence 5"),
        // A second console's go-to or jog.
        (MoveType::CartesianTrajectory, 0, "cartesian trajectory"),
        (MoveType::Twist, 0, "twist"),
    ] {
        let (mut app, t0) = console(TelemetrySource::Modbus);
        start(&mut app, "5", t0);
        // Ours runs for a while: past the 2 s an arm has to take a run.
        for n in 1..=30 {
            assert_eq!(
                feed(&mut app, running(ACTION_5, 10.0), t0 + ms(100 * n)),
                []
            );
        }
        let other = last_run(id, move_type, ActionStatus::Started, 10.0);
        let effects = feed(&mut app, other, t0 + ms(3100));
        assert_eq!(effects, [STOP], "{theirs}");
        assert_eq!(
            message(&app),
            format!(
                "action 5 not done: MOVED BY ANOTHER CLIENT: the arm runs {theirs}, not our \
                 action 5; STOP sent"
            )
        );
        assert!(app.motion_truth().action().is_none(), "{theirs}");
        assert_ne!(app.motion_shown(), moving("ACTION 5"), "{theirs}");
        // Its end at rest is not ours: nothing says done, nothing moves.
        let said = message(&app);
        let end = last_run(id, move_type, ActionStatus::Completed, 0.0);
        let effects = feed(&mut app, end, t0 + ms(3200));
        assert!(no_motion(&effects), "{effects:?}");
        assert_eq!(message(&app), said, "{theirs}");
    }
}

/// A console over Modbus alone, whose home is the stored action 2: `h`, yes, taken.
fn home_started() -> (armjog::console::app::App, std::time::Instant) {
    let config = AppConfig {
        positions_on_operator: false,
        frames: true,
        home_action: Some(HOME_ACTION),
        ..config()
    };
    let (mut app, t0) = console_with(config, TelemetrySource::Modbus);
    press(&mut app, "h", t0);
    let yes = press(&mut app, "y", t0 + QUESTION_QUIET);
    assert_eq!(yes, [Effect::Arm(ArmCommand::Home)]);
    app.handle(
        Input::Arm(ArmEvent::Done {
            command: ArmCommand::Home,
        }),
        t0 + QUESTION_QUIET + ms(5),
    );
    (app, t0 + QUESTION_QUIET)
}

#[test]
fn another_clients_action_under_our_modbus_home_stops_it_and_is_never_home_done() {
    let (mut app, t0) = home_started();
    for n in 1..=10 {
        assert_eq!(
            feed(&mut app, running(HOME_ACTION, 10.0), t0 + ms(100 * n)),
            []
        );
    }
    assert_eq!(app.motion_shown(), moving("HOME"));
    // `armjog modbus action --id 5` from elsewhere: the arm runs Zero instead.
    let zero = last_run(5, MoveType::Action, ActionStatus::Started, 10.0);
    assert_eq!(feed(&mut app, zero, t0 + ms(1100)), [STOP]);
    assert_eq!(
        message(&app),
        "home not done: MOVED BY ANOTHER CLIENT: the arm runs action 5, not our action 2; \
         STOP sent"
    );
    assert!(app.motion_truth().action().is_none());
    let said = message(&app);
    let end = last_run(5, MoveType::Action, ActionStatus::Completed, 0.0);
    assert_eq!(feed(&mut app, end, t0 + ms(1200)), []);
    assert_eq!(message(&app), said);
    assert_ne!(app.motion_shown(), moving("HOME"));
}

#[test]
fn our_modbus_home_is_done_when_the_arm_reports_our_action_completed_at_rest() {
    let (mut app, t0) = home_started();
    // The status still describes home's last run at first: not this one's end.
    let before = last_run(2, MoveType::Action, ActionStatus::Completed, 0.0);
    assert_eq!(feed(&mut app, before, t0 + ms(50)), []);
    assert_eq!(app.motion_shown(), moving("HOME"));
    for n in 1..=10 {
        feed(&mut app, running(HOME_ACTION, 10.0), t0 + ms(50 + 100 * n));
    }
    let done = last_run(2, MoveType::Action, ActionStatus::Completed, 0.0);
    assert_eq!(feed(&mut app, done, t0 + ms(1200)), []);
    assert_eq!(message(&app), "home done");
    assert_eq!(app.motion_shown(), MotionShown::Idle);
}
