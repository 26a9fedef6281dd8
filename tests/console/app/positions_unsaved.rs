//! A save is saved or marked: the book's writer on a folder it cannot write (the book's folder
//! is a file, as good as a full disk or a read-only folder, and one root cannot write through
//! either): the position shows NOT SAVED in the panel, the next save (once the folder can be
//! written) retries and clears the mark, and quitting with a position not saved asks first.

use std::time::{Duration, Instant};

use armjog::console::app::{App, Effect, Input, Overlay};
use armjog::console::book_io::{self, BookFiles};
use armjog::console::form::Confirm;
use armjog::console::jog::ReleaseMode;
use armjog::console::positions::PositionBook;

use crate::app_support::{app, press, row, screen};

fn type_text(app: &mut App, text: &str, now: Instant) {
    for c in text.chars() {
        press(app, &c.to_string(), now);
    }
}

/// Defines `name` at x, y, z through the cartesian form; returns the effects of its Enter.
fn define(app: &mut App, name: &str, now: Instant) -> Vec<Effect> {
    press(app, "C", now);
    // The form is prefilled with the selected name.
    while app_form_name(app).is_some_and(|n| !n.is_empty()) {
        press(app, "backspace", now);
    }
    type_text(app, name, now);
    for value in ["100", "200", "300"] {
        press(app, "tab", now);
        type_text(app, value, now);
    }
    press(app, "enter", now)
}

fn app_form_name(app: &App) -> Option<String> {
    match app.overlay() {
        Overlay::Form(form) => form.fields.first().map(|f| f.value.clone()),
        _ => None,
    }
}

/// Carries out the app's saves as the runtime does.
fn save_all(files: &BookFiles, effects: &[Effect]) {
    for effect in effects {
        if let Effect::SavePositions(book) = effect {
            files.save(book.clone());
        }
    }
}

async fn outcome(files: &mut BookFiles) -> Input {
    let outcome = tokio::time::timeout(Duration::from_secs(10), files.save_outcomes.recv())
        .await
        .expect("the writer answers in time")
        .expect("an outcome");
    Input::PositionsSaved(outcome)
}

/// The positions panel's row showing `name`, drawn at 80 x 40.
fn panel_row(app: &App, name: &str) -> String {
    let terminal = screen(app, 80, 40);
    (0..40)
        .map(|y| row(&terminal, y))
        .find(|r| r.contains(name) && r.contains("mm"))
        .unwrap_or_else(|| panic!("no row shows {name}"))
}

#[tokio::test]
async fn a_failed_save_is_marked_retried_by_the_next_and_quitting_asks_first() {
    let dir = tempfile::tempdir().expect("temp dir");
    let folder = dir.path().join("positions");
    let path = folder.join("book.json");
    let mut files = BookFiles::open(Some(path.clone())).expect("opened");
    let (mut app, t0) = app(ReleaseMode::Reported, false);
    app.begin_loading_positions(path.display().to_string());
    let loaded = book_io::loaded(&mut files.loading).await;
    app.handle(Input::PositionsLoaded(loaded), t0);

    // The folder cannot be made: the save fails.
    std::fs::write(&folder, "in the way").expect("blocker");
    let effects = define(&mut app, "pick", t0);
    assert!(matches!(effects.as_slice(), [Effect::SavePositions(_)]));
    save_all(&files, &effects);
    app.handle(outcome(&mut files).await, t0);
    assert!(app.positions().get("pick").is_some_and(|e| e.unsaved));
    assert_eq!(app.unsaved_positions(), 1);
    let shown = panel_row(&app, "pick");
    assert!(shown.contains("NOT SAVED"), "{shown}");
    let message = app
        .message()
        .map(|(text, _)| text.to_string())
        .unwrap_or_default();
    assert!(message.contains("positions not saved"), "{message}");
    assert!(message.contains(&path.display().to_string()), "{message}");

    // Another message does not end the warning that something is unsaved: the mark stays.
    press(&mut app, "x", t0 + Duration::from_secs(1));
    assert!(panel_row(&app, "pick").contains("NOT SAVED"));

    // Quitting asks first, and no is no.
    let effects = press(&mut app, "q", t0 + Duration::from_secs(2));
    assert!(
        !effects.iter().any(|e| matches!(e, Effect::Quit)),
        "{effects:?}"
    );
    assert!(matches!(
        app.overlay(),
        Overlay::Confirm(Confirm::QuitUnsaved { count: 1 })
    ));
    let effects = press(&mut app, "enter", t0 + Duration::from_secs(3));
    assert!(
        !effects.iter().any(|e| matches!(e, Effect::Quit)),
        "only y quits"
    );
    assert!(matches!(app.overlay(), Overlay::None));

    // Space freed: the next save writes the whole book, the failed position with it.
    std::fs::remove_file(&folder).expect("blocker removed");
    let effects = define(&mut app, "place", t0 + Duration::from_secs(4));
    save_all(&files, &effects);
    assert!(
        app.positions().get("pick").is_some_and(|e| e.unsaved),
        "not yet"
    );
    app.handle(outcome(&mut files).await, t0 + Duration::from_secs(4));
    assert_eq!(app.unsaved_positions(), 0);
    assert!(!panel_row(&app, "pick").contains("NOT SAVED"));
    let on_disk = PositionBook::load(&path).expect("written");
    assert_eq!(on_disk.names().collect::<Vec<_>>(), ["pick", "place"]);

    // Nothing unsaved: q quits at once.
    let effects = press(&mut app, "q", t0 + Duration::from_secs(5));
    assert!(effects.iter().any(|e| matches!(e, Effect::Quit)));
    files.finish(Duration::from_secs(10)).await;
}

#[tokio::test]
async fn quitting_anyway_writes_the_book_once_more() {
    let dir = tempfile::tempdir().expect("temp dir");
    let folder = dir.path().join("positions");
    let path = folder.join("book.json");
    let mut files = BookFiles::open(Some(path.clone())).expect("opened");
    let (mut app, t0) = app(ReleaseMode::Reported, false);
    app.begin_loading_positions(path.display().to_string());
    let loaded = book_io::loaded(&mut files.loading).await;
    app.handle(Input::PositionsLoaded(loaded), t0);
    std::fs::write(&folder, "in the way").expect("blocker");
    let effects = define(&mut app, "pick", t0);
    save_all(&files, &effects);
    app.handle(outcome(&mut files).await, t0);
    press(&mut app, "q", t0);
    std::fs::remove_file(&folder).expect("blocker removed");
    // Answered after the question's first 150 ms, as a person answers.
    let effects = press(&mut app, "y", t0 + Duration::from_millis(200));
    assert!(
        matches!(
            effects.as_slice(),
            [.., Effect::SavePositions(_), Effect::Quit]
        ),
        "{effects:?}"
    );
    save_all(&files, &effects);
    files.finish(Duration::from_secs(10)).await;
    let on_disk = PositionBook::load(&path).expect("written at quit");
    assert_eq!(on_disk.names().collect::<Vec<_>>(), ["pick"]);
}
