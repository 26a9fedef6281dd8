//! Keymaps: which key does which [`Action`], loaded from JSON (format: `docs/user-guide.md`,
//! "Keymaps"). A bad file is refused with a [`KeymapError`] naming file, line and column. The
//! keymaps under `keymaps/` are built in ([`Keymap::builtin`]).
//!
//! [`Keymap::action`] falls back to a key's [keypad twin](KeyName::keypad_twin) when it has no
//! binding of its own (`kp8` <-> `8`): terminals without the kitty protocol cannot tell the two
//! apart. An explicit binding wins.

mod json;
mod key_name;

pub use key_name::{
    BaseKey, KeyName, KeyNameError, KeypadKey, MAX_FUNCTION_KEY, Modifiers, NamedKey,
    shifted_letter,
};

use crate::console::action::Action;
use std::collections::BTreeMap;
use std::fmt;

/// The keymaps built into the binary: name and JSON text.
const BUILTIN_KEYMAPS: [(&str, &str); 2] = [
    ("default", include_str!("../../keymaps/default.json")),
    ("numpad", include_str!("../../keymaps/numpad.json")),
];

/// The actions every keymap must bind: the technician must always be able to stop and quit.
pub const REQUIRED_ACTIONS: [Action; 2] = [Action::Stop, Action::Quit];

/// A validated keymap: every key names one action, and `stop` and `quit` are bound.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Keymap {
    name: String,
    description: String,
    bindings: BTreeMap<KeyName, Action>,
}

impl Keymap {
    /// Parses and validates a keymap; `source_name` is for error messages only.
    pub fn from_json(source_name: &str, text: &str) -> Result<Keymap, KeymapError> {
        json::parse(source_name, text)
    }

    /// A keymap built into the binary, by name (`"default"`, `"numpad"`).
    pub fn builtin(name: &str) -> Option<Keymap> {
        let (name, text) = builtin_source(name)?;
        Keymap::from_json(&builtin_source_name(name), text).ok()
    }

    /// The names of the built-in keymaps.
    pub fn builtin_names() -> impl Iterator<Item = &'static str> {
        BUILTIN_KEYMAPS.iter().map(|(name, _)| *name)
    }

    /// The JSON text of a built-in keymap, e.g. to write it out as a starting point.
    pub fn builtin_json(name: &str) -> Option<&'static str> {
        builtin_source(name).map(|(_, text)| text)
    }

    /// A built-in keymap by name, or else a keymap file by path (`--keymap NAME|PATH`).
    pub fn load(name_or_path: &str) -> Result<Keymap, KeymapError> {
        if let Some((name, text)) = builtin_source(name_or_path) {
            return Keymap::from_json(&builtin_source_name(name), text);
        }
        match crate::files::read_to_string_bounded(
            std::path::Path::new(name_or_path),
            crate::files::KEYMAP_LIMIT,
        ) {
            Ok(text) => Keymap::from_json(name_or_path, &text),
            Err(error) => {
                let looks_like_a_name = !name_or_path.contains(['/', '\\', '.']);
                let message = if looks_like_a_name {
                    format!(
                        "no built-in keymap has this name (built-in: {}) and there is no \
                         readable file by this name ({error})",
                        Keymap::builtin_names().collect::<Vec<_>>().join(", ")
                    )
                } else {
                    format!("cannot read the keymap file: {error}")
                };
                Err(KeymapError {
                    source_name: name_or_path.to_owned(),
                    position: None,
                    kind: KeymapErrorKind::Unreadable,
                    message,
                })
            }
        }
    }

    pub fn name(&self) -> &str {
        &self.name
    }

    pub fn description(&self) -> &str {
        &self.description
    }

    /// Every binding as written in the file, ordered by key (unmodified keys first).
    pub fn bindings(&self) -> &BTreeMap<KeyName, Action> {
        &self.bindings
    }

    /// The action of a key: its own binding, or else its keypad twin's (see the module docs).
    pub fn action(&self, key: &KeyName) -> Option<Action> {
        self.bindings.get(key).copied().or_else(|| {
            key.keypad_twin()
                .and_then(|twin| self.bindings.get(&twin).copied())
        })
    }

    /// The jog actions a release of `key` ends: bound to `key`, to it without modifiers, and to the
    /// other case of a letter (shift pressed mid-hold turns the release of "w" into "W").
    pub fn release_candidates(&self, key: &KeyName) -> Vec<Action> {
        let bare = key.without_modifiers();
        let mut keys = vec![*key, bare];
        if let BaseKey::Char(c) = bare.base() {
            keys.extend(
                [single_char(c.to_lowercase()), single_char(c.to_uppercase())]
                    .into_iter()
                    .flatten()
                    .map(KeyName::char),
            );
        }
        let mut actions: Vec<Action> = keys
            .iter()
            .filter_map(|k| self.action(k))
            .filter(|a| a.jog().is_some())
            .collect();
        actions.sort();
        actions.dedup();
        actions
    }

    /// The keys bound to an action, unmodified keys first (for the help overlay and hints).
    pub fn keys_for(&self, action: Action) -> Vec<KeyName> {
        self.bindings
            .iter()
            .filter(|(_, bound)| **bound == action)
            .map(|(key, _)| *key)
            .collect()
    }

    /// The key the screen names for `action`: the first of [`Keymap::keys_for`].
    pub fn key_for(&self, action: Action) -> Option<KeyName> {
        self.keys_for(action).first().copied()
    }

    /// Every bound action with its keys, in [`Action::ALL`] order (the help's).
    pub fn entries(&self) -> Vec<(Action, Vec<KeyName>)> {
        Action::ALL
            .into_iter()
            .map(|action| (action, self.keys_for(action)))
            .filter(|(_, keys)| !keys.is_empty())
            .collect()
    }
}

fn builtin_source(name: &str) -> Option<(&'static str, &'static str)> {
    BUILTIN_KEYMAPS
        .iter()
        .find(|(builtin_name, _)| *builtin_name == name)
        .copied()
}

fn builtin_source_name(name: &str) -> String {
    format!("keymaps/{name}.json")
}

/// What is wrong with a keymap.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum KeymapErrorKind {
    /// The file could not be read (or the name is neither a built-in keymap nor a file).
    Unreadable,
    /// Not valid JSON.
    InvalidJson,
    /// Valid JSON of the wrong shape: a value of the wrong type, e.g. a number as an action.
    InvalidValue,
    /// A top-level field other than `name`, `description` and `bindings`.
    UnknownField,
    /// A top-level field given twice.
    DuplicateField,
    /// `name` or `bindings` is missing.
    MissingField,
    /// A binding's key is not a key name.
    UnknownKey,
    /// A binding's value is not an action name.
    UnknownAction,
    /// The same key bound twice (also when spelled differently: `alt+ctrl+x`, `ctrl+alt+x`).
    DuplicateKey,
    /// No key for `stop` or `quit`.
    MissingRequiredAction,
}

/// A line and a column, both counted from 1; the column counts characters.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct TextPosition {
    pub line: usize,
    pub column: usize,
}

/// A refused keymap: `FILE:LINE:COLUMN: reason`, or `FILE: reason` if unreadable.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct KeymapError {
    source_name: String,
    position: Option<TextPosition>,
    kind: KeymapErrorKind,
    message: String,
}

impl KeymapError {
    /// The file (path as given, or `keymaps/NAME.json` for a built-in keymap).
    pub fn source_name(&self) -> &str {
        &self.source_name
    }

    pub fn position(&self) -> Option<TextPosition> {
        self.position
    }

    /// The line, from 1; `None` when the file could not be read.
    pub fn line(&self) -> Option<usize> {
        self.position.map(|position| position.line)
    }

    /// The column in characters, from 1; `None` when the file could not be read.
    pub fn column(&self) -> Option<usize> {
        self.position.map(|position| position.column)
    }

    pub fn kind(&self) -> KeymapErrorKind {
        self.kind
    }

    /// The reason, without file and position.
    pub fn message(&self) -> &str {
        &self.message
    }
}

impl fmt::Display for KeymapError {
    fn fmt(&self, formatter: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.position {
            Some(TextPosition { line, column }) => write!(
                formatter,
                "{}:{line}:{column}: {}",
                self.source_name, self.message
            ),
            None => write!(formatter, "{}: {}", self.source_name, self.message),
        }
    }
}

impl std::error::Error for KeymapError {}

/// The only char of `chars`, if there is exactly one (a case mapping, a key name).
fn single_char(mut chars: impl Iterator<Item = char>) -> Option<char> {
    let first = chars.next()?;
    chars.next().is_none().then_some(first)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(name: &str) -> KeyName {
        match name.parse() {
            Ok(key) => key,
            Err(error) => panic!("{error}"),
        }
    }

    fn keymap(text: &str) -> Keymap {
        match Keymap::from_json("test.json", text) {
            Ok(keymap) => keymap,
            Err(error) => panic!("{error}"),
        }
    }

    #[test]
    fn builtins_load_and_bind_every_action() {
        for name in Keymap::builtin_names() {
            let loaded = match Keymap::load(name) {
                Ok(keymap) => keymap,
                Err(error) => panic!("{error}"),
            };
            assert_eq!(loaded.name(), name);
            let unbound: Vec<Action> = Action::ALL
                .into_iter()
                .filter(|action| loaded.keys_for(*action).is_empty())
                .collect();
            assert_eq!(unbound, Vec::<Action>::new(), "{name}");
            assert_eq!(Keymap::builtin(name), Some(loaded));
        }
        assert_eq!(Keymap::builtin("nonesuch"), None);
        assert!(Keymap::builtin("default").is_some());
    }

    #[test]
    fn keypad_keys_fall_back_to_their_twins_and_explicit_bindings_win() {
        let map = keymap(
            r#"{"name": "t", "bindings": {
                "kp8": "jog_x_plus", "2": "jog_x_minus",
                "kp5": "stop", "5": "quit", "up": "pan_altitude_plus"}}"#,
        );
        assert_eq!(map.action(&key("kp8")), Some(Action::JogXPlus));
        assert_eq!(map.action(&key("8")), Some(Action::JogXPlus));
        assert_eq!(map.action(&key("kp2")), Some(Action::JogXMinus));
        assert_eq!(map.action(&key("kp5")), Some(Action::Stop));
        assert_eq!(map.action(&key("5")), Some(Action::Quit));
        assert_eq!(map.action(&key("kpup")), Some(Action::PanAltitudePlus));
        assert_eq!(map.action(&key("kpbegin")), None);
        assert_eq!(map.action(&key("ctrl+8")), None);
        assert_eq!(map.action(&key("w")), None);
    }

    #[test]
    fn keys_for_and_entries_follow_the_help_order() {
        let map = keymap(
            r#"{"name": "t", "bindings": {
                "q": "quit", "ctrl+c": "quit", "space": "stop", "w": "jog_x_plus"}}"#,
        );
        assert_eq!(map.keys_for(Action::Quit), vec![key("q"), key("ctrl+c")]);
        assert_eq!(map.keys_for(Action::Help), vec![]);
        let actions: Vec<Action> = map.entries().into_iter().map(|(a, _)| a).collect();
        assert_eq!(actions, vec![Action::JogXPlus, Action::Stop, Action::Quit]);
    }

    #[test]
    fn a_name_that_is_not_a_builtin_nor_a_file_says_so() {
        let error = match Keymap::load("nonesuch") {
            Ok(_) => panic!("loaded"),
            Err(error) => error,
        };
        assert_eq!(error.kind(), KeymapErrorKind::Unreadable);
        assert_eq!(error.position(), None);
        let shown = error.to_string();
        assert!(shown.starts_with("nonesuch: no built-in keymap"), "{shown}");
        assert!(shown.contains("default, numpad"), "{shown}");
    }
}
