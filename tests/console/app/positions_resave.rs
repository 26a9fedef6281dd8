//! A name the Talos operator has lost: the console does not send the doomed Go To. It offers to
//! re-save the name from the remembered coordinates (Set Cartesian Position) and goes there once
//! the operator has them, and only then, with nothing in between.

use armjog::console::app::QUESTION_QUIET;
use std::time::{Duration, Instant};

use armjog::console::app::{App, Effect, Input, Overlay, RESAVE_GO_WITHIN};
use armjog::console::form::Confirm;
use armjog::console::jog::ReleaseMode;
use armjog::console::positions::PositionBook;
use armjog::link::interface::{ArmCommand, ArmError, ArmEvent, CommandKind, LinkStatus};
use armjog::talos::ReturnCode;

use crate::app_support::{app, ms, press};

const PICK: [i32; 3] = [5000, -1205, 2500];

/// An app on an operator, with "pick" remembered at [`PICK`] and "ghost" with no coordinates.
fn remembering() -> (App, Instant) {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    let mut book = PositionBook::new();
    book.get_or_insert("pick").cartesian = Some(PICK);
    book.get_or_insert("ghost");
    app.handle(Input::PositionsLoaded(Ok(book)), t0);
    (app, t0)
}

/// The operator answered "unknown position" for `name` when asked at link-up.
fn lost(app: &mut App, name: &str, now: Instant) {
    app.handle(
        Input::Arm(ArmEvent::UnknownPosition { name: name.into() }),
        now,
    );
}

fn select(app: &mut App, name: &str, now: Instant) {
    while app.selected_name() != Some(name) {
        press(app, "pagedown", now);
    }
}

fn resave_of_pick() -> ArmCommand {
    let [x, y, z] = PICK;
    ArmCommand::SetCartesianPosition {
        name: "pick".into(),
        x,
        y,
        z,
    }
}

fn goes_to(effects: &[Effect]) -> bool {
    effects
        .iter()
        .any(|e| matches!(e, Effect::Arm(ArmCommand::GoToPosition { .. })))
}

fn done(app: &mut App, command: ArmCommand, now: Instant) -> Vec<Effect> {
    app.handle(Input::Arm(ArmEvent::Done { command }), now)
}

#[test]
fn going_to_a_lost_name_offers_the_resave_and_goes_there_once_the_operator_has_it() {
    let (mut app, t0) = remembering();
    lost(&mut app, "pick", t0);
    select(&mut app, "pick", t0);
    let effects = press(&mut app, "o", t0);
    assert!(!goes_to(&effects), "{effects:?}");
    assert_eq!(
        app.overlay(),
        &Overlay::Confirm(Confirm::Resave("pick".into()))
    );
    let question = Confirm::Resave("pick".into()).question();
    assert!(
        question.contains("unknown to the operator")
            && question.contains("re-save it from the remembered coordinates"),
        "{question}"
    );
    let effects = press(&mut app, "y", t0 + ms(10) + QUESTION_QUIET);
    assert!(
        effects.contains(&Effect::Arm(resave_of_pick())),
        "{effects:?}"
    );
    assert!(
        !goes_to(&effects),
        "no Go To before the operator has the name"
    );
    let effects = done(&mut app, resave_of_pick(), t0 + ms(60));
    assert!(
        effects.contains(&Effect::Arm(ArmCommand::GoToPosition {
            name: "pick".into()
        })),
        "{effects:?}"
    );
    let entry = app.positions().get("pick").expect("kept");
    assert!(!entry.unknown_to_operator);
    assert_eq!(entry.cartesian, Some(PICK));
}

#[test]
fn no_is_no_and_nothing_is_sent() {
    let (mut app, t0) = remembering();
    lost(&mut app, "pick", t0);
    select(&mut app, "pick", t0);
    press(&mut app, "o", t0);
    let effects = press(&mut app, "n", t0 + ms(10) + QUESTION_QUIET);
    assert!(
        !effects.iter().any(|e| matches!(e, Effect::Arm(_))),
        "{effects:?}"
    );
    assert_eq!(app.overlay(), &Overlay::None);
}

/// Confirms the re-save of "pick", as above, and returns the time of the "yes".
fn resave_confirmed(app: &mut App, t0: Instant) -> Instant {
    lost(app, "pick", t0);
    select(app, "pick", t0);
    press(app, "o", t0);
    let yes = t0 + ms(10) + QUESTION_QUIET;
    let effects = press(app, "y", yes);
    assert!(
        effects.contains(&Effect::Arm(resave_of_pick())),
        "{effects:?}"
    );
    yes
}

#[test]
fn a_key_focus_loss_or_link_loss_before_the_operator_answers_cancels_the_go_to() {
    let interruptions: [fn(&mut App, Instant); 3] = [
        |app, now| {
            press(app, "space", now);
        },
        |app, now| {
            app.handle(Input::FocusLost, now);
        },
        |app, now| {
            app.handle(
                Input::Arm(ArmEvent::Status(LinkStatus::Down {
                    reason: "cable".into(),
                })),
                now,
            );
            app.handle(
                Input::Arm(ArmEvent::Status(LinkStatus::Up {
                    description: "back".into(),
                })),
                now + ms(1),
            );
        },
    ];
    for (i, interrupt) in interruptions.into_iter().enumerate() {
        let (mut app, t0) = remembering();
        let yes = resave_confirmed(&mut app, t0);
        interrupt(&mut app, yes + ms(20));
        let effects = done(&mut app, resave_of_pick(), yes + ms(40));
        assert!(!goes_to(&effects), "interruption {i}: {effects:?}");
        assert!(
            !app.positions()
                .get("pick")
                .is_some_and(|e| e.unknown_to_operator),
            "the name is re-saved all the same"
        );
    }
}

#[test]
fn an_answer_after_the_window_re_saves_without_moving() {
    let (mut app, t0) = remembering();
    let yes = resave_confirmed(&mut app, t0);
    let late = yes + RESAVE_GO_WITHIN + ms(1);
    let effects = done(&mut app, resave_of_pick(), late);
    assert!(!goes_to(&effects), "{effects:?}");
    let (text, _) = app.message().expect("a message");
    assert!(text.contains("go to it again"), "{text}");
}

#[test]
fn a_refused_resave_goes_nowhere() {
    let (mut app, t0) = remembering();
    let yes = resave_confirmed(&mut app, t0);
    app.handle(
        Input::Arm(ArmEvent::Failed {
            command: CommandKind::SetCartesianPosition,
            error: ArmError::ReturnCode(ReturnCode::OUT_OF_RANGE),
        }),
        yes + ms(20),
    );
    // A stray late success for the same name must not move either.
    let effects = done(&mut app, resave_of_pick(), yes + ms(30));
    assert!(!goes_to(&effects), "{effects:?}");
}

#[test]
fn a_go_to_that_fails_with_unknown_position_offers_the_resave() {
    let (mut app, t0) = remembering();
    select(&mut app, "pick", t0);
    press(&mut app, "o", t0);
    assert_eq!(
        app.overlay(),
        &Overlay::Confirm(Confirm::GoTo("pick".into())),
        "not known to be lost: the usual question"
    );
    let effects = press(&mut app, "y", t0 + ms(10) + QUESTION_QUIET);
    assert!(goes_to(&effects), "{effects:?}");
    // What the driver reports when the operator answers UNKNOWN_POSITION.
    lost(&mut app, "pick", t0 + ms(20));
    app.handle(
        Input::Arm(ArmEvent::Failed {
            command: CommandKind::GoToPosition,
            error: ArmError::ReturnCode(ReturnCode::UNKNOWN_POSITION),
        }),
        t0 + ms(20),
    );
    assert_eq!(
        app.overlay(),
        &Overlay::Confirm(Confirm::Resave("pick".into()))
    );
    let (text, _) = app.message().expect("a message");
    assert!(text.contains("does not know 'pick'"), "{text}");
    let effects = press(&mut app, "y", t0 + ms(500));
    assert!(
        effects.contains(&Effect::Arm(resave_of_pick())),
        "{effects:?}"
    );
}

#[test]
fn a_lost_name_without_coordinates_is_neither_gone_to_nor_offered() {
    let (mut app, t0) = remembering();
    lost(&mut app, "ghost", t0);
    select(&mut app, "ghost", t0);
    let effects = press(&mut app, "o", t0);
    assert!(!goes_to(&effects), "{effects:?}");
    assert_eq!(app.overlay(), &Overlay::None);
    let (text, _) = app.message().expect("a message");
    assert!(text.contains("no coordinates"), "{text}");
    // A later step must not find a stale re-save to finish.
    let effects = done(&mut app, resave_of_pick(), t0 + Duration::from_millis(5));
    assert!(!goes_to(&effects));
}
