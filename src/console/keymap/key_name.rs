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
mod tests;
