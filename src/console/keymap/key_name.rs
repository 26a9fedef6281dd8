//! The identity of a key as a keymap names it, whatever its kind (press, repeat, release); the
//! names are listed in `docs/user-guide.md`, "Keymaps".
//!
//! A character key names the character it types, so shift is never a prefix (`"A"`, `"?"`). The
//! kitty protocol without `REPORT_ALTERNATE_KEYS` reports `?` as `/` + SHIFT, which cannot be told
//! apart without the layout, so the console pushes that flag with the others; no layout is guessed
//! here. Without the kitty protocol the keypad cannot be told from the main keys:
//! [`KeyName::keypad_twin`] links them.

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

/// Every named key: its name in keymap files and the crossterm code that reports it.
const NAMED_KEYS: [(NamedKey, &str, KeyCode); 15] = [
    (NamedKey::Space, "space", KeyCode::Char(' ')),
    (NamedKey::Enter, "enter", KeyCode::Enter),
    (NamedKey::Esc, "esc", KeyCode::Esc),
    (NamedKey::Tab, "tab", KeyCode::Tab),
    (NamedKey::Backspace, "backspace", KeyCode::Backspace),
    (NamedKey::Delete, "delete", KeyCode::Delete),
    (NamedKey::Insert, "insert", KeyCode::Insert),
    (NamedKey::Home, "home", KeyCode::Home),
    (NamedKey::End, "end", KeyCode::End),
    (NamedKey::PageUp, "pageup", KeyCode::PageUp),
    (NamedKey::PageDown, "pagedown", KeyCode::PageDown),
    (NamedKey::Up, "up", KeyCode::Up),
    (NamedKey::Down, "down", KeyCode::Down),
    (NamedKey::Left, "left", KeyCode::Left),
    (NamedKey::Right, "right", KeyCode::Right),
];

impl NamedKey {
    pub const ALL: [NamedKey; 15] = {
        let mut all = [NamedKey::Space; 15];
        let mut i = 0;
        while i < all.len() {
            all[i] = NAMED_KEYS[i].0;
            i += 1;
        }
        all
    };

    /// The name used in keymap files.
    pub fn name(self) -> &'static str {
        let named = NAMED_KEYS.iter().find(|(key, _, _)| *key == self);
        named.map_or("", |(_, name, _)| name)
    }

    fn from_name(name: &str) -> Option<NamedKey> {
        NamedKey::ALL.into_iter().find(|key| key.name() == name)
    }

    /// Whether the kitty protocol reports a keypad key as this one with the `KEYPAD` state.
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
    /// Whether the key types a character, so shift is part of it and never a prefix.
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
    /// The name of a crossterm key event's key. `None` for keys a keymap cannot name: bare
    /// modifiers, lock and media keys, print screen, pause, menu, `Null`, control characters, and
    /// anything held with super, hyper or meta.
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
                let (named, _, _) = NAMED_KEYS.iter().find(|(_, _, known)| *known == code)?;
                if on_keypad && named.is_on_keypad() {
                    BaseKey::Keypad(KeypadKey::Named(*named))
                } else {
                    BaseKey::Named(*named)
                }
            }
        };
        if key.is_character() {
            modifiers.shift = false;
        }
        Some(KeyName { modifiers, key })
    }

    /// An unmodified character key (`' '` is `"space"`).
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

    /// The key with shift: `"shift+tab"`; a character key is unchanged (shift is in the character).
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

    /// Without modifiers: a release after ctrl or alt was let go first.
    pub fn without_modifiers(&self) -> KeyName {
        KeyName {
            modifiers: Modifiers::NONE,
            key: self.key,
        }
    }

    /// The key a terminal without the kitty protocol reports in place of this one, or the other way
    /// round (`kp8` <-> `8`, `kpenter` <-> `enter`, `kpup` <-> `up`, modifiers kept); `None`
    /// without a twin.
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

/// The character a key types when the kitty protocol reported the unshifted letter with SHIFT: the
/// capital (unless it is more than one character, `ß`). The one rule for a key's name and its text
/// (`run::key_input`).
pub fn shifted_letter(character: char) -> char {
    if !character.is_lowercase() {
        return character;
    }
    super::single_char(character.to_uppercase()).unwrap_or(character)
}

#[cfg(test)]
mod tests;
