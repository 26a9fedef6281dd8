//! Key names as text: `Display`, `FromStr`, serde, and the words for a wrong name.

use std::fmt;
use std::str::FromStr;

use super::{BaseKey, KeyName, KeypadKey, MAX_FUNCTION_KEY, Modifiers, NamedKey};
use super::{is_keypad_char, shifted_letter};
use crate::console::keymap::single_char;

impl fmt::Display for KeyName {
    fn fmt(&self, formatter: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.modifiers.ctrl {
            formatter.write_str("ctrl+")?;
        }
        if self.modifiers.alt {
            formatter.write_str("alt+")?;
        }
        if self.modifiers.shift {
            formatter.write_str("shift+")?;
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
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct KeyNameError {
    pub name: String,
    pub reason: String,
}

impl fmt::Display for KeyNameError {
    fn fmt(&self, formatter: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(formatter, "unknown key {:?} ({})", self.name, self.reason)
    }
}

impl std::error::Error for KeyNameError {}

const EXPECTED_KEYS: &str = "expected a character such as \"a\", \"A\" or \"?\", a named key \
    (space, enter, esc, tab, backspace, delete, insert, home, end, pageup, pagedown, up, down, \
    left, right, f1..f35), a keypad key (kp0..kp9, kp., kp/, kp*, kp-, kp+, kp=, kp,, kpenter, \
    kpup, kpdown, kpleft, kpright, kphome, kpend, kppageup, kppagedown, kpinsert, kpdelete, \
    kpbegin), optionally after ctrl+, alt+ or shift+";

impl FromStr for KeyName {
    type Err = KeyNameError;

    fn from_str(name: &str) -> Result<KeyName, KeyNameError> {
        let refuse = |reason: String| KeyNameError {
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
                return Err(refuse(format!("{prefix} appears twice")));
            }
            *flag = true;
            rest = &rest[prefix.len()..];
        }
        let key = parse_base_key(rest).map_err(refuse)?;
        if modifiers.shift && key.is_character() {
            const RULE: &str = "shift+ is not used with character keys: a key is named by the \
                character it types (\"A\" rather than \"shift+a\", \"?\" rather than \
                \"shift+/\"); space and keypad keys match with or without shift";
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
                Some(capital) => format!("{RULE}: did you mean \"{capital}\"?"),
                None => RULE.to_owned(),
            }));
        }
        Ok(KeyName { modifiers, key })
    }
}

fn parse_base_key(text: &str) -> Result<BaseKey, String> {
    if let Some(character) = single_char(text.chars()) {
        return if character == ' ' {
            Err("write the space bar as \"space\"".to_owned())
        } else if crate::text::is_unsafe(character) || character.is_whitespace() {
            Err("control, bidi and whitespace characters have no key name".to_owned())
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
            _ => Err(format!("function keys go from f1 to f{MAX_FUNCTION_KEY}")),
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
        return Err(format!("the key is missing; {EXPECTED_KEYS}"));
    }
    let lowercase = text.to_lowercase();
    if lowercase != text
        && let Ok(key) = parse_base_key(&lowercase)
        && !matches!(key, BaseKey::Char(_))
    {
        return Err(format!(
            "key names are lowercase: did you mean {lowercase:?}?"
        ));
    }
    Err(EXPECTED_KEYS.to_owned())
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
