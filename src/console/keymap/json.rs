//! Reading a keymap file, refusing anything doubtful with a position. Every check runs inside
//! deserialization so serde_json gives the line and column; for errors about one string
//! [`token_start`] walks back to its opening quote (serde_json's position may be past it).

use super::{Keymap, KeymapError, KeymapErrorKind, REQUIRED_ACTIONS, TextPosition};
use crate::console::action::Action;
use crate::console::keymap::KeyName;
use serde::de::{self, DeserializeSeed, Deserializer, MapAccess, Visitor};
use std::cell::Cell;
use std::collections::BTreeMap;
use std::fmt;

const FIELDS: [&str; 3] = ["name", "description", "bindings"];

pub(super) fn parse(source_name: &str, text: &str) -> Result<Keymap, KeymapError> {
    let problem = Cell::new(None);
    let mut deserializer = serde_json::Deserializer::from_str(text);
    let parsed = FileVisitor {
        problem: ProblemSlot(&problem),
    }
    .deserialize(&mut deserializer)
    .and_then(|keymap| deserializer.end().map(|()| keymap));
    parsed.map_err(|error| describe(source_name, text, &error, problem.get()))
}

fn describe(
    source_name: &str,
    text: &str,
    error: &serde_json::Error,
    problem: Option<KeymapErrorKind>,
) -> KeymapError {
    let kind = problem.unwrap_or(match error.is_data() {
        true => KeymapErrorKind::InvalidValue,
        false => KeymapErrorKind::InvalidJson,
    });
    let shown = error.to_string();
    let position_suffix = format!(" at line {} column {}", error.line(), error.column());
    let message = shown
        .strip_suffix(&position_suffix)
        .unwrap_or(&shown)
        .to_owned();
    let read_up_to = byte_offset(text, error.line(), error.column());
    let points_at_a_string = matches!(
        kind,
        KeymapErrorKind::UnknownKey
            | KeymapErrorKind::UnknownAction
            | KeymapErrorKind::DuplicateKey
            | KeymapErrorKind::UnknownField
            | KeymapErrorKind::DuplicateField
    );
    let position = match read_up_to {
        Some(end) => match points_at_a_string.then(|| token_start(text, end)).flatten() {
            Some(start) => position_of_character(text, start),
            None => position_of_last_read(text, end),
        },
        None => TextPosition {
            line: error.line().max(1),
            column: error.column().max(1),
        },
    };
    KeymapError {
        source_name: source_name.to_owned(),
        position: Some(position),
        kind,
        message,
    }
}

/// The byte offset of serde_json's (line, column): `column` bytes into line `line`.
fn byte_offset(text: &str, line: usize, column: usize) -> Option<usize> {
    let line_start = if line <= 1 {
        0
    } else {
        text.match_indices('\n').nth(line - 2)?.0 + 1
    };
    let offset = line_start.checked_add(column)?;
    (offset <= text.len()).then_some(offset)
}

/// The position of the last character before byte `end` (after a newline: next line, column 1).
fn position_of_last_read(text: &str, end: usize) -> TextPosition {
    let before = text.get(..end).unwrap_or(text);
    match before.char_indices().next_back() {
        Some((_, '\n')) | None => position_of_character(text, before.len()),
        Some((start, _)) => position_of_character(text, start),
    }
}

/// Line and character column (both from 1) of the character starting at byte `offset`.
fn position_of_character(text: &str, offset: usize) -> TextPosition {
    let before = text.get(..offset).unwrap_or(text);
    let line_start = before.rfind('\n').map_or(0, |newline| newline + 1);
    TextPosition {
        line: 1 + before.matches('\n').count(),
        column: 1 + before[line_start..].chars().count(),
    }
}

/// The offset of the opening quote of the string ending before `end`, skipping whitespace and at
/// most one `}` (serde_json may have consumed it). `None` if no string ends there.
fn token_start(text: &str, end: usize) -> Option<usize> {
    let bytes = text.as_bytes();
    let skip_whitespace = |mut index: usize| {
        while index > 0 && bytes[index - 1].is_ascii_whitespace() {
            index -= 1;
        }
        index
    };
    let mut index = skip_whitespace(end.min(bytes.len()));
    if index > 0 && bytes[index - 1] == b'}' {
        index = skip_whitespace(index - 1);
    }
    if index == 0 || bytes[index - 1] != b'"' {
        return None;
    }
    let closing_quote = index - 1;
    // The nearest quote after an even run of backslashes opens it.
    let mut candidate = closing_quote;
    while candidate > 0 {
        candidate -= 1;
        if bytes[candidate] == b'"' {
            let backslashes = bytes[..candidate]
                .iter()
                .rev()
                .take_while(|byte| **byte == b'\\')
                .count();
            if backslashes.is_multiple_of(2) {
                return Some(candidate);
            }
        }
    }
    None
}

/// Records the kind of the first problem found, for [`describe`].
#[derive(Clone, Copy)]
struct ProblemSlot<'a>(&'a Cell<Option<KeymapErrorKind>>);

impl ProblemSlot<'_> {
    fn raise<E: de::Error>(self, kind: KeymapErrorKind, message: impl fmt::Display) -> E {
        self.0.set(Some(kind));
        E::custom(message)
    }
}

struct FileVisitor<'a> {
    problem: ProblemSlot<'a>,
}

impl<'de> DeserializeSeed<'de> for FileVisitor<'_> {
    type Value = Keymap;

    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<Keymap, D::Error> {
        deserializer.deserialize_map(self)
    }
}

impl<'de> Visitor<'de> for FileVisitor<'_> {
    type Value = Keymap;

    fn expecting(&self, formatter: &mut fmt::Formatter) -> fmt::Result {
        formatter.write_str("a keymap object with \"name\", \"description\" and \"bindings\"")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Keymap, A::Error> {
        let problem = self.problem;
        let mut name: Option<String> = None;
        let mut description: Option<String> = None;
        let mut bindings: Option<BTreeMap<KeyName, Action>> = None;
        while let Some(field) = map.next_key::<String>()? {
            let duplicate = || {
                problem.raise(
                    KeymapErrorKind::DuplicateField,
                    format!("field {field:?} appears twice"),
                )
            };
            match field.as_str() {
                "name" | "description" => {
                    let text = if field == "name" {
                        &mut name
                    } else {
                        &mut description
                    };
                    if text.is_some() {
                        return Err(duplicate());
                    }
                    *text = Some(shown_text(problem, &field, map.next_value()?)?);
                }
                "bindings" => {
                    if bindings.is_some() {
                        return Err(duplicate());
                    }
                    bindings = Some(map.next_value_seed(BindingsSeed { problem })?);
                }
                _ => {
                    return Err(problem.raise(
                        KeymapErrorKind::UnknownField,
                        format!(
                            "unknown field {field:?} (expected one of: {})",
                            FIELDS.join(", ")
                        ),
                    ));
                }
            }
        }
        let missing = |field: &str| {
            problem.raise(
                KeymapErrorKind::MissingField,
                format!("the keymap has no {field:?} field"),
            )
        };
        let name = name.ok_or_else(|| missing("name"))?;
        let bindings = bindings.ok_or_else(|| missing("bindings"))?;
        Ok(Keymap {
            name,
            description: description.unwrap_or_default(),
            bindings,
        })
    }
}

/// A keymap's name or description is shown, so it is refused as a key name is, naming where.
fn shown_text<E: de::Error>(
    problem: ProblemSlot<'_>,
    field: &str,
    text: String,
) -> Result<String, E> {
    match text
        .char_indices()
        .find(|(_, c)| crate::text::is_unsafe(*c))
    {
        None => Ok(text),
        Some((offset, c)) => Err(problem.raise(
            KeymapErrorKind::InvalidValue,
            format!(
                "the keymap's {field} has the control or bidi character U+{:04X} at byte {offset}",
                u32::from(c)
            ),
        )),
    }
}

struct BindingsSeed<'a> {
    problem: ProblemSlot<'a>,
}

impl<'de> DeserializeSeed<'de> for BindingsSeed<'_> {
    type Value = BTreeMap<KeyName, Action>;

    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<Self::Value, D::Error> {
        deserializer.deserialize_map(self)
    }
}

impl<'de> Visitor<'de> for BindingsSeed<'_> {
    type Value = BTreeMap<KeyName, Action>;

    fn expecting(&self, formatter: &mut fmt::Formatter) -> fmt::Result {
        formatter.write_str("an object of bindings such as {\"w\": \"jog_x_plus\"}")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
        let problem = self.problem;
        let mut bindings = BTreeMap::new();
        while let Some(key) = map.next_key_seed(key_name(problem))? {
            if let Some(earlier) = bindings.get(&key) {
                return Err(problem.raise(
                    KeymapErrorKind::DuplicateKey,
                    format!(
                        "duplicate binding: key \"{key}\" is already bound above (to \"{}\")",
                        Action::name(*earlier)
                    ),
                ));
            }
            let action = map.next_value_seed(action(problem))?;
            bindings.insert(key, action);
        }
        for required in REQUIRED_ACTIONS {
            if !bindings.values().any(|bound| *bound == required) {
                return Err(problem.raise(
                    KeymapErrorKind::MissingRequiredAction,
                    format!(
                        "no key is bound to \"{}\": every keymap must let the technician stop \
                         the arm and quit",
                        required.name()
                    ),
                ));
            }
        }
        Ok(bindings)
    }
}

/// A string turned into a `T` by `read`, whose refusal is raised as the problem of its kind.
struct TextSeed<'a, T> {
    problem: ProblemSlot<'a>,
    expecting: &'static str,
    read: fn(&str) -> Result<T, (KeymapErrorKind, String)>,
}

impl<'de, T> DeserializeSeed<'de> for TextSeed<'_, T> {
    type Value = T;

    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<T, D::Error> {
        deserializer.deserialize_str(self)
    }
}

impl<T> Visitor<'_> for TextSeed<'_, T> {
    type Value = T;

    fn expecting(&self, formatter: &mut fmt::Formatter) -> fmt::Result {
        formatter.write_str(self.expecting)
    }

    fn visit_str<E: de::Error>(self, text: &str) -> Result<T, E> {
        (self.read)(text).map_err(|(kind, message)| self.problem.raise(kind, message))
    }
}

fn key_name(problem: ProblemSlot<'_>) -> TextSeed<'_, KeyName> {
    TextSeed {
        problem,
        expecting: "a key name",
        read: |text| {
            text.parse().map_err(|error: super::KeyNameError| {
                (KeymapErrorKind::UnknownKey, error.to_string())
            })
        },
    }
}

fn action(problem: ProblemSlot<'_>) -> TextSeed<'_, Action> {
    TextSeed {
        problem,
        expecting: "an action name such as \"stop\"",
        read: |text| {
            let found = Action::ALL.into_iter().find(|action| action.name() == text);
            found.ok_or_else(|| {
                let expected: Vec<String> = Action::ALL.iter().map(|a| a.name()).collect();
                let message = format!(
                    "unknown action {text:?} (expected one of: {})",
                    expected.join(", ")
                );
                (KeymapErrorKind::UnknownAction, message)
            })
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn token_start_finds_the_opening_quote() {
        let text = "{ \"ab\\\"c\" : 1 }";
        // Just after the closing quote, after the following whitespace, and after a `}`.
        assert_eq!(token_start(text, 9), Some(2));
        assert_eq!(token_start(text, 10), Some(2));
        assert_eq!(token_start("{\"a\"\n }", 7), Some(1));
        assert_eq!(token_start("{ 12 }", 4), None);
        assert_eq!(token_start("", 0), None);
    }

    #[test]
    fn positions_count_characters_from_one() {
        let text = "ab\né\"x\"";
        assert_eq!(
            position_of_character(text, 0),
            TextPosition { line: 1, column: 1 }
        );
        // 'é' is two bytes: the quote after it is byte 5, character column 2.
        assert_eq!(
            position_of_character(text, 5),
            TextPosition { line: 2, column: 2 }
        );
        assert_eq!(byte_offset(text, 2, 3), Some(6));
        assert_eq!(byte_offset(text, 3, 0), None);
    }
}
