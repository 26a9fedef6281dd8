//! Keymaps: the shipped ones, key names from crossterm events, and bad keymap files refused
//! with file, line and column.
//!
//! Every expected line and column below was counted by hand on the JSON text next to it
//! (lines and columns from 1; columns count characters). The column points at the start of the
//! offending string for a bad key, action or field name, at the `}` that closes the object for
//! a missing binding or field, and at the character where serde_json gave up for bad JSON.

use armjog::console::action::Action;
use armjog::console::keymap::{KeyName, Keymap, KeymapError, KeymapErrorKind};
use crossterm::event::{KeyCode, KeyEvent, KeyEventKind, KeyEventState, KeyModifiers};
use std::collections::BTreeSet;

fn key(name: &str) -> KeyName {
    match name.parse() {
        Ok(key) => key,
        Err(error) => panic!("{error}"),
    }
}

fn load(name: &str) -> Keymap {
    match Keymap::load(name) {
        Ok(keymap) => keymap,
        Err(error) => panic!("{error}"),
    }
}

fn refused(text: &str) -> KeymapError {
    match Keymap::from_json("keymaps/bad.json", text) {
        Ok(keymap) => panic!("accepted: {keymap:?}"),
        Err(error) => error,
    }
}

/// Checks kind, line, column, the message's start, and that the display names the file.
fn assert_refused(
    text: &str,
    kind: KeymapErrorKind,
    line: usize,
    column: usize,
    message_start: &str,
) {
    let error = refused(text);
    let shown = error.to_string();
    assert_eq!(error.kind(), kind, "{shown}");
    assert_eq!(error.source_name(), "keymaps/bad.json");
    assert_eq!(
        (error.line(), error.column()),
        (Some(line), Some(column)),
        "{shown}"
    );
    let prefix = format!("keymaps/bad.json:{line}:{column}: {message_start}");
    assert!(
        shown.starts_with(&prefix),
        "{shown:?} does not start with {prefix:?}"
    );
    assert!(error.message().starts_with(message_start), "{shown}");
}

// ---- The shipped keymaps ----

#[test]
fn every_shipped_keymap_is_built_in_loads_and_binds_every_action() {
    let directory = concat!(env!("CARGO_MANIFEST_DIR"), "/keymaps");
    let mut shipped = BTreeSet::new();
    let entries = match std::fs::read_dir(directory) {
        Ok(entries) => entries,
        Err(error) => panic!("{directory}: {error}"),
    };
    for entry in entries.flatten() {
        let path = entry.path();
        let Some(stem) = path.file_stem().and_then(|stem| stem.to_str()) else {
            continue;
        };
        shipped.insert(stem.to_owned());
        let text = std::fs::read_to_string(&path).unwrap_or_default();
        assert_eq!(
            Keymap::builtin_json(stem),
            Some(text.as_str()),
            "{} is not built in (add it to BUILTIN_KEYMAPS)",
            path.display()
        );
        // The file itself loads by path too.
        let by_path = match Keymap::load(&path.to_string_lossy()) {
            Ok(keymap) => keymap,
            Err(error) => panic!("{error}"),
        };
        assert_eq!(Some(by_path), Keymap::builtin(stem));
    }
    let builtin: BTreeSet<String> = Keymap::builtin_names().map(str::to_owned).collect();
    assert_eq!(shipped, builtin);
    assert!(builtin.contains("default") && builtin.contains("numpad"));

    for name in Keymap::builtin_names() {
        let keymap = load(name);
        assert_eq!(keymap.name(), name);
        assert!(
            !keymap.description().is_empty(),
            "{name} has no description"
        );
        for action in Action::ALL {
            assert!(
                !keymap.keys_for(action).is_empty(),
                "{name} binds no key to {}",
                action.name()
            );
        }
        let listed: Vec<Action> = keymap.entries().into_iter().map(|(a, _)| a).collect();
        assert_eq!(listed, Action::ALL.to_vec(), "{name}: help order");
    }
}

#[test]
fn shipped_jog_keys_have_no_modifiers_and_dialog_keys_stay_free() {
    for name in Keymap::builtin_names() {
        let keymap = load(name);
        for (key, action) in keymap.bindings() {
            if action.jog().is_some() {
                assert_eq!(key.without_modifiers(), *key, "{name}: jog on {key}");
            }
        }
        for dialog_key in ["enter", "esc", "kpenter"] {
            assert_eq!(
                keymap.action(&self::key(dialog_key)),
                None,
                "{name}: {dialog_key}"
            );
        }
    }
}

#[test]
fn default_keymap_has_the_required_bindings() {
    let keymap = load("default");
    for (name, action) in [
        ("w", Action::JogXPlus),
        ("s", Action::JogXMinus),
        ("a", Action::JogYPlus),
        ("d", Action::JogYMinus),
        ("r", Action::JogZPlus),
        ("f", Action::JogZMinus),
        ("right", Action::PanAzimuthPlus),
        ("left", Action::PanAzimuthMinus),
        ("up", Action::PanAltitudePlus),
        ("down", Action::PanAltitudeMinus),
        ("space", Action::Stop),
        ("?", Action::Help),
        ("q", Action::Quit),
    ] {
        assert_eq!(keymap.action(&key(name)), Some(action), "{name}");
    }
    // Case matters: the capitals are other keys.
    assert_eq!(keymap.action(&key("W")), None);
    assert_eq!(keymap.action(&key("Q")), None);
}

#[test]
fn numpad_keymap_jogs_from_the_keypad_in_every_terminal() {
    let keymap = load("numpad");
    for (keypad, action) in [
        ("8", Action::JogXPlus),
        ("2", Action::JogXMinus),
        ("4", Action::JogYPlus),
        ("6", Action::JogYMinus),
        ("9", Action::JogZPlus),
        ("3", Action::JogZMinus),
        ("5", Action::Stop),
        ("0", Action::Stop),
    ] {
        // kitty protocol: the keypad key by its own name.
        assert_eq!(keymap.action(&key(&format!("kp{keypad}"))), Some(action));
        // Other terminals report the plain digit: the keypad twin's binding applies.
        assert_eq!(keymap.action(&key(keypad)), Some(action));
    }
    for (name, action) in [
        ("right", Action::PanAzimuthPlus),
        ("left", Action::PanAzimuthMinus),
        ("up", Action::PanAltitudePlus),
        ("down", Action::PanAltitudeMinus),
        // NumLock off with the kitty protocol: the keypad still jogs.
        ("kpup", Action::JogXPlus),
        ("kpbegin", Action::Stop),
        ("space", Action::Stop),
        ("?", Action::Help),
        ("q", Action::Quit),
    ] {
        assert_eq!(keymap.action(&key(name)), Some(action), "{name}");
    }
}

#[test]
fn load_reads_a_file_by_path_and_names_it_in_errors() {
    let directory = std::env::temp_dir().join(format!("armjog-keymap-{}", std::process::id()));
    if let Err(error) = std::fs::create_dir_all(&directory) {
        panic!("{}: {error}", directory.display());
    }
    let good = directory.join("mine.json");
    let bad = directory.join("bad.json");
    let written = std::fs::write(
        &good,
        r#"{"name": "mine", "bindings": {"space": "stop", "ctrl+q": "quit"}}"#,
    )
    .and_then(|()| {
        std::fs::write(
            &bad,
            "{\n  \"name\": \"bad\",\n  \"bindings\": {\"space\": \"halt\"}\n}\n",
        )
    });
    if let Err(error) = written {
        panic!("{}: {error}", directory.display());
    }
    let good_path = good.to_string_lossy().into_owned();
    let bad_path = bad.to_string_lossy().into_owned();

    let mine = load(&good_path);
    assert_eq!(mine.name(), "mine");
    assert_eq!(mine.action(&key("ctrl+q")), Some(Action::Quit));
    assert_eq!(mine.action(&key("q")), None);

    let error = match Keymap::load(&bad_path) {
        Ok(_) => panic!("loaded {bad_path}"),
        Err(error) => error,
    };
    // Line 3 is `  "bindings": {"space": "halt"}`; "halt" opens at column 25.
    assert_eq!(error.kind(), KeymapErrorKind::UnknownAction);
    assert!(
        error
            .to_string()
            .starts_with(&format!("{bad_path}:3:25: unknown action \"halt\"")),
        "{error}"
    );

    let missing = directory
        .join("missing.json")
        .to_string_lossy()
        .into_owned();
    let error = match Keymap::load(&missing) {
        Ok(_) => panic!("loaded {missing}"),
        Err(error) => error,
    };
    assert_eq!(error.kind(), KeymapErrorKind::Unreadable);
    assert_eq!(error.line(), None);
    assert!(
        error
            .to_string()
            .starts_with(&format!("{missing}: cannot read")),
        "{error}"
    );

    let _ = std::fs::remove_dir_all(&directory);
}

// ---- Bad keymaps ----

#[test]
fn unknown_action_is_refused_at_the_action() {
    let text = r#"{
  "name": "bad",
  "bindings": {
    "space": "stop",
    "q": "quit",
    "w": "jog_w_plus"
  }
}"#;
    // Line 6 `    "w": "jog_w_plus"`: 4 spaces, "w" at 5-7, ':' 8, ' ' 9, the value at 10.
    assert_refused(
        text,
        KeymapErrorKind::UnknownAction,
        6,
        10,
        "unknown action \"jog_w_plus\" (expected one of: jog_x_plus, jog_x_minus, ",
    );
    assert!(
        refused(text)
            .message()
            .ends_with("help, quit, make_tour, play_tour, tour_leg)")
    );
}

#[test]
fn action_of_the_wrong_type_is_refused_at_the_value() {
    let text = "{\n  \"name\": \"bad\",\n  \"bindings\": { \"space\": 5, \"q\": \"quit\" }\n}";
    // Line 3 `  "bindings": { "space": 5, ...`: "bindings" 3-12, ':' 13, ' ' 14, '{' 15,
    // ' ' 16, "space" 17-23, ':' 24, ' ' 25, '5' at 26.
    assert_refused(
        text,
        KeymapErrorKind::InvalidValue,
        3,
        26,
        "invalid type: integer `5`",
    );
}

#[test]
fn unknown_key_is_refused_at_the_key() {
    let text = r#"{
  "name": "bad",
  "bindings": {
    "space": "stop",
    "q": "quit",
    "spacebar": "help"
  }
}"#;
    assert_refused(
        text,
        KeymapErrorKind::UnknownKey,
        6,
        5,
        "unknown key \"spacebar\" (expected a character",
    );

    let text = "{\"name\": \"bad\", \"bindings\": {\"q\": \"quit\", \"Space\": \"stop\"}}";
    // One line: {"name": "bad", → cols 1-15, ' ' 16, "bindings" 17-26, ':' 27, ' ' 28,
    // '{' 29, "q" 30-32, ':' 33, ' ' 34, "quit" 35-40, ',' 41, ' ' 42, "Space" at 43.
    assert_refused(
        text,
        KeymapErrorKind::UnknownKey,
        1,
        43,
        "unknown key \"Space\" (key names are lowercase: did you mean \"space\"?)",
    );
}

#[test]
fn duplicate_key_is_refused_at_the_second_one() {
    let text = r#"{
  "name": "bad",
  "bindings": {
    "space": "stop",
    "w": "jog_x_plus",
    "q": "quit",
    "w" : "jog_x_minus"
  }
}"#;
    assert_refused(
        text,
        KeymapErrorKind::DuplicateKey,
        7,
        5,
        "duplicate binding: key \"w\" is already bound above (to \"jog_x_plus\")",
    );

    // The same key spelled two ways, the second on the last line of the object.
    let text = r#"{
  "name": "bad",
  "bindings": {
    "space": "stop", "q": "quit", "ctrl+alt+x": "quick_stop",
      "alt+ctrl+x": "quick_stop" }
}"#;
    assert_refused(
        text,
        KeymapErrorKind::DuplicateKey,
        5,
        7,
        "duplicate binding: key \"ctrl+alt+x\" is already bound above (to \"quick_stop\")",
    );
}

#[test]
fn unknown_top_level_field_is_refused_at_the_field() {
    let text = r#"{
  "name": "bad",
  "colour": "red",
  "bindings": { "space": "stop", "q": "quit" }
}"#;
    assert_refused(
        text,
        KeymapErrorKind::UnknownField,
        3,
        3,
        "unknown field \"colour\" (expected one of: name, description, bindings)",
    );

    // Columns count characters: 'à' is two bytes but one column.
    let text = "{\n  \"name\": \"bad\",\n  \"description\": \"bras à gauche\", \"colour\": 1,\n  \"bindings\": {}\n}";
    // Line 3: "description" 3-15, ':' 16, ' ' 17, "bras à gauche" 18-32, ',' 33, ' ' 34,
    // "colour" at 35.
    assert_refused(
        text,
        KeymapErrorKind::UnknownField,
        3,
        35,
        "unknown field \"colour\"",
    );
}

#[test]
fn duplicate_and_missing_top_level_fields_are_refused() {
    let text = "{\n  \"name\": \"a\",\n  \"name\": \"b\",\n  \"bindings\": {}\n}";
    assert_refused(
        text,
        KeymapErrorKind::DuplicateField,
        3,
        3,
        "field \"name\" appears twice",
    );

    let text = "{\n  \"bindings\": { \"space\": \"stop\", \"q\": \"quit\" }\n}";
    // The top-level object closes at line 3, column 1.
    assert_refused(
        text,
        KeymapErrorKind::MissingField,
        3,
        1,
        "the keymap has no \"name\" field",
    );

    let text = "{ \"name\": \"bad\" }";
    assert_refused(
        text,
        KeymapErrorKind::MissingField,
        1,
        17,
        "the keymap has no \"bindings\" field",
    );
}

#[test]
fn keymap_without_stop_or_quit_is_refused_at_the_end_of_the_bindings() {
    let text = r#"{
  "name": "bad",
  "bindings": {
    "q": "quit",
    "w": "jog_x_plus"
  }
}"#;
    assert_refused(
        text,
        KeymapErrorKind::MissingRequiredAction,
        6,
        3,
        "no key is bound to \"stop\"",
    );

    let text = r#"{ "name": "bad", "bindings": { "space": "stop" } }"#;
    // '{' 1, ' ' 2, "name" 3-8, ':' 9, ' ' 10, "bad" 11-15, ',' 16, ' ' 17, "bindings" 18-27,
    // ':' 28, ' ' 29, '{' 30, ' ' 31, "space" 32-38, ':' 39, ' ' 40, "stop" 41-46, ' ' 47,
    // '}' at 48.
    assert_refused(
        text,
        KeymapErrorKind::MissingRequiredAction,
        1,
        48,
        "no key is bound to \"quit\"",
    );
}

#[test]
fn invalid_json_is_refused_where_the_parser_stopped() {
    // A trailing comma: serde_json stops at the '}' after it (line 6, column 3).
    let text = r#"{
  "name": "bad",
  "bindings": {
    "space": "stop",
    "q": "quit",
  }
}"#;
    assert_refused(text, KeymapErrorKind::InvalidJson, 6, 3, "trailing comma");

    // A missing colon: line 4 `    "space" "stop",`, the unexpected '"' at column 13.
    let text = "{\n  \"name\": \"bad\",\n  \"bindings\": {\n    \"space\" \"stop\",\n    \"q\": \"quit\"\n  }\n}";
    assert_refused(text, KeymapErrorKind::InvalidJson, 4, 13, "expected `:`");

    // An empty file.
    assert_refused(
        "",
        KeymapErrorKind::InvalidJson,
        1,
        1,
        "EOF while parsing a value",
    );

    // Text after the object: the 'x' on line 2, column 1.
    let text = "{\"name\": \"bad\", \"bindings\": {\"space\": \"stop\", \"q\": \"quit\"}}\nx";
    assert_refused(
        text,
        KeymapErrorKind::InvalidJson,
        2,
        1,
        "trailing characters",
    );

    // Not an object at all.
    assert_refused(
        "[]",
        KeymapErrorKind::InvalidValue,
        1,
        1,
        "invalid type: sequence",
    );
}

// ---- Key names ----

fn name_of(event: KeyEvent) -> Option<String> {
    KeyName::from_event(&event).map(|key| key.to_string())
}

fn press(code: KeyCode, modifiers: KeyModifiers) -> KeyEvent {
    KeyEvent::new(code, modifiers)
}

#[test]
fn key_names_from_crossterm_events() {
    let none = KeyModifiers::NONE;
    for (event, name) in [
        (press(KeyCode::Char('w'), none), "w"),
        (press(KeyCode::Char('a'), KeyModifiers::SHIFT), "A"),
        (press(KeyCode::Char('A'), KeyModifiers::SHIFT), "A"),
        (press(KeyCode::Char('A'), none), "A"),
        (press(KeyCode::Char(' '), none), "space"),
        (press(KeyCode::Char('?'), none), "?"),
        (press(KeyCode::Char('?'), KeyModifiers::SHIFT), "?"),
        (press(KeyCode::Up, none), "up"),
        (press(KeyCode::Down, none), "down"),
        (press(KeyCode::Left, none), "left"),
        (press(KeyCode::Right, none), "right"),
        (press(KeyCode::F(5), none), "f5"),
        (press(KeyCode::Char('x'), KeyModifiers::CONTROL), "ctrl+x"),
        (press(KeyCode::Char('x'), KeyModifiers::ALT), "alt+x"),
        (press(KeyCode::Delete, none), "delete"),
        (press(KeyCode::BackTab, KeyModifiers::SHIFT), "shift+tab"),
        (press(KeyCode::Char('8'), none), "8"),
        (
            KeyEvent::new_with_kind_and_state(
                KeyCode::Char('8'),
                none,
                KeyEventKind::Press,
                KeyEventState::KEYPAD,
            ),
            "kp8",
        ),
        (
            KeyEvent::new_with_kind_and_state(
                KeyCode::Char('5'),
                none,
                KeyEventKind::Release,
                KeyEventState::KEYPAD | KeyEventState::NUM_LOCK,
            ),
            "kp5",
        ),
    ] {
        assert_eq!(name_of(event).as_deref(), Some(name), "{event:?}");
    }
    // Press, repeat and release of a key have one name.
    let release = KeyEvent::new_with_kind(KeyCode::Char('w'), none, KeyEventKind::Release);
    assert_eq!(KeyName::from_event(&release), Some(key("w")));
    // A bare modifier key has no name.
    let shift = press(
        KeyCode::Modifier(crossterm::event::ModifierKeyCode::LeftShift),
        KeyModifiers::SHIFT,
    );
    assert_eq!(KeyName::from_event(&shift), None);
}

#[test]
fn key_names_round_trip_through_display_and_from_str() {
    for name in [
        "w",
        "A",
        "?",
        "+",
        "-",
        "=",
        "[",
        "]",
        ",",
        ".",
        "space",
        "enter",
        "esc",
        "tab",
        "shift+tab",
        "backspace",
        "delete",
        "insert",
        "home",
        "end",
        "pageup",
        "pagedown",
        "up",
        "down",
        "left",
        "right",
        "f1",
        "f5",
        "f12",
        "kp0",
        "kp8",
        "kp+",
        "kp.",
        "kpenter",
        "kpup",
        "kpbegin",
        "ctrl+x",
        "alt+x",
        "ctrl+alt+x",
        "ctrl++",
        "ctrl+A",
        "alt+shift+f5",
    ] {
        let parsed = key(name);
        assert_eq!(parsed.to_string(), name);
        assert_eq!(key(&parsed.to_string()), parsed);
    }
    // Modifiers in another order come back in the canonical order.
    assert_eq!(key("alt+ctrl+x").to_string(), "ctrl+alt+x");
}

#[test]
fn bad_key_names_are_named_in_the_error() {
    for name in ["spacebar", "Enter", "f0", "shift+a", "kpx", "", "ctrl+"] {
        let error = match name.parse::<KeyName>() {
            Ok(parsed) => panic!("{name:?} parsed as {parsed}"),
            Err(error) => error,
        };
        assert!(
            error
                .to_string()
                .starts_with(&format!("unknown key {name:?} (")),
            "{error}"
        );
    }
}
