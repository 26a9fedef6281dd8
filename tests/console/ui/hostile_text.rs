//! Text from outside never reaches the terminal raw: a bidi override or a control character in
//! a book name, a keymap's name or one of its keys is refused where it is read, and anything
//! that reaches a panel anyway is escaped (`\u{202e}`) or dropped before the terminal.

use armjog::console::app::Input;
use armjog::console::jog::ReleaseMode;
use armjog::console::keymap::{KeyName, Keymap, KeymapErrorKind};
use armjog::console::positions::PositionBook;

use crate::app_support::{app, buffer_text, screen};

const RLO: char = '\u{202E}';

fn keymap_with(name: &str, key: &str) -> String {
    serde_json::json!({
        "name": name,
        "bindings": { "space": "stop", "q": "quit", key: "home" }
    })
    .to_string()
}

#[test]
fn a_keymap_with_a_bidi_or_control_name_or_key_is_refused_naming_it() {
    let name =
        Keymap::from_json("bad.json", &keymap_with("evil\u{202E}gpj", "h")).expect_err("refused");
    assert_eq!(name.kind(), KeymapErrorKind::InvalidValue);
    assert!(name.to_string().contains("U+202E"), "{name}");
    let escape =
        Keymap::from_json("bad.json", &keymap_with("a\u{1b}[2Jb", "h")).expect_err("refused");
    assert!(escape.to_string().contains("U+001B"), "{escape}");
    let key = Keymap::from_json("bad.json", &keymap_with("fine", "\u{202E}")).expect_err("refused");
    assert_eq!(key.kind(), KeymapErrorKind::UnknownKey);
    assert!("\u{2066}".parse::<KeyName>().is_err());
    assert!(Keymap::from_json("ok.json", &keymap_with("fine", "h")).is_ok());
}

#[test]
fn a_hostile_name_in_the_book_is_escaped_on_the_screen_and_nothing_raw_reaches_it() {
    let (mut app, t0) = app(ReleaseMode::Reported, false);
    // Straight into the app, past the load's repair: the panel's own guard is what is tested.
    let mut book = PositionBook::new();
    book.get_or_insert("evil\u{202E}gpj.exe").cartesian = Some([1000, 0, 0]);
    book.get_or_insert("bell\u{7}\u{1b}[2J").cartesian = Some([2000, 0, 0]);
    app.handle(Input::PositionsLoaded(Ok(book)), t0);
    let terminal = screen(&app, 120, 40);
    let text = buffer_text(terminal.backend().buffer());
    assert!(!text.contains(RLO), "no raw override on screen");
    assert!(
        !text.chars().any(|c| c.is_control()),
        "no raw control on screen"
    );
    assert!(text.contains("evil\\u{202e}gpj.exe"), "{text}");
    assert!(text.contains("bell\\u{7}\\u{1b}[2J"), "{text}");
}

#[test]
fn the_last_guard_drops_unsafe_characters_from_any_cell() {
    let mut buffer = ratatui::buffer::Buffer::empty(ratatui::layout::Rect::new(0, 0, 6, 1));
    buffer[(0, 0)].set_symbol("a\u{202E}");
    buffer[(1, 0)].set_symbol("\u{1b}");
    buffer[(2, 0)].set_symbol("\u{2067}");
    buffer[(3, 0)].set_symbol("e\u{301}");
    armjog::console::ui::neutralise(&mut buffer);
    let symbols: Vec<&str> = (0..4).map(|x| buffer[(x, 0)].symbol()).collect();
    assert_eq!(symbols, ["a", "\u{FFFD}", "\u{FFFD}", "e\u{301}"]);
}

#[test]
fn a_book_file_with_hostile_names_loads_with_a_message_naming_what_was_wrong() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("book.json");
    let json = serde_json::json!({
        "format": 1,
        "positions": {
            "evil\u{202E}gpj": {"cartesian": [1, 0, 0]},
            "": {"cartesian": [2, 0, 0]},
            "pick": {"cartesian": [3, 0, 0]},
        }
    });
    std::fs::write(&path, json.to_string()).expect("written");
    let book = PositionBook::load(&path).expect("loads");
    let (mut app, t0) = app(ReleaseMode::Reported, false);
    app.begin_loading_positions(path.display().to_string());
    app.handle(Input::PositionsLoaded(Ok(book)), t0);
    assert_eq!(app.positions().len(), 3, "nothing lost");
    let (message, _) = app.message().expect("a message");
    // The first repair (in name order), and how many more the log holds.
    assert!(message.contains("position name '' is empty"), "{message}");
    assert!(message.contains("loaded as 'unnamed'"), "{message}");
    assert!(app.positions().get("evil\\u{202e}gpj").is_some());
    assert!(message.contains("and 1 more"), "{message}");
    assert!(!message.contains(RLO));
}
