//! One bad entry never costs the rest of a book: a file the strict reader refuses is read entry by
//! entry; good entries load, each bad one is set aside with its reason, and the file's bytes are
//! kept in a `.bad` copy, so the next save loses nothing of the hand edit. A file that is not a
//! book at all is refused whole.

use std::path::{Path, PathBuf};

use serde_json::Value;

use super::{BookEntry, Named, PositionBook, Tour};
use crate::text;

/// A part of the file that did not load: what it was and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SetAside {
    /// `position 'pick'`, `tour 'rounds'`, `tour 3`, `key "colour"`.
    pub what: String,
    pub why: String,
}

/// How many `.bad` copies of one book are kept beside it before a save refuses to add one.
const MAX_BAD_COPIES: usize = 100;

/// The book in `text`, entry by entry; `None` when it is not a book at all.
pub(super) fn parse(text: &str) -> Option<(PositionBook, Vec<SetAside>)> {
    let Ok(Value::Object(top)) = serde_json::from_str::<Value>(text) else {
        return None;
    };
    let format = top.get("format").and_then(Value::as_u64)?;
    let Some(Value::Object(positions)) = top.get("positions") else {
        return None;
    };
    let mut book = PositionBook::new();
    book.format = u32::try_from(format).unwrap_or(u32::MAX);
    let mut aside = Vec::new();
    let mut list: Vec<Named> = Vec::with_capacity(positions.len());
    for (name, value) in positions {
        match serde_json::from_value::<BookEntry>(value.clone()) {
            Ok(entry) => list.push((name.clone(), entry)),
            Err(e) => aside.push(SetAside {
                what: format!("position '{}'", text::logged(name)),
                why: text::logged(&e.to_string()).to_string(),
            }),
        }
    }
    list.sort_by(|a, b| a.0.cmp(&b.0));
    book.positions = std::sync::Arc::new(list);
    match top.get("tours") {
        None => {}
        Some(Value::Array(tours)) => {
            for (i, value) in tours.iter().enumerate() {
                match serde_json::from_value::<Tour>(value.clone()) {
                    Ok(tour) => book.tours.push(tour),
                    Err(e) => aside.push(SetAside {
                        what: match value.get("name").and_then(Value::as_str) {
                            Some(name) => format!("tour '{}'", text::logged(name)),
                            None => format!("tour {}", i + 1),
                        },
                        why: text::logged(&e.to_string()).to_string(),
                    }),
                }
            }
        }
        Some(_) => aside.push(SetAside {
            what: "the tours".into(),
            why: "not a list of tours".into(),
        }),
    }
    for key in top.keys() {
        if !["format", "positions", "tours"].contains(&key.as_str()) {
            aside.push(SetAside {
                what: format!("key \"{}\"", text::logged(key)),
                why: "not part of a positions file".into(),
            });
        }
    }
    Some((book, aside))
}

/// A load's notes on what it set aside: the first names them all, then one per entry.
pub(super) fn notes(aside: &[SetAside], copy: &std::io::Result<PathBuf>) -> Vec<String> {
    if aside.is_empty() {
        return Vec::new();
    }
    const NAMED: usize = 5;
    let mut named: Vec<&str> = aside.iter().take(NAMED).map(|a| a.what.as_str()).collect();
    let more = aside.len().saturating_sub(NAMED);
    let more = (more > 0).then(|| format!("and {more} more"));
    named.extend(more.as_deref());
    let kept = match copy {
        Ok(copy) => format!("the file as it was is kept in {}", copy.display()),
        Err(e) => {
            format!("no copy of the file could be kept ({e}): it is not written over until one is")
        }
    };
    let mut notes = vec![format!(
        "{} bad entr{} set aside ({}); {kept}",
        aside.len(),
        if aside.len() == 1 { "y" } else { "ies" },
        named.join(", ")
    )];
    notes.extend(
        aside
            .iter()
            .map(|a| format!("{} set aside: {}", a.what, a.why)),
    );
    notes
}

/// Keeps `bytes` in a copy beside the book (`book.json.bad`, `.bad.2`, ... never written over; a
/// copy holding these bytes is reused). Returns its path.
pub fn keep_bad_copy(path: &Path, bytes: &[u8]) -> std::io::Result<PathBuf> {
    let mut base = path.as_os_str().to_owned();
    base.push(".bad");
    for n in 1..=MAX_BAD_COPIES {
        let mut name = base.clone();
        if n > 1 {
            name.push(format!(".{n}"));
        }
        let copy = PathBuf::from(name);
        match std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&copy)
        {
            Ok(mut file) => {
                use std::io::Write;
                let written = file.write_all(bytes).and_then(|()| file.sync_all());
                if let Err(e) = written {
                    let _ = std::fs::remove_file(&copy);
                    return Err(e);
                }
                return Ok(copy);
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                let limit = crate::files::POSITIONS_LIMIT;
                let same = std::fs::metadata(&copy).is_ok_and(|m| m.len() == bytes.len() as u64)
                    && crate::files::read_bytes_bounded(&copy, limit).is_ok_and(|b| b == bytes);
                if same {
                    return Ok(copy);
                }
            }
            Err(e) => return Err(e),
        }
    }
    Err(std::io::Error::other(format!(
        "{MAX_BAD_COPIES} copies {}.bad… exist already: move some away",
        path.display()
    )))
}

#[cfg(test)]
mod tests;
