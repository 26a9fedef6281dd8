//! Saving over a name asks first, renaming, and undoing the last delete, on a fake clock: in
//! the console's own book (Modbus) and on a Talos operator, step by step with its answers.

use crate::app_support::message;
use armjog::console::app::QUESTION_QUIET;
use std::time::Instant;

use armjog::console::action::Action;
use armjog::console::app::{App, Effect, Input, Overlay};
use armjog::console::form::Confirm;
use armjog::console::jog::ReleaseMode;
use armjog::console::keymap::{KeyName, Keymap};
use armjog::console::positions::PositionBook;
use armjog::link::interface::{ArmCommand, ArmError, ArmEvent, CommandKind, PositionCoordinates};
use armjog::talos::ReturnCode;

use crate::app_support;

use app_support::*;

/// A console whose book holds "bench" and "pick" (selected), with coordinates and, for
/// "pick", an orientation.
fn with_book(on_operator: bool) -> (App, Instant) {
    let (mut app, t0) = app(ReleaseMode::Reported, on_operator);
    let mut book = PositionBook::new();
    book.get_or_insert("bench").cartesian = Some([3000, 3000, 800]);
    let pick = book.get_or_insert("pick");
    pick.cartesian = Some([5000, -1205, 2500]);
    pick.orientation = Some([90.0, 0.0, 90.0]);
    app.handle(Input::PositionsLoaded(Ok(book)), t0);
    press(&mut app, "pagedown", t0);
    assert_eq!(app.selected_name(), Some("pick"));
    (app, t0)
}

fn type_text(app: &mut App, text: &str, now: Instant) {
    for c in text.chars() {
        press(app, &c.to_string(), now);
    }
}

fn clear_field(app: &mut App, now: Instant) {
    for _ in 0..40 {
        press(app, "backspace", now);
    }
}

fn arm(app: &mut App, event: ArmEvent, now: Instant) -> Vec<Effect> {
    app.handle(Input::Arm(event), now)
}

fn done(app: &mut App, command: ArmCommand, now: Instant) -> Vec<Effect> {
    arm(app, ArmEvent::Done { command }, now)
}

fn failed(app: &mut App, command: CommandKind, now: Instant) -> Vec<Effect> {
    let error = ArmError::ReturnCode(ReturnCode::BUSY);
    arm(app, ArmEvent::Failed { command, error }, now)
}

fn set_cartesian(name: &str, [x, y, z]: [i32; 3]) -> Effect {
    Effect::Arm(ArmCommand::SetCartesianPosition {
        name: name.into(),
        x,
        y,
        z,
    })
}

fn names(app: &App) -> Vec<String> {
    app.positions().names().map(str::to_string).collect()
}

// ---- Overwrite ----

#[test]
fn saving_over_an_existing_name_asks_and_sends_nothing_before_yes() {
    let (mut app, t0) = with_book(true);
    press(&mut app, "p", t0);
    type_text(&mut app, "bench", t0);
    assert!(press(&mut app, "enter", t0).is_empty(), "asks first");
    let Overlay::Confirm(confirm) = app.overlay() else {
        panic!("no question: {:?}", app.overlay())
    };
    assert!(matches!(confirm, Confirm::Overwrite { .. }));
    assert_eq!(confirm.question(), "overwrite 'bench'?");
    // Neither a second enter, nor n, nor esc says yes: each goes back to the form as typed.
    let mut asked = t0;
    for no in ["enter", "n", "esc"] {
        asked += QUESTION_QUIET;
        assert!(press(&mut app, no, asked).is_empty(), "{no}");
        let Overlay::Form(form) = app.overlay() else {
            panic!("{no}: the form did not come back: {:?}", app.overlay())
        };
        assert_eq!(form.fields[0].value, "bench", "{no}");
        assert!(
            form.error
                .as_deref()
                .unwrap_or("")
                .contains("'bench' exists"),
            "{no}"
        );
        assert!(
            press(&mut app, "enter", asked).is_empty(),
            "{no}: asks again"
        );
    }
    let save = ArmCommand::SavePosition {
        name: "bench".into(),
        anchor: false,
        parent: None,
    };
    assert_eq!(
        press(&mut app, "y", asked + QUESTION_QUIET),
        [Effect::Arm(save)]
    );
    assert_eq!(*app.overlay(), Overlay::None);
}

#[test]
fn a_new_name_is_saved_without_a_question() {
    let (mut app, t0) = with_book(true);
    press(&mut app, "p", t0);
    type_text(&mut app, "table", t0);
    assert_eq!(press(&mut app, "enter", t0).len(), 1, "sent at once");
}

#[test]
fn defining_a_position_over_an_existing_name_in_the_book_asks_first() {
    let (mut app, t0) = with_book(false);
    press(&mut app, "C", t0);
    clear_field(&mut app, t0);
    type_text(&mut app, "bench", t0);
    for value in ["100", "200", "300"] {
        press(&mut app, "tab", t0);
        type_text(&mut app, value, t0);
    }
    assert!(press(&mut app, "enter", t0).is_empty());
    assert_eq!(
        app.positions().get("bench").and_then(|e| e.cartesian),
        Some([3000, 3000, 800]),
        "unchanged before yes"
    );
    let effects = press(&mut app, "y", t0 + QUESTION_QUIET);
    assert!(matches!(effects.as_slice(), [Effect::SavePositions(_)]));
    assert_eq!(
        app.positions().get("bench").and_then(|e| e.cartesian),
        Some([1000, 2000, 3000])
    );
}

// ---- Rename ----

#[test]
fn rename_and_undo_are_bound_in_both_keymaps() {
    for name in ["default", "numpad"] {
        let keymap = Keymap::builtin(name).expect("keymap");
        let key = |k: &str| keymap.action(&k.parse::<KeyName>().expect("key"));
        assert_eq!(key("R"), Some(Action::RenamePosition), "{name}");
        assert_eq!(key("u"), Some(Action::UndoDelete), "{name}");
    }
}

#[test]
fn renaming_in_the_book_keeps_the_whole_entry_under_the_new_name() {
    let (mut app, t0) = with_book(false);
    let before = app.positions().get("pick").cloned();
    press(&mut app, "R", t0);
    let Overlay::Form(form) = app.overlay() else {
        panic!("no form")
    };
    assert_eq!(form.fields[0].value, "pick", "prefilled with the selection");
    type_text(&mut app, "up", t0);
    let effects = press(&mut app, "enter", t0);
    assert!(
        matches!(effects.as_slice(), [Effect::SavePositions(book)] if book.get("pickup").is_some())
    );
    assert_eq!(names(&app), ["bench", "pickup"]);
    assert_eq!(app.positions().get("pickup").cloned(), before);
    assert_eq!(app.selected_name(), Some("pickup"));
    assert_eq!(message(&app), "renamed 'pick' to 'pickup'");
}

#[test]
fn renaming_to_the_same_name_is_refused_in_the_form() {
    let (mut app, t0) = with_book(false);
    press(&mut app, "R", t0);
    assert!(press(&mut app, "enter", t0).is_empty());
    let Overlay::Form(form) = app.overlay() else {
        panic!("the form closed")
    };
    assert!(
        form.error
            .as_deref()
            .unwrap_or("")
            .contains("its name already")
    );
}

#[test]
fn renaming_onto_an_existing_name_asks_first() {
    let (mut app, t0) = with_book(false);
    press(&mut app, "R", t0);
    clear_field(&mut app, t0);
    type_text(&mut app, "bench", t0);
    assert!(press(&mut app, "enter", t0).is_empty());
    assert!(matches!(
        app.overlay(),
        Overlay::Confirm(Confirm::Overwrite { .. })
    ));
    press(&mut app, "y", t0 + QUESTION_QUIET);
    assert_eq!(names(&app), ["bench"]);
    assert_eq!(
        app.positions().get("bench").and_then(|e| e.cartesian),
        Some([5000, -1205, 2500]),
        "pick's coordinates under the name bench"
    );
}

/// Opens the rename form on "pick" and submits "place".
fn rename_pick_to_place(app: &mut App, t0: Instant) -> Vec<Effect> {
    press(app, "R", t0);
    clear_field(app, t0);
    type_text(app, "place", t0);
    press(app, "enter", t0)
}

#[test]
fn renaming_on_the_operator_saves_the_new_name_where_the_old_is_then_deletes_the_old() {
    let (mut app, t0) = with_book(true);
    let ask = ArmCommand::GetPosition {
        name: "pick".into(),
    };
    assert_eq!(rename_pick_to_place(&mut app, t0), [Effect::Arm(ask)]);
    // The operator has it elsewhere than the book remembered: its answer wins.
    let now = [5100, -1200, 2600];
    let coordinates = PositionCoordinates {
        cartesian: Some(now),
        polar: None,
    };
    let name = "pick".into();
    let effects = arm(&mut app, ArmEvent::Position { name, coordinates }, t0);
    assert_eq!(effects, [set_cartesian("place", now)]);
    let saved = ArmCommand::SetCartesianPosition {
        name: "place".into(),
        x: now[0],
        y: now[1],
        z: now[2],
    };
    let delete = ArmCommand::DeletePosition {
        name: "pick".into(),
    };
    assert_eq!(done(&mut app, saved, t0), [Effect::Arm(delete.clone())]);
    let effects = done(&mut app, delete, t0);
    assert!(
        matches!(effects.as_slice(), [Effect::SavePositions(book)] if book.get("pick").is_none())
    );
    assert_eq!(names(&app), ["bench", "place"]);
    let place = app.positions().get("place").cloned().unwrap_or_default();
    assert_eq!(place.cartesian, Some(now));
    assert_eq!(
        place.orientation,
        Some([90.0, 0.0, 90.0]),
        "the rest of the entry kept"
    );
    assert_eq!(app.selected_name(), Some("place"));
    assert_eq!(message(&app), "renamed 'pick' to 'place'");
    // The rename's delete is no delete to undo.
    press(&mut app, "u", t0);
    assert_eq!(message(&app), "nothing deleted to restore");
}

#[test]
fn a_rename_whose_save_fails_stops_and_deletes_nothing() {
    let (mut app, t0) = with_book(true);
    rename_pick_to_place(&mut app, t0);
    let coordinates = PositionCoordinates {
        cartesian: Some([1, 2, 3]),
        polar: None,
    };
    let name = "pick".into();
    arm(&mut app, ArmEvent::Position { name, coordinates }, t0);
    let effects = failed(&mut app, CommandKind::SetCartesianPosition, t0);
    assert!(effects.is_empty(), "no delete: {effects:?}");
    assert_eq!(names(&app), ["bench", "pick"]);
    let said = message(&app);
    assert!(
        said.contains("saving 'place' failed") && said.contains("BUSY"),
        "{said}"
    );
    assert!(said.contains("'pick' is unchanged"), "{said}");
}

#[test]
fn a_rename_whose_delete_fails_says_both_names_exist() {
    let (mut app, t0) = with_book(true);
    rename_pick_to_place(&mut app, t0);
    // An operator that answers "ACK" without coordinates: the book's are used.
    let coordinates = PositionCoordinates {
        cartesian: None,
        polar: None,
    };
    let name = "pick".into();
    let effects = arm(&mut app, ArmEvent::Position { name, coordinates }, t0);
    assert_eq!(effects, [set_cartesian("place", [5000, -1205, 2500])]);
    let saved = ArmCommand::SetCartesianPosition {
        name: "place".into(),
        x: 5000,
        y: -1205,
        z: 2500,
    };
    done(&mut app, saved, t0);
    let effects = failed(&mut app, CommandKind::DeletePosition, t0);
    assert!(matches!(effects.as_slice(), [Effect::SavePositions(_)]));
    assert_eq!(names(&app), ["bench", "pick", "place"]);
    let said = message(&app);
    assert!(
        said.contains("deleting 'pick' failed") && said.contains("both names exist"),
        "{said}"
    );
}

#[test]
fn a_rename_of_a_name_the_operator_does_not_know_stops() {
    let (mut app, t0) = with_book(true);
    rename_pick_to_place(&mut app, t0);
    let name = "pick".into();
    let effects = arm(&mut app, ArmEvent::UnknownPosition { name }, t0);
    assert!(effects.is_empty());
    assert_eq!(
        message(&app),
        "not renamed: the operator does not know 'pick'"
    );
    assert_eq!(names(&app), ["bench", "pick"]);
}

// ---- Undo delete ----

#[test]
fn undo_restores_the_last_delete_in_the_book() {
    let (mut app, t0) = with_book(false);
    let before = app.positions().get("pick").cloned();
    press(&mut app, "u", t0);
    assert_eq!(message(&app), "nothing deleted to restore");
    press(&mut app, "delete", t0);
    press(&mut app, "y", t0 + QUESTION_QUIET);
    assert_eq!(names(&app), ["bench"]);
    let effects = press(&mut app, "u", t0);
    assert!(
        matches!(effects.as_slice(), [Effect::SavePositions(book)] if book.get("pick").is_some())
    );
    assert_eq!(
        app.positions().get("pick").cloned(),
        before,
        "name, coordinates, all"
    );
    assert_eq!(app.selected_name(), Some("pick"));
    assert_eq!(message(&app), "restored 'pick' at 500.0 -120.5 250.0 mm");
    press(&mut app, "u", t0);
    assert_eq!(message(&app), "nothing deleted to restore", "one level");
}

#[test]
fn undo_on_the_operator_resaves_the_deleted_position_by_its_coordinates() {
    let (mut app, t0) = with_book(true);
    press(&mut app, "delete", t0);
    let delete = ArmCommand::DeletePosition {
        name: "pick".into(),
    };
    assert_eq!(
        press(&mut app, "y", t0 + QUESTION_QUIET),
        [Effect::Arm(delete.clone())]
    );
    done(&mut app, delete, t0);
    assert_eq!(names(&app), ["bench"]);
    let coordinates = [5000, -1205, 2500];
    assert_eq!(
        press(&mut app, "u", t0),
        [set_cartesian("pick", coordinates)]
    );
    assert_eq!(
        names(&app),
        ["bench"],
        "not in the book before the operator has it"
    );
    // Refused the first time: undo can try again.
    failed(&mut app, CommandKind::SetCartesianPosition, t0);
    assert!(message(&app).contains("restoring 'pick' failed"));
    assert_eq!(
        press(&mut app, "u", t0),
        [set_cartesian("pick", coordinates)]
    );
    let restore = ArmCommand::SetCartesianPosition {
        name: "pick".into(),
        x: 5000,
        y: -1205,
        z: 2500,
    };
    let effects = done(&mut app, restore, t0);
    assert!(matches!(effects.as_slice(), [Effect::SavePositions(_)]));
    let pick = app.positions().get("pick").cloned().unwrap_or_default();
    assert_eq!(pick.cartesian, Some(coordinates));
    assert_eq!(pick.orientation, Some([90.0, 0.0, 90.0]));
    assert_eq!(message(&app), "restored 'pick' at 500.0 -120.5 250.0 mm");
}

#[test]
fn undo_does_not_restore_over_a_name_saved_again_meanwhile() {
    let (mut app, t0) = with_book(false);
    press(&mut app, "delete", t0);
    press(&mut app, "y", t0 + QUESTION_QUIET);
    press(&mut app, "C", t0);
    clear_field(&mut app, t0);
    type_text(&mut app, "pick", t0);
    for value in ["1", "2", "3"] {
        press(&mut app, "tab", t0);
        type_text(&mut app, value, t0);
    }
    press(&mut app, "enter", t0);
    assert!(press(&mut app, "u", t0).is_empty());
    assert!(message(&app).contains("exists again"), "{}", message(&app));
    assert_eq!(
        app.positions().get("pick").and_then(|e| e.cartesian),
        Some([10, 20, 30])
    );
}
