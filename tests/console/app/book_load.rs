//! The position book loading off the event loop, seen from the state machine (fake clock): keys
//! work while it loads, the loaded book fills the panel, and nothing saved meanwhile overwrites
//! the file or is lost.

use crate::app_support;

use app_support::*;
use armjog::console::app::{BookState, CHECKED_ON_CONNECT, Effect, Input};
use armjog::console::jog::ReleaseMode;
use armjog::console::positions::{BookError, PositionBook};
use armjog::link::interface::{ArmCommand, ArmEvent, LinkStatus};

/// A book path in a fresh directory, removed when the `TempDir` is dropped.
fn temp_book() -> (tempfile::TempDir, std::path::PathBuf) {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("book.json");
    (dir, path)
}

fn book_of(names: &[&str]) -> PositionBook {
    let mut book = PositionBook::new();
    for (i, name) in names.iter().enumerate() {
        book.get_or_insert(name).cartesian = Some([i as i32 * 100, 0, 1000]);
    }
    book
}

/// What the runtime does with the effects: writes the book on a save.
fn write_saves(effects: &[Effect], path: &std::path::Path) -> usize {
    let mut saves = 0;
    for effect in effects {
        if let Effect::SavePositions(book) = effect {
            book.save(path).expect("save");
            saves += 1;
        }
    }
    saves
}

#[test]
fn a_loaded_book_fills_the_panel_and_the_selection_starts_on_its_first_name() {
    let (mut app, t0) = app(ReleaseMode::Reported, false);
    app.begin_loading_positions("book.json");
    assert_eq!(
        *app.book_state(),
        BookState::Loading {
            file: "book.json".into()
        }
    );
    assert!(app.positions().is_empty());
    let effects = app.handle(
        Input::PositionsLoaded(Ok(book_of(&["bench", "home", "pick"]))),
        t0 + ms(1500),
    );
    assert_eq!(
        effects,
        vec![],
        "nothing changed meanwhile: nothing to save"
    );
    assert_eq!(*app.book_state(), BookState::Ready);
    assert_eq!(app.positions().len(), 3);
    assert_eq!(app.selected_name(), Some("bench"));
    press(&mut app, "pagedown", t0 + ms(1600));
    assert_eq!(app.selected_name(), Some("home"));
}

#[test]
fn jog_release_stop_and_quit_work_while_the_book_loads() {
    let (mut app, t0) = app(ReleaseMode::Reported, false);
    app.begin_loading_positions("book.json");
    assert_eq!(press(&mut app, "w", t0), vec![jog(1, 0, 0)]);
    assert_eq!(release(&mut app, "w", t0 + ms(200)), vec![STOP]);
    assert!(press(&mut app, "space", t0 + ms(300)).contains(&STOP));
    let quit = press(&mut app, "q", t0 + ms(400));
    assert!(quit.contains(&STOP), "{quit:?}");
    assert!(quit.contains(&Effect::Quit), "{quit:?}");
    assert!(matches!(app.book_state(), BookState::Loading { .. }));
}

#[test]
fn a_save_while_loading_leaves_the_file_intact_and_lands_in_the_loaded_book() {
    let (_dir, path) = temp_book();
    let on_disk = book_of(&["bench", "home"]);
    on_disk.save(&path).expect("save");
    let before = std::fs::read(&path).expect("read");

    let (mut app, t0) = app(ReleaseMode::Reported, true);
    app.begin_loading_positions(path.display().to_string());
    // The operator confirms a save made while the book loads.
    let save = ArmCommand::SavePosition {
        name: "pick".into(),
        anchor: false,
        parent: None,
    };
    let effects = app.handle(Input::Arm(ArmEvent::Done { command: save }), t0);
    assert_eq!(write_saves(&effects, &path), 0, "{effects:?}");
    assert_eq!(
        std::fs::read(&path).expect("read"),
        before,
        "file untouched"
    );
    let (message, _) = app.message().expect("a message");
    assert!(message.contains("still loading"), "{message}");

    let loaded = PositionBook::load(&path).expect("load");
    let effects = app.handle(Input::PositionsLoaded(Ok(loaded)), t0 + ms(900));
    assert_eq!(write_saves(&effects, &path), 1, "{effects:?}");
    let saved = PositionBook::load(&path).expect("load");
    let names: Vec<&str> = saved.names().collect();
    assert_eq!(names, ["bench", "home", "pick"], "nothing lost");
    assert_eq!(
        app.selected_name(),
        Some("pick"),
        "the selection stays on it"
    );
}

#[test]
fn a_book_that_cannot_be_read_is_named_and_never_saved_over() {
    let (_dir, path) = temp_book();
    std::fs::write(&path, "{ \"format\": 1, \"positions\": { \"a\" }").expect("write");
    let before = std::fs::read(&path).expect("read");
    let corrupt = PositionBook::load(&path).expect_err("corrupt");
    let error = corrupt.to_string();

    let (mut app, t0) = app(ReleaseMode::Reported, false);
    app.begin_loading_positions(path.display().to_string());
    app.handle(Input::PositionsLoaded(Err(corrupt.into())), t0);
    assert_eq!(
        *app.book_state(),
        BookState::Failed {
            error: error.clone()
        }
    );
    let (message, _) = app.message().expect("a message");
    assert!(message.contains(&path.display().to_string()), "{message}");

    // Jogging still works; a change is refused a place in the file.
    assert_eq!(press(&mut app, "w", t0 + ms(10)), vec![jog(1, 0, 0)]);
    assert_eq!(release(&mut app, "w", t0 + ms(20)), vec![STOP]);
    let delete = ArmCommand::DeletePosition { name: "a".into() };
    let effects = app.handle(Input::Arm(ArmEvent::Done { command: delete }), t0 + ms(30));
    assert_eq!(write_saves(&effects, &path), 0, "{effects:?}");
    assert_eq!(
        std::fs::read(&path).expect("read"),
        before,
        "file untouched"
    );
    let (message, _) = app.message().expect("a message");
    assert!(message.contains("not saved"), "{message}");
}

#[test]
fn a_big_book_checks_a_bounded_number_of_names_with_the_operator() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    app.begin_loading_positions("book.json");
    let names: Vec<String> = (0..5000).map(|i| format!("pos-{i:05}")).collect();
    let refs: Vec<&str> = names.iter().map(String::as_str).collect();
    // The link is already up when the book arrives: the check happens then.
    let effects = app.handle(Input::PositionsLoaded(Ok(book_of(&refs))), t0);
    let asked = |effects: &[Effect]| {
        effects
            .iter()
            .filter(|e| matches!(e, Effect::Arm(ArmCommand::GetPosition { .. })))
            .count()
    };
    assert_eq!(asked(&effects), CHECKED_ON_CONNECT);
    // And again after a reconnect, no more than that.
    app.handle(
        Input::Arm(ArmEvent::Status(LinkStatus::Down {
            reason: "test".into(),
        })),
        t0 + ms(10),
    );
    let effects = app.handle(
        Input::Arm(ArmEvent::Status(LinkStatus::Up {
            description: "test".into(),
        })),
        t0 + ms(20),
    );
    assert_eq!(asked(&effects), CHECKED_ON_CONNECT);
}

/// `App::handle`'s follow-ups hold a save back before they count the saves that go out: a change
/// to a book that could not be read is marked not saved at once, not awaited from a write that
/// never comes.
#[test]
fn a_change_to_an_unreadable_book_is_marked_not_saved_at_once() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    app.begin_loading_positions("book.json");
    let bad = BookError::Parse {
        path: "book.json".into(),
        line: 1,
        column: 1,
        message: "bad json".into(),
    };
    app.handle(Input::PositionsLoaded(Err(bad.into())), t0);
    let save = ArmCommand::SavePosition {
        name: "pick".into(),
        anchor: false,
        parent: None,
    };
    let effects = app.handle(Input::Arm(ArmEvent::Done { command: save }), t0 + ms(10));
    assert!(
        !effects
            .iter()
            .any(|e| matches!(e, Effect::SavePositions(_))),
        "{effects:?}"
    );
    assert_eq!(app.unsaved_positions(), 1, "pick is marked not saved");
}
