//! Names read from a file pass the rule a typed name passes (`PositionName`): a bad one (empty,
//! NUL, bidi override, huge) is repaired ([`crate::text::name_repair`], made unique), a parent
//! naming it follows, and a note says what was wrong.

use std::collections::{BTreeMap, BTreeSet};

use super::{Named, PositionBook};
use crate::talos::PositionName;
use crate::talos::name::MAX_NAME_LEN;
use crate::text;

impl PositionBook {
    /// Repairs the names that break the rule, noting each in `load_notes`.
    pub(super) fn repair_names(&mut self) {
        let breaks = |name: &str| PositionName::validate(name.as_bytes()).is_err();
        let bad_names = self.positions.iter().any(|(name, _)| breaks(name));
        let bad_parents = self
            .positions
            .iter()
            .any(|(_, entry)| entry.parent.as_deref().is_some_and(breaks));
        if !bad_names && !bad_parents {
            return;
        }
        let list = std::sync::Arc::make_mut(&mut self.positions);
        let mut taken: BTreeSet<String> = list
            .iter()
            .filter(|(name, _)| !breaks(name))
            .map(|(name, _)| name.clone())
            .collect();
        let mut renamed: BTreeMap<String, String> = BTreeMap::new();
        for (name, _) in list.iter_mut() {
            let Err(why) = PositionName::validate(name.as_bytes()) else {
                continue;
            };
            let base = text::name_repair(name).unwrap_or_else(|| "unnamed".to_string());
            let repaired = unique(&base, &taken);
            self.load_notes.push(format!(
                "position name '{}' {why}: loaded as '{repaired}'",
                text::logged(name)
            ));
            taken.insert(repaired.clone());
            renamed.insert(std::mem::replace(name, repaired.clone()), repaired);
        }
        for (name, entry) in list.iter_mut() {
            let Some(parent) = entry.parent.as_mut() else {
                continue;
            };
            if let Some(repaired) = renamed.get(parent.as_str()) {
                *parent = repaired.clone();
            } else if let Err(why) = PositionName::validate(parent.as_bytes()) {
                let repaired = text::name_repair(parent).unwrap_or_else(|| "unnamed".into());
                self.load_notes.push(format!(
                    "parent '{}' of '{name}' {why}: loaded as '{repaired}'",
                    text::logged(parent)
                ));
                *parent = repaired;
            }
        }
        list.sort_by(|a: &Named, b: &Named| a.0.cmp(&b.0));
    }

    /// What loading repaired, one line each (empty for a book that kept the rule); taken once.
    pub fn take_load_notes(&mut self) -> Vec<String> {
        std::mem::take(&mut self.load_notes)
    }
}

/// `base`, or `base~2`, `base~3`… (cut to fit the length limit), whichever no other name has.
pub(super) fn unique(base: &str, taken: &BTreeSet<String>) -> String {
    if !taken.contains(base) {
        return base.to_string();
    }
    (2..)
        .map(|n| {
            let suffix = format!("~{n}");
            // `base` is ASCII: any byte index is a character boundary.
            let keep = base.len().min(MAX_NAME_LEN - suffix.len());
            format!("{}{suffix}", &base[..keep])
        })
        .find(|candidate| !taken.contains(candidate))
        .unwrap_or_else(|| base.to_string())
}

/// Whether `copy` is a name [`unique`] gives a copy of `base`: `base~N` (`base` cut to fit).
pub(super) fn is_copy_of(copy: &str, base: &str) -> bool {
    let Some((kept, n)) = copy.rsplit_once('~') else {
        return false;
    };
    let numbered = !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()) && n != "0" && n != "1";
    let whole = kept == base || (copy.len() == MAX_NAME_LEN && base.starts_with(kept));
    numbered && whole
}

#[cfg(test)]
mod tests {
    use super::*;

    fn book_file(json: &str) -> (tempfile::TempDir, std::path::PathBuf) {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("book.json");
        std::fs::write(&path, json).expect("written");
        (dir, path)
    }

    #[test]
    fn hostile_names_are_repaired_with_a_note_each_and_the_rest_loads() {
        let megabyte = "m".repeat(1 << 20);
        let marks = format!("a{}", "\u{301}".repeat(100_000));
        let json = serde_json::json!({
            "format": 1,
            "positions": {
                "": {"cartesian": [1, 0, 0]},
                "nul\u{0}here": {"cartesian": [2, 0, 0]},
                "evil\u{202E}gpj": {"cartesian": [3, 0, 0]},
                megabyte.clone(): {"cartesian": [4, 0, 0]},
                marks.clone(): {"cartesian": [5, 0, 0]},
                "pick": {"cartesian": [6, 0, 0], "anchor": true, "parent": "evil\u{202E}gpj"},
                "unnamed": {"cartesian": [7, 0, 0]},
            }
        });
        let (_dir, path) = book_file(&json.to_string());
        let mut book = PositionBook::load(&path).expect("loads");
        let notes = book.take_load_notes();
        assert_eq!(notes.len(), 5, "{notes:#?}");
        assert!(book.take_load_notes().is_empty(), "taken once");
        let names: Vec<&str> = book.names().collect();
        for name in &names {
            assert!(PositionName::validate(name.as_bytes()).is_ok(), "{name:?}");
        }
        assert_eq!(book.len(), 7, "nothing lost: {names:?}");
        // The good names are untouched; the empty one does not take the existing "unnamed".
        assert_eq!(book.get("pick").and_then(|e| e.cartesian), Some([6, 0, 0]));
        assert_eq!(
            book.get("unnamed").and_then(|e| e.cartesian),
            Some([7, 0, 0])
        );
        assert_eq!(
            book.get("unnamed~2").and_then(|e| e.cartesian),
            Some([1, 0, 0])
        );
        assert_eq!(
            book.get("nul\\0here").and_then(|e| e.cartesian),
            Some([2, 0, 0])
        );
        assert_eq!(
            book.get("evil\\u{202e}gpj").and_then(|e| e.cartesian),
            Some([3, 0, 0])
        );
        assert_eq!(
            book.get("pick").and_then(|e| e.parent.as_deref()),
            Some("evil\\u{202e}gpj"),
            "the parent follows its repaired name"
        );
        assert_eq!(
            book.get(&"m".repeat(255)).and_then(|e| e.cartesian),
            Some([4, 0, 0])
        );
        // Each note says what was wrong, escaped and capped: one line, never the megabyte.
        let all = notes.join("\n");
        assert!(all.contains("is empty"), "{all}");
        assert!(all.contains("has byte 0x00 at offset 3"), "{all}");
        assert!(all.contains("has byte 0xE2 at offset 4"), "{all}");
        assert!(all.contains("is 1048576 bytes long"), "{all}");
        assert!(all.contains("is 200001 bytes long"), "{all}");
        for note in &notes {
            assert!(note.len() < 2_000, "capped: {} bytes", note.len());
            assert!(!note.contains(['\0', '\u{202E}', '\n']), "{note:?}");
        }
        // The book is in name order still: every name is found.
        for name in book.names() {
            assert!(book.get(name).is_some(), "{name}");
        }
    }

    #[test]
    fn a_book_keeping_the_rule_loads_without_notes() {
        let (_dir, path) = book_file(r#"{"format":1,"positions":{"pick":{},"place":{}}}"#);
        let mut book = PositionBook::load(&path).expect("loads");
        assert!(book.take_load_notes().is_empty());
        assert_eq!(book.names().collect::<Vec<_>>(), ["pick", "place"]);
    }

    #[test]
    fn unique_names_stay_within_the_limit() {
        let taken: BTreeSet<String> = ["a".repeat(255), format!("{}~2", "a".repeat(253))]
            .into_iter()
            .collect();
        let name = unique(&"a".repeat(255), &taken);
        assert_eq!(name, format!("{}~3", "a".repeat(253)));
        assert!(name.len() <= MAX_NAME_LEN);
    }

    #[test]
    fn a_copys_name_is_known_as_a_copy_of_its_base() {
        let none = BTreeSet::new();
        let taken: BTreeSet<String> = ["pick".to_string()].into();
        assert!(is_copy_of(&unique("pick", &taken), "pick"));
        let long = "a".repeat(255);
        let taken: BTreeSet<String> = [long.clone()].into();
        assert!(is_copy_of(&unique(&long, &taken), &long), "cut to fit");
        for (copy, base) in [("pick", "pick"), ("pickle~2", "pick"), ("pick~", "pick")] {
            assert!(!is_copy_of(copy, base), "{copy} of {base}");
        }
        assert!(!is_copy_of("pick~1", "pick") && !is_copy_of("pi~2", "pick"));
        assert_eq!(unique("pick", &none), "pick");
    }
}
