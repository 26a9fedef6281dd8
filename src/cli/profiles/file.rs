//! Reading `config.toml`'s `[arms.NAME]` tables, keys checked against clap's options, with lines;
//! a profile's `fence` table is read by `super::fence`.

use std::any::TypeId;
use std::ops::Range;
use std::path::{Path, PathBuf};

use clap::{Arg, Args, Command};
use toml::Spanned;
use toml::de::{DeTable, DeValue};

use super::{Profile, ProfileError, Profiles, Setting, fence, first_line};
use crate::cli::console::ConsoleArgs;

/// The largest config file read: a few profiles are a few kB.
pub const CONFIG_LIMIT: u64 = 1024 * 1024;

/// What a key's value must be in TOML.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Integer,
    /// An integer or a float.
    Number,
    Text,
    Switch,
}

impl Kind {
    fn of(arg: &Arg) -> Kind {
        if !arg.get_action().takes_values() {
            return Kind::Switch;
        }
        let id = arg.get_value_parser().type_id();
        let integers = [
            TypeId::of::<u8>(),
            TypeId::of::<u16>(),
            TypeId::of::<u32>(),
            TypeId::of::<u64>(),
            TypeId::of::<usize>(),
            TypeId::of::<i8>(),
            TypeId::of::<i16>(),
            TypeId::of::<i32>(),
            TypeId::of::<i64>(),
        ];
        if integers.iter().any(|t| id == *t) {
            Kind::Integer
        } else if id == TypeId::of::<f64>() || id == TypeId::of::<f32>() {
            Kind::Number
        } else {
            Kind::Text
        }
    }

    fn expected(self) -> &'static str {
        match self {
            Kind::Integer => "an integer",
            Kind::Number => "a number",
            Kind::Text => "a string",
            Kind::Switch => "true or false",
        }
    }
}

/// The console's options as a profile names them: long names with `-` written `_`.
pub fn console_options() -> Command {
    ConsoleArgs::augment_args(Command::new("armjog"))
}

/// The profile key of an option: its long name with `_` for `-`.
pub fn key_of(arg: &Arg) -> Option<String> {
    arg.get_long().map(|long| long.replace('-', "_"))
}

/// The key of a profile's fence table (`[arms.NAME.fence]`), which is no option.
pub const FENCE_KEY: &str = "fence";

/// Every key a profile may hold: the options in the order `--help` lists them, then `fence`.
pub fn known_keys() -> Vec<String> {
    console_options()
        .get_arguments()
        .filter_map(key_of)
        .chain([FENCE_KEY.to_string()])
        .collect()
}

/// Reads and checks the file at `path`.
pub fn load(path: &Path) -> Result<Profiles, ProfileError> {
    let text = crate::files::read_to_string_bounded(path, CONFIG_LIMIT).map_err(|e| {
        let path = path.to_path_buf();
        match e.kind() {
            std::io::ErrorKind::NotFound => ProfileError::NoFile { path },
            _ => ProfileError::Unreadable {
                path,
                reason: e.to_string(),
            },
        }
    })?;
    parse(path, &text)
}

/// Checks `text`, the contents of the file at `path` (named in every error).
pub fn parse(path: &Path, text: &str) -> Result<Profiles, ProfileError> {
    let at = Locator {
        path: path.to_path_buf(),
        text,
    };
    let document = DeTable::parse(text).map_err(|e| {
        let line = e.span().map_or(1, |span| at.line(&span));
        at.error(line, format!("not valid TOML: {}", one_line(e.message())))
    })?;
    let mut arms = Vec::new();
    for (key, value) in document.get_ref() {
        if key.get_ref() != "arms" {
            return Err(at.unknown_key(key, &["arms".to_string()]));
        }
        let DeValue::Table(table) = value.get_ref() else {
            return Err(at.wrong_type(value, "arms", "a table of [arms.NAME]"));
        };
        for (name, profile) in table {
            arms.push(read_profile(&at, name, profile)?);
        }
    }
    // In the file's order (the parser's map is sorted by name).
    arms.sort_by_key(|p| p.line);
    Ok(Profiles {
        file: path.to_path_buf(),
        arms,
    })
}

fn read_profile(
    at: &Locator,
    name: &Spanned<std::borrow::Cow<'_, str>>,
    value: &Spanned<DeValue<'_>>,
) -> Result<Profile, ProfileError> {
    let arm = format!("arms.{}", name.get_ref());
    let DeValue::Table(table) = value.get_ref() else {
        return Err(at.wrong_type(value, &arm, "a table of options"));
    };
    let options = console_options();
    let keys = known_keys();
    let mut settings = Vec::new();
    let mut fence = None;
    for (key, value) in table {
        if key.get_ref() == FENCE_KEY {
            fence = Some(fence::read(at, &arm, key, value)?);
            continue;
        }
        let Some(arg) = options
            .get_arguments()
            .find(|arg| key_of(arg).as_deref() == Some(key.get_ref().as_ref()))
        else {
            return Err(at.unknown_key(key, &keys));
        };
        let kind = Kind::of(arg);
        let line = at.line(&key.span());
        let Some(text) = argument_text(value.get_ref(), kind) else {
            return Err(at.wrong_type(value, key.get_ref(), kind.expected()));
        };
        check_value(arg, key.get_ref(), &text).map_err(|why| at.error(line, why))?;
        settings.push(Setting {
            key: key.get_ref().to_string(),
            value: text,
            line,
        });
    }
    Ok(Profile {
        name: name.get_ref().to_string(),
        line: at.line(&name.span()),
        settings,
        fence,
    })
}

/// The value as the command line would give it, if it has the kind the option takes.
fn argument_text(value: &DeValue<'_>, kind: Kind) -> Option<String> {
    match (value, kind) {
        (DeValue::String(s), Kind::Text) => Some(s.to_string()),
        (DeValue::Integer(i), Kind::Integer | Kind::Number) => {
            // Out of range for i128 is out of range for every option too: the check says so.
            i128::from_str_radix(i.as_str(), i.radix())
                .map(|i| i.to_string())
                .ok()
                .or_else(|| Some(format!("{i}")))
        }
        (DeValue::Float(f), Kind::Number) => Some(f.as_str().to_string()),
        (DeValue::Boolean(b), Kind::Switch) => Some(b.to_string()),
        _ => None,
    }
}

/// Runs the option's own parser on `text`; errors read `KEY = VALUE: why`.
fn check_value(arg: &Arg, key: &str, text: &str) -> Result<(), String> {
    let possible: Vec<String> = arg
        .get_possible_values()
        .iter()
        .map(|p| p.get_name().to_string())
        .collect();
    if !possible.is_empty() && !possible.iter().any(|p| p == text) {
        let mut why = format!("{key}: '{text}' is not one of {}", possible.join(", "));
        if let Some(near) = nearest(text, &possible) {
            why.push_str(&format!("; did you mean '{near}'?"));
        }
        return Err(why);
    }
    if Kind::of(arg) == Kind::Switch {
        return Ok(());
    }
    let Some(long) = arg.get_long() else {
        return Ok(());
    };
    let args = ["armjog".to_string(), format!("--{long}={text}")];
    let Err(e) = console_options().try_get_matches_from(args) else {
        return Ok(());
    };
    // The parser's own words (`must be above 0 ...`); clap's first line otherwise.
    let why = std::error::Error::source(&e).map_or_else(|| first_line(&e), |s| s.to_string());
    Err(format!("{key} = {text}: {why}"))
}

/// The candidate near enough to `typed` to be meant: an edit per three characters, at least one.
pub fn nearest<'a>(typed: &str, candidates: &'a [String]) -> Option<&'a str> {
    let allowed = (typed.chars().count() / 3).max(1);
    candidates
        .iter()
        .map(|c| (strsim::damerau_levenshtein(typed, c), c))
        .filter(|(distance, _)| *distance <= allowed)
        .min_by_key(|(distance, _)| *distance)
        .map(|(_, c)| c.as_str())
}

/// A TOML message on one line: the parser's may span several.
fn one_line(message: &str) -> String {
    message.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// Names places in the file.
pub(super) struct Locator<'a> {
    path: PathBuf,
    text: &'a str,
}

impl Locator<'_> {
    /// The 1-based line of a byte span's start: the pieces before it, split at newlines.
    pub(super) fn line(&self, span: &Range<usize>) -> usize {
        let start = span.start.min(self.text.len());
        self.text.as_bytes()[..start].split(|b| *b == b'\n').count()
    }

    pub(super) fn error(&self, line: usize, message: String) -> ProfileError {
        ProfileError::Invalid {
            path: self.path.clone(),
            line,
            message,
        }
    }

    pub(super) fn unknown_key(
        &self,
        key: &Spanned<std::borrow::Cow<'_, str>>,
        known: &[String],
    ) -> ProfileError {
        let typed = key.get_ref();
        let mut message = format!("unknown key '{typed}'");
        match nearest(typed, known) {
            Some(near) => message.push_str(&format!("; did you mean '{near}'?")),
            None => message.push_str(&format!(" (known: {})", known.join(", "))),
        }
        self.error(self.line(&key.span()), message)
    }

    pub(super) fn wrong_type(
        &self,
        value: &Spanned<DeValue<'_>>,
        key: &str,
        expected: &str,
    ) -> ProfileError {
        self.error(
            self.line(&value.span()),
            format!(
                "{key}: expected {expected}, found {}",
                found(value.get_ref())
            ),
        )
    }
}

/// What a value is, as an error names it (`an integer`).
pub(super) fn found(value: &DeValue<'_>) -> &'static str {
    match value {
        DeValue::String(_) => "a string",
        DeValue::Integer(_) => "an integer",
        DeValue::Float(_) => "a float",
        DeValue::Boolean(_) => "a boolean",
        DeValue::Datetime(_) => "a date",
        DeValue::Array(_) => "an array",
        DeValue::Table(_) => "a table",
    }
}
