//! Key names as text: `Display`, `FromStr`, serde, and the words for a wrong name.

use std::fmt;
use std::str::FromStr;

use super::{BaseKey, KeyName, KeypadKey, MAX_FUNCTION_KEY, Modifiers, NamedKey};
use super::{is_keypad_char, shifted_letter};
use crate::console::keymap::single_char;

impl fmt::Display for KeyName {
    fn fmt(&self, formatter: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Modifiers { ctrl, alt, shift } = self.modifiers;
        for (held, prefix) in [(ctrl, "ctrl+"), (alt, "alt+"), (shift, "shift+")] {
            if held {
                formatter.write_str(prefix)?;
            }
        }
        match self.key {
            BaseKey::Char(character) => write!(formatter, "{character}"),
            BaseKey::Named(named) => formatter.write_str(named.name()),
            BaseKey::Function(number) => write!(formatter, "f{number}"),
            BaseKey::Keypad(KeypadKey::Char(character)) => write!(formatter, "kp{character}"),
            BaseKey::Keypad(KeypadKey::Named(named)) => write!(formatter, "kp{}", named.name()),
            BaseKey::Keypad(KeypadKey::Begin) => formatter.write_str("kpbegin"),
        }
    }
}

/// A key name that could not be parsed: the name as written and why.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown key {name:?} ({reason})")]
pub struct KeyNameError {
    pub name: String,
    pub reason: BadKeyName,
}

/// Why a key name is wrong, in the words a keymap file's author reads.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum BadKeyName {
    #[error("{0} appears twice")]
    ModifierTwice(&'static str),
    #[error("{SHIFT_RULE}")]
    ShiftedCharacter,
    #[error("{SHIFT_RULE}: did you mean \"{0}\"?")]
    ShiftedLetter(KeyName),
    #[error("write the space bar as \"space\"")]
    SpaceBar,
    #[error("control, bidi and whitespace characters have no key name")]
    Unprintable,
    #[error("function keys go from f1 to f{MAX_FUNCTION_KEY}")]
    NoSuchFunctionKey,
    #[error("the key is missing; {EXPECTED_KEYS}")]
    Missing,
    #[error("key names are lowercase: did you mean {0:?}?")]
    Uppercase(String),
    #[error("{EXPECTED_KEYS}")]
    Unknown,
}

const SHIFT_RULE: &str = "shift+ is not used with character keys: a key is named by the \
    character it types (\"A\" rather than \"shift+a\", \"?\" rather than \"shift+/\"); space \
    and keypad keys match with or without shift";

const EXPECTED_KEYS: &str = "expected a character such as \"a\", \"A\" or \"?\", a named key \
    (space, enter, esc, tab, backspace, delete, insert, home, end, pageup, pagedown, up, down, \
    left, right, f1..f35), a keypad key (kp0..kp9, kp., kp/, kp*, kp-, kp+, kp=, kp,, kpenter, \
    kpup, kpdown, kpleft, kpright, kphome, kpend, kppageup, kppagedown, kpinsert, kpdelete, \
    kpbegin), optionally after ctrl+, alt+ or shift+";

impl FromStr for KeyName {
    type Err = KeyNameError;

    fn from_str(name: &str) -> Result<KeyName, KeyNameError> {
        let refuse = |reason: BadKeyName| KeyNameError {
            name: name.to_owned(),
            reason,
        };
        let mut modifiers = Modifiers::NONE;
        let mut rest = name;
        loop {
            let (flag, prefix) = if rest.starts_with("ctrl+") {
                (&mut modifiers.ctrl, "ctrl+")
            } else if rest.starts_with("alt+") {
                (&mut modifiers.alt, "alt+")
            } else if rest.starts_with("shift+") {
                (&mut modifiers.shift, "shift+")
            } else {
                break;
            };
            if rest.len() == prefix.len() {
                // "ctrl+" alone: the '+' is not a key here, there is no key at all.
                break;
            }
            if *flag {
                return Err(refuse(BadKeyName::ModifierTwice(prefix)));
            }
            *flag = true;
            rest = &rest[prefix.len()..];
        }
        let key = parse_base_key(rest).map_err(refuse)?;
        if modifiers.shift && key.is_character() {
            let capital = match key {
                BaseKey::Char(character) if shifted_letter(character) != character => {
                    Some(KeyName {
                        modifiers: Modifiers {
                            shift: false,
                            ..modifiers
                        },
                        key: BaseKey::Char(shifted_letter(character)),
                    })
                }
                _ => None,
            };
            return Err(refuse(match capital {
                Some(capital) => BadKeyName::ShiftedLetter(capital),
                None => BadKeyName::ShiftedCharacter,
            }));
        }
        Ok(KeyName { modifiers, key })
    }
}

fn parse_base_key(text: &str) -> Result<BaseKey, BadKeyName> {
    if let Some(character) = single_char(text.chars()) {
        return if character == ' ' {
            Err(BadKeyName::SpaceBar)
        } else if crate::text::is_unsafe(character) || character.is_whitespace() {
            Err(BadKeyName::Unprintable)
        } else {
            Ok(BaseKey::Char(character))
        };
    }
    if let Some(named) = NamedKey::from_name(text) {
        return Ok(BaseKey::Named(named));
    }
    if let Some(digits) = text.strip_prefix('f')
        && !digits.is_empty()
        && digits.bytes().all(|byte| byte.is_ascii_digit())
        && !digits.starts_with('0')
    {
        return match digits.parse::<u8>() {
            Ok(number) if (1..=MAX_FUNCTION_KEY).contains(&number) => Ok(BaseKey::Function(number)),
            _ => Err(BadKeyName::NoSuchFunctionKey),
        };
    }
    if let Some(keypad) = text.strip_prefix("kp") {
        if let Some(character) = single_char(keypad.chars())
            && is_keypad_char(character)
        {
            return Ok(BaseKey::Keypad(KeypadKey::Char(character)));
        }
        if keypad == "begin" {
            return Ok(BaseKey::Keypad(KeypadKey::Begin));
        }
        if let Some(named) = NamedKey::from_name(keypad)
            && named.is_on_keypad()
        {
            return Ok(BaseKey::Keypad(KeypadKey::Named(named)));
        }
    }
    if text.is_empty() {
        return Err(BadKeyName::Missing);
    }
    let lowercase = text.to_lowercase();
    if lowercase != text
        && let Ok(key) = parse_base_key(&lowercase)
        && !matches!(key, BaseKey::Char(_))
    {
        return Err(BadKeyName::Uppercase(lowercase));
    }
    Err(BadKeyName::Unknown)
}

impl serde::Serialize for KeyName {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_str(self)
    }
}

impl<'de> serde::Deserialize<'de> for KeyName {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<KeyName, D::Error> {
        let text = <std::borrow::Cow<'de, str>>::deserialize(deserializer)?;
        text.parse().map_err(serde::de::Error::custom)
    }
}
