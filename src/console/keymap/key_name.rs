//! The identity of a key as a keymap names it, independent of press, repeat and release.
//!
//! # Names
//!
//! - A **character** is written as itself and is case-sensitive: `"a"`, `"A"`, `"?"`, `"+"`,
//!   `"["`. The space bar is `"space"`; other whitespace and control characters have no name.
//! - **Named keys**: `space`, `enter`, `esc`, `tab`, `backspace`, `delete`, `insert`, `home`,
//!   `end`, `pageup`, `pagedown`, `up`, `down`, `left`, `right`, and `f1` to `f35`.
//! - **Keypad keys** (only told apart by terminals with the kitty keyboard protocol): `kp0` to
//!   `kp9`, `kp.`, `kp/`, `kp*`, `kp-`, `kp+`, `kp=`, `kp,`, `kpenter`, and with NumLock off
//!   `kpup`, `kpdown`, `kpleft`, `kpright`, `kphome`, `kpend`, `kppageup`, `kppagedown`,
//!   `kpinsert`, `kpdelete`, `kpbegin` (the 5 in the middle).
//! - **Modifiers** are prefixes: `ctrl+`, `alt+` and, for keys that are not characters only,
//!   `shift+` (`"shift+tab"`, `"shift+up"`, `"shift+f5"`). Any order parses; `Display` writes
//!   `ctrl+alt+shift+`. Key names are lowercase.
//!
//! # Shift
//!
//! A character key names the character it types, so shift is part of the character and never a
//! prefix: `"A"`, not `"shift+a"`; `"?"`, not `"shift+/"`. Terminals report a shifted letter
//! either as `Char('A')` or (kitty protocol) as `Char('a')` with SHIFT: both are `"A"`. A
//! shifted non-letter arrives as the shifted character (`Char('?')`, with or without SHIFT) in
//! every mode except the kitty protocol *without* `REPORT_ALTERNATE_KEYS`, which reports only the
//! unshifted key (`Char('/')` + SHIFT) and so cannot tell `?` from `/` without knowing the
//! keyboard layout. The console must therefore push `REPORT_ALTERNATE_KEYS` together with
//! `REPORT_EVENT_TYPES | REPORT_ALL_KEYS_AS_ESCAPE_CODES`; no layout is guessed here.
//!
//! # Keypad
//!
//! With the kitty protocol crossterm marks keypad keys with `KeyEventState::KEYPAD`: those are
//! named `kp8`, `kpenter`, `kpup`... Without it (tmux, xterm, GNOME Terminal, the Linux
//! console) the keypad is indistinguishable from the main keys: keypad 8 arrives as `"8"`, or as
//! `"up"` with NumLock off. [`KeyName::keypad_twin`] links the two, and
//! [`Keymap::action`](super::Keymap::action) falls back to the twin when a key has no binding of
//! its own, so a keymap that binds `"kp8"` works in every terminal and behaves the same in all of
//! them (the top-row 8 then does what keypad 8 does, as it must in a terminal that cannot tell
//! them apart).

mod text;

use crossterm::event::{KeyCode, KeyEvent, KeyEventState, KeyModifiers};

pub use text::KeyNameError;

/// The highest function key crossterm reports (`KeyCode::F(35)`).
pub const MAX_FUNCTION_KEY: u8 = 35;

/// A key that is not a character.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum NamedKey {
    Space,
    Enter,
    Esc,
    Tab,
    Backspace,
    Delete,
    Insert,
    Home,
    End,
    PageUp,
    PageDown,
    Up,
    Down,
    Left,
    Right,
}

impl NamedKey {
    pub const ALL: [NamedKey; 15] = [
        NamedKey::Space,
        NamedKey::Enter,
        NamedKey::Esc,
        NamedKey::Tab,
        NamedKey::Backspace,
        NamedKey::Delete,
        NamedKey::Insert,
        NamedKey::Home,
        NamedKey::End,
        NamedKey::PageUp,
        NamedKey::PageDown,
        NamedKey::Up,
        NamedKey::Down,
        NamedKey::Left,
        NamedKey::Right,
    ];

    /// The name used in keymap files.
    pub fn name(self) -> &'static str {
        match self {
            NamedKey::Space => "space",
            NamedKey::Enter => "enter",
            NamedKey::Esc => "esc",
            NamedKey::Tab => "tab",
            NamedKey::Backspace => "backspace",
            NamedKey::Delete => "delete",
            NamedKey::Insert => "insert",
            NamedKey::Home => "home",
            NamedKey::End => "end",
            NamedKey::PageUp => "pageup",
            NamedKey::PageDown => "pagedown",
            NamedKey::Up => "up",
            NamedKey::Down => "down",
            NamedKey::Left => "left",
            NamedKey::Right => "right",
        }
    }

    fn from_name(name: &str) -> Option<NamedKey> {
        NamedKey::ALL.into_iter().find(|key| key.name() == name)
    }

    /// Whether the keypad has a key that the kitty protocol reports as this one with the
    /// `KEYPAD` state (`kpenter`, `kpup`, ... `kpdelete`).
    fn is_on_keypad(self) -> bool {
        !matches!(
            self,
            NamedKey::Space | NamedKey::Esc | NamedKey::Tab | NamedKey::Backspace
        )
    }
}

/// The characters of the keypad: `kp0`..`kp9`, `kp.`, `kp/`, `kp*`, `kp-`, `kp+`, `kp=`, `kp,`.
fn is_keypad_char(character: char) -> bool {
    character.is_ascii_digit() || ".,/*-+=".contains(character)
}

/// A key of the numeric keypad, as told apart by the kitty keyboard protocol.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum KeypadKey {
    /// A digit or an operator key: `kp8`, `kp+`.
    Char(char),
    /// A navigation key (NumLock off) or the keypad's enter: `kpup`, `kpenter`.
    Named(NamedKey),
    /// The middle key (5) with NumLock off: `kpbegin`.
    Begin,
}

/// The key itself, without modifiers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum BaseKey {
    /// A printable character other than space (`Named(Space)`); case-sensitive.
    Char(char),
    Named(NamedKey),
    /// `f1` to `f35`.
    Function(u8),
    Keypad(KeypadKey),
}

impl BaseKey {
    /// Whether the key types a character, so that shift is part of its identity and never a
    /// prefix.
    const fn is_character(self) -> bool {
        matches!(
            self,
            BaseKey::Char(_)
                | BaseKey::Named(NamedKey::Space)
                | BaseKey::Keypad(KeypadKey::Char(_))
        )
    }
}

/// The modifiers a keymap can name. Shift is only ever set for keys that are not characters.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Modifiers {
    pub ctrl: bool,
    pub alt: bool,
    pub shift: bool,
}

impl Modifiers {
    pub const NONE: Modifiers = Modifiers {
        ctrl: false,
        alt: false,
        shift: false,
    };
}

/// A key as a keymap names it: modifiers and a base key. Ordered with unmodified keys first.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct KeyName {
    modifiers: Modifiers,
    key: BaseKey,
}

impl KeyName {
    /// The name of the key of a crossterm key event, whatever its kind (press, repeat or
    /// release).
    ///
    /// `None` for keys a keymap cannot name: bare modifier keys (reported on their own by the
    /// kitty protocol), lock keys, media keys, print screen, pause, menu, `Null`, control
    /// characters, and any key held with super, hyper or meta.
    pub fn from_event(event: &KeyEvent) -> Option<KeyName> {
        if event
            .modifiers
            .intersects(KeyModifiers::SUPER | KeyModifiers::HYPER | KeyModifiers::META)
        {
            return None;
        }
        let on_keypad = event.state.contains(KeyEventState::KEYPAD);
        let mut modifiers = Modifiers {
            ctrl: event.modifiers.contains(KeyModifiers::CONTROL),
            alt: event.modifiers.contains(KeyModifiers::ALT),
            shift: event.modifiers.contains(KeyModifiers::SHIFT),
        };
        let key = match event.code {
            KeyCode::Char(character) if on_keypad && is_keypad_char(character) => {
                BaseKey::Keypad(KeypadKey::Char(character))
            }
            KeyCode::Char(' ') => BaseKey::Named(NamedKey::Space),
            KeyCode::Char(character)
                if crate::text::is_unsafe(character) || character.is_whitespace() =>
            {
                return None;
            }
            KeyCode::Char(character) if modifiers.shift => BaseKey::Char(shifted_letter(character)),
            KeyCode::Char(character) => BaseKey::Char(character),
            KeyCode::BackTab => {
                modifiers.shift = true;
                BaseKey::Named(NamedKey::Tab)
            }
            KeyCode::F(number) if (1..=MAX_FUNCTION_KEY).contains(&number) => {
                BaseKey::Function(number)
            }
            KeyCode::KeypadBegin => BaseKey::Keypad(KeypadKey::Begin),
            code => {
                let named = match code {
                    KeyCode::Enter => NamedKey::Enter,
                    KeyCode::Esc => NamedKey::Esc,
                    KeyCode::Tab => NamedKey::Tab,
                    KeyCode::Backspace => NamedKey::Backspace,
                    KeyCode::Delete => NamedKey::Delete,
                    KeyCode::Insert => NamedKey::Insert,
                    KeyCode::Home => NamedKey::Home,
                    KeyCode::End => NamedKey::End,
                    KeyCode::PageUp => NamedKey::PageUp,
                    KeyCode::PageDown => NamedKey::PageDown,
                    KeyCode::Up => NamedKey::Up,
                    KeyCode::Down => NamedKey::Down,
                    KeyCode::Left => NamedKey::Left,
                    KeyCode::Right => NamedKey::Right,
                    _ => return None,
                };
                if on_keypad && named.is_on_keypad() {
                    BaseKey::Keypad(KeypadKey::Named(named))
                } else {
                    BaseKey::Named(named)
                }
            }
        };
        if key.is_character() {
            modifiers.shift = false;
        }
        Some(KeyName { modifiers, key })
    }

    /// An unmodified character key: `KeyName::char('y')` is `"y"`, `KeyName::char(' ')` is
    /// `"space"`.
    pub const fn char(character: char) -> KeyName {
        let key = match character {
            ' ' => BaseKey::Named(NamedKey::Space),
            _ => BaseKey::Char(character),
        };
        KeyName {
            modifiers: Modifiers::NONE,
            key,
        }
    }

    /// An unmodified named key: `KeyName::named(NamedKey::Enter)` is `"enter"`.
    pub const fn named(key: NamedKey) -> KeyName {
        KeyName {
            modifiers: Modifiers::NONE,
            key: BaseKey::Named(key),
        }
    }

    /// The same key with ctrl held: `KeyName::char('c').with_ctrl()` is `"ctrl+c"`.
    pub const fn with_ctrl(mut self) -> KeyName {
        self.modifiers.ctrl = true;
        self
    }

    /// The same key with shift held: `"shift+tab"`. A character key is left as it is: shift
    /// is part of the character it types (see the module docs).
    pub const fn with_shift(mut self) -> KeyName {
        if !self.key.is_character() {
            self.modifiers.shift = true;
        }
        self
    }

    /// The key without modifiers.
    pub fn base(&self) -> BaseKey {
        self.key
    }

    pub fn modifiers(&self) -> Modifiers {
        self.modifiers
    }

    /// The same key with no modifiers: what a release may be reported as when the technician
    /// lets go of ctrl or alt before the key itself.
    pub fn without_modifiers(&self) -> KeyName {
        KeyName {
            modifiers: Modifiers::NONE,
            key: self.key,
        }
    }

    /// The key that a terminal without the kitty protocol reports in place of this one, or the
    /// other way round: `kp8` <-> `8`, `kp+` <-> `+`, `kpenter` <-> `enter`, `kpup` <-> `up`
    /// (modifiers kept). `None` for keys without a twin (`kpbegin`, letters, `f5`, ...).
    pub fn keypad_twin(&self) -> Option<KeyName> {
        let twin = match self.key {
            BaseKey::Keypad(KeypadKey::Char(character)) => BaseKey::Char(character),
            BaseKey::Keypad(KeypadKey::Named(named)) => BaseKey::Named(named),
            BaseKey::Keypad(KeypadKey::Begin) | BaseKey::Function(_) => return None,
            BaseKey::Char(character) if is_keypad_char(character) => {
                BaseKey::Keypad(KeypadKey::Char(character))
            }
            BaseKey::Named(named) if named.is_on_keypad() => {
                BaseKey::Keypad(KeypadKey::Named(named))
            }
            BaseKey::Char(_) | BaseKey::Named(_) => return None,
        };
        Some(KeyName {
            modifiers: self.modifiers,
            key: twin,
        })
    }
}

/// The character a shifted key types when the terminal reported the unshifted letter with
/// SHIFT (kitty protocol): the capital letter. Anything else is already the typed character,
/// and so is a letter whose capital is more than one character (`ß`, `ŉ`): no one character
/// is its capital. The one rule for the key's name and the text it types (`run::key_input`).
pub fn shifted_letter(character: char) -> char {
    if !character.is_lowercase() {
        return character;
    }
    let mut upper = character.to_uppercase();
    match (upper.next(), upper.next()) {
        (Some(single), None) => single,
        _ => character,
    }
}

#[cfg(test)]
mod tests {
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
        assert!(key("ctrl++").modifiers().ctrl);
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
}
