//! The positions a tour visits, edited, on a fake clock: a rename carries into the tour (over
//! the operator once it has the new name), a delete names the tours it breaks and undo makes
//! them whole, and a tour naming a deleted position is refused before any question.

use armjog::console::app::{Effect, Input, Overlay, QUESTION_QUIET};
use armjog::console::positions::Tour;
use armjog::link::interface::{ArmCommand, ArmEvent};

use super::tours::{Bench, leg, pose_x};
use crate::app_support::no_motion;

#[test]
fn a_tour_naming_a_deleted_position_is_refused_with_its_name_before_any_question() {
    let mut b = Bench::new(false);
    b.press("pagedown");
    assert_eq!(b.app.selected_name(), Some("pick"));
    b.press("delete");
    b.at(QUESTION_QUIET);
    b.press("y");
    assert!(b.app.positions().get("pick").is_none());
    b.press("O");
    let effects = b.press("enter");
    assert!(no_motion(&effects));
    assert_eq!(b.app.overlay(), &Overlay::None, "no question");
    assert_eq!(
        b.message(),
        "tour 'rounds' cannot be played: leg 2/3: 'pick' is not in the book"
    );
}

#[test]
fn renaming_a_position_a_tour_visits_carries_into_the_tour() {
    let mut b = Bench::new(false);
    b.press("pagedown");
    b.press("R");
    b.type_text("up");
    let effects = b.press("enter");
    let saved = effects.iter().find_map(|e| match e {
        Effect::SavePositions(save) => save.tour("rounds").map(Tour::legs_text),
        _ => None,
    });
    assert_eq!(
        saved.as_deref(),
        Some("bench → pickup → place"),
        "{effects:?}"
    );
    assert_eq!(
        b.message(),
        "renamed 'pick' to 'pickup', in tour 'rounds' too"
    );
    // The tour plays through the new name.
    let first = leg(&b.play("N"));
    b.finish_leg(first);
    let second = leg(&b.press("N"));
    assert_eq!(pose_x(&second), 0.41, "the renamed position's pose");
}

#[test]
fn renaming_on_the_operator_carries_into_the_tour_once_the_operator_has_it() {
    let mut b = Bench::new(true);
    b.press("pagedown");
    b.press("R");
    b.type_text("up");
    b.press("enter");
    let unchanged = b.app.positions().tour("rounds").map(Tour::legs_text);
    assert_eq!(
        unchanged.as_deref(),
        Some("bench → pick → place"),
        "not yet"
    );
    b.event(ArmEvent::Position {
        name: "pick".into(),
        coordinates: armjog::link::interface::PositionCoordinates {
            cartesian: Some([4100, 1000, 3000]),
            polar: None,
        },
    });
    b.event(ArmEvent::Done {
        command: ArmCommand::SetCartesianPosition {
            name: "pickup".into(),
            x: 4100,
            y: 1000,
            z: 3000,
        },
    });
    let effects = b.event(ArmEvent::Done {
        command: ArmCommand::DeletePosition {
            name: "pick".into(),
        },
    });
    assert!(
        effects
            .iter()
            .any(|e| matches!(e, Effect::SavePositions(_)))
    );
    let renamed = b.app.positions().tour("rounds").map(Tour::legs_text);
    assert_eq!(renamed.as_deref(), Some("bench → pickup → place"));
    assert_eq!(
        b.message(),
        "renamed 'pick' to 'pickup', in tour 'rounds' too"
    );
}

#[test]
fn deleting_a_position_a_tour_visits_names_the_tour_and_undo_makes_the_tour_whole() {
    let mut b = Bench::new(false);
    let mut book = b.app.positions().clone();
    book.set_tour(Tour {
        name: "short".into(),
        positions: vec!["pick".into()],
    });
    b.app.handle(Input::PositionsLoaded(Ok(book)), b.now);
    b.press("pagedown");
    b.press("delete");
    let Overlay::Confirm(question) = b.app.overlay().clone() else {
        panic!("no question: {:?}", b.app.overlay())
    };
    assert_eq!(
        question.question(),
        "Delete position 'pick'? Tours 'rounds' and 'short' visit it and cannot be played \
         without it (undo restores it)"
    );
    b.at(QUESTION_QUIET);
    b.press("y");
    assert_eq!(
        b.message(),
        "deleted 'pick': tours 'rounds' and 'short' cannot be played without it (undo restores \
         it)"
    );
    // The tours keep the name: undo brings the position back and the tour plays whole.
    b.press("u");
    assert!(b.app.positions().get("pick").is_some());
    let first = leg(&b.play("N"));
    b.finish_leg(first);
    assert!(matches!(leg(&b.press("N")), ArmCommand::MoveToPose(_)));
}
