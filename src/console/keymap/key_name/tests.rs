use super::*;
use crossterm::event::KeyEventKind;

fn key(name: &str) -> KeyName {
    match name.parse() {
        Ok(key) => key,
        Err(error) => panic!("{error}"),
    }
}

fn event(code: KeyCode, modifiers: KeyModifiers) -> KeyEvent {
    KeyEvent::new(code, modifiers)
}

fn name_of(event: KeyEvent) -> Option<String> {
    KeyName::from_event(&event).map(|key| key.to_string())
}

#[test]
fn built_names_equal_the_parsed_ones() {
    assert_eq!(KeyName::char('y'), key("y"));
    assert_eq!(KeyName::char('Y'), key("Y"));
    assert_eq!(KeyName::char(' '), key("space"));
    assert_eq!(KeyName::named(NamedKey::Enter), key("enter"));
    assert_eq!(KeyName::char('c').with_ctrl(), key("ctrl+c"));
    assert_eq!(KeyName::named(NamedKey::Tab).with_shift(), key("shift+tab"));
    // Shift is part of a character: "shift+a" is no name, "A" is.
    assert_eq!(KeyName::char('a').with_shift(), key("a"));
    assert_ne!(KeyName::named(NamedKey::Enter), key("kpenter"));
}

#[test]
fn characters_are_case_sensitive() {
    assert_ne!(key("a"), key("A"));
    assert_eq!(key("A").base(), BaseKey::Char('A'));
    assert_eq!(key("?").base(), BaseKey::Char('?'));
}

#[test]
fn every_kind_of_name_round_trips() {
    let mut names: Vec<String> = NamedKey::ALL.iter().map(|k| k.name().to_owned()).collect();
    names.extend((1..=MAX_FUNCTION_KEY).map(|n| format!("f{n}")));
    names.extend("0123456789.,/*-+=".chars().map(|c| format!("kp{c}")));
    names.extend(
        NamedKey::ALL
            .iter()
            .filter(|k| k.is_on_keypad())
            .map(|k| format!("kp{}", k.name())),
    );
    names.push("kpbegin".to_owned());
    for character in "aZ?+-=[],.;'/\\`~!@#$%^&*()_{}|:\"<>é1f".chars() {
        names.push(character.to_string());
    }
    for name in names.clone() {
        names.push(format!("ctrl+{name}"));
        names.push(format!("alt+{name}"));
        names.push(format!("ctrl+alt+{name}"));
    }
    names.push("shift+tab".to_owned());
    names.push("ctrl+alt+shift+f12".to_owned());
    names.push("shift+kpup".to_owned());
    for name in names {
        assert_eq!(key(&name).to_string(), name);
    }
}

#[test]
fn modifiers_parse_in_any_order() {
    assert_eq!(key("alt+ctrl+x"), key("ctrl+alt+x"));
    assert_eq!(key("shift+alt+up").to_string(), "alt+shift+up");
    assert_eq!(key("ctrl++").base(), BaseKey::Char('+'));
    assert!(key("ctrl++").modifiers.ctrl);
}

#[test]
fn bad_names_are_refused_with_the_name() {
    for (name, reason_part) in [
        ("", "missing"),
        ("ctrl+", "expected a character"),
        ("spacebar", "expected a character"),
        ("Enter", "did you mean \"enter\""),
        ("F5", "did you mean \"f5\""),
        ("f0", "expected a character"),
        ("f36", "f1 to f35"),
        ("kp", "expected a character"),
        ("kpa", "expected a character"),
        ("kpspace", "expected a character"),
        (" ", "\"space\""),
        ("\t", "control"),
        ("shift+a", "did you mean \"A\"?"),
        ("ctrl+shift+a", "did you mean \"ctrl+A\"?"),
        ("shift+?", "rather than \"shift+/\""),
        ("shift+space", "shift+ is not used"),
        ("shift+kp8", "shift+ is not used"),
        ("ctrl+ctrl+x", "twice"),
        ("meta+x", "expected a character"),
    ] {
        let error = match name.parse::<KeyName>() {
            Ok(key) => panic!("{name:?} parsed as {key}"),
            Err(error) => error,
        };
        assert_eq!(error.name, name);
        let shown = error.to_string();
        assert!(
            shown.starts_with(&format!("unknown key {name:?}")),
            "{shown}"
        );
        assert!(shown.contains(reason_part), "{name:?}: {shown}");
    }
}

#[test]
fn shifted_letters_are_capitals_however_reported() {
    // Legacy terminals: the capital with SHIFT (crossterm adds it) or without (caps lock).
    assert_eq!(
        name_of(event(KeyCode::Char('A'), KeyModifiers::SHIFT)).as_deref(),
        Some("A")
    );
    assert_eq!(
        name_of(event(KeyCode::Char('A'), KeyModifiers::NONE)).as_deref(),
        Some("A")
    );
    // Kitty protocol without alternate keys: the unshifted letter with SHIFT.
    assert_eq!(
        name_of(event(KeyCode::Char('a'), KeyModifiers::SHIFT)).as_deref(),
        Some("A")
    );
    assert_eq!(
        name_of(event(
            KeyCode::Char('a'),
            KeyModifiers::SHIFT | KeyModifiers::CONTROL
        ))
        .as_deref(),
        Some("ctrl+A")
    );
    // A shifted symbol is the symbol, with or without SHIFT reported (Windows reports it).
    assert_eq!(
        name_of(event(KeyCode::Char('?'), KeyModifiers::SHIFT)).as_deref(),
        Some("?")
    );
    assert_eq!(
        name_of(event(KeyCode::Char('?'), KeyModifiers::NONE)).as_deref(),
        Some("?")
    );
    assert_eq!(
        name_of(event(KeyCode::Char('é'), KeyModifiers::SHIFT)).as_deref(),
        Some("É")
    );
    // A letter whose capital is two characters stays itself.
    assert_eq!(
        name_of(event(KeyCode::Char('ß'), KeyModifiers::SHIFT)).as_deref(),
        Some("ß")
    );
}

#[test]
fn event_kind_does_not_matter() {
    for kind in [
        KeyEventKind::Press,
        KeyEventKind::Repeat,
        KeyEventKind::Release,
    ] {
        let event = KeyEvent::new_with_kind(KeyCode::Char('w'), KeyModifiers::NONE, kind);
        assert_eq!(KeyName::from_event(&event), Some(key("w")));
    }
}

#[test]
fn named_keys_from_events() {
    for (code, name) in [
        (KeyCode::Char(' '), "space"),
        (KeyCode::Enter, "enter"),
        (KeyCode::Esc, "esc"),
        (KeyCode::Tab, "tab"),
        (KeyCode::BackTab, "shift+tab"),
        (KeyCode::Backspace, "backspace"),
        (KeyCode::Delete, "delete"),
        (KeyCode::Insert, "insert"),
        (KeyCode::Home, "home"),
        (KeyCode::End, "end"),
        (KeyCode::PageUp, "pageup"),
        (KeyCode::PageDown, "pagedown"),
        (KeyCode::Up, "up"),
        (KeyCode::Down, "down"),
        (KeyCode::Left, "left"),
        (KeyCode::Right, "right"),
        (KeyCode::F(1), "f1"),
        (KeyCode::F(12), "f12"),
        (KeyCode::KeypadBegin, "kpbegin"),
    ] {
        assert_eq!(
            name_of(event(code, KeyModifiers::NONE)).as_deref(),
            Some(name)
        );
    }
    assert_eq!(
        name_of(event(KeyCode::Char(' '), KeyModifiers::SHIFT)).as_deref(),
        Some("space")
    );
    assert_eq!(
        name_of(event(KeyCode::Char(' '), KeyModifiers::CONTROL)).as_deref(),
        Some("ctrl+space")
    );
    assert_eq!(
        name_of(event(KeyCode::Up, KeyModifiers::SHIFT)).as_deref(),
        Some("shift+up")
    );
}

#[test]
fn keypad_keys_need_the_keypad_state() {
    let keypad = |code| {
        KeyEvent::new_with_kind_and_state(
            code,
            KeyModifiers::NONE,
            KeyEventKind::Press,
            KeyEventState::KEYPAD,
        )
    };
    assert_eq!(name_of(keypad(KeyCode::Char('8'))).as_deref(), Some("kp8"));
    assert_eq!(name_of(keypad(KeyCode::Char('+'))).as_deref(), Some("kp+"));
    assert_eq!(name_of(keypad(KeyCode::Enter)).as_deref(), Some("kpenter"));
    assert_eq!(name_of(keypad(KeyCode::Up)).as_deref(), Some("kpup"));
    assert_eq!(
        name_of(keypad(KeyCode::PageDown)).as_deref(),
        Some("kppagedown")
    );
    assert_eq!(
        name_of(event(KeyCode::Char('8'), KeyModifiers::NONE)).as_deref(),
        Some("8")
    );
}

#[test]
fn unnameable_keys_have_no_name() {
    use crossterm::event::{MediaKeyCode, ModifierKeyCode};
    for code in [
        KeyCode::Null,
        KeyCode::CapsLock,
        KeyCode::NumLock,
        KeyCode::ScrollLock,
        KeyCode::PrintScreen,
        KeyCode::Pause,
        KeyCode::Menu,
        KeyCode::F(0),
        KeyCode::F(36),
        KeyCode::Char('\u{7f}'),
        KeyCode::Media(MediaKeyCode::Play),
        KeyCode::Modifier(ModifierKeyCode::LeftShift),
    ] {
        assert_eq!(name_of(event(code, KeyModifiers::NONE)), None, "{code:?}");
    }
    assert_eq!(
        name_of(event(KeyCode::Char('w'), KeyModifiers::SUPER)),
        None
    );
}

#[test]
fn keypad_twins_go_both_ways() {
    for (keypad, main) in [
        ("kp8", "8"),
        ("kp+", "+"),
        ("kpenter", "enter"),
        ("kpup", "up"),
        ("ctrl+kp5", "ctrl+5"),
    ] {
        assert_eq!(key(keypad).keypad_twin(), Some(key(main)));
        assert_eq!(key(main).keypad_twin(), Some(key(keypad)));
    }
    for lone in ["kpbegin", "a", "space", "esc", "tab", "f5", "?"] {
        assert_eq!(key(lone).keypad_twin(), None, "{lone}");
    }
}

#[test]
fn unmodified_keys_sort_first() {
    assert!(key("q") < key("ctrl+c"));
    assert!(key("w") < key("space"));
}
