//! A hand-edited book with bad entries: the rest loads, the bad ones are named, the bytes kept.

use super::*;

fn book_file(json: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("book.json");
    std::fs::write(&path, json).expect("written");
    (dir, path)
}

const HAND_EDITED: &str = r#"{
  "format": 1,
  "positions": {
    "bench": {"cartesian": [4000, 0, 3000]},
    "gone": null,
    "pick": {"cartesian": [1, 2, 3], "frame": "tool"},
    "place": {"cartesian": [5, 6, 7]},
    "typo": {"anchr": true}
  },
  "tours": [
    {"name": "rounds", "positions": ["bench", "place"]},
    {"name": "broken", "positions": "bench"},
    42
  ],
  "colour": "blue"
}
"#;

#[test]
fn the_good_entries_load_and_each_bad_one_is_named_with_its_reason() {
    let (dir, path) = book_file(HAND_EDITED);
    let mut book = PositionBook::load(&path).expect("the good entries load");
    let names: Vec<&str> = book.names().collect();
    assert_eq!(names, ["bench", "place"]);
    let tours: Vec<&str> = book.tours().iter().map(|t| t.name.as_str()).collect();
    assert_eq!(tours, ["rounds"]);
    let notes = book.take_load_notes();
    let first = &notes[0];
    let copy = dir.path().join("book.json.bad");
    for named in [
        "6 bad entries set aside",
        "position 'gone'",
        "position 'pick'",
        "position 'typo'",
        "tour 'broken'",
        "tour 3",
        "and 1 more",
        &format!("kept in {}", copy.display()),
    ] {
        assert!(first.contains(named), "{named} in {first}");
    }
    let all = notes.join("\n");
    for reason in ["tool", "anchr", "null", "key \"colour\""] {
        assert!(all.contains(reason), "{reason} in {all}");
    }
    assert_eq!(notes.len(), 7, "{notes:#?}");
    // The file's bytes are kept as they were; the book itself is untouched by loading.
    assert_eq!(std::fs::read_to_string(&copy).expect("copy"), HAND_EDITED);
    assert_eq!(std::fs::read_to_string(&path).expect("book"), HAND_EDITED);
}

#[test]
fn an_older_bad_copy_is_never_written_over_and_the_same_bytes_are_kept_once() {
    let (dir, path) = book_file(HAND_EDITED);
    let older = dir.path().join("book.json.bad");
    std::fs::write(&older, "an older hand edit").expect("older copy");
    PositionBook::load(&path).expect("loads");
    assert_eq!(
        std::fs::read_to_string(&older).expect("older"),
        "an older hand edit"
    );
    let second = dir.path().join("book.json.bad.2");
    assert_eq!(std::fs::read_to_string(&second).expect("copy"), HAND_EDITED);
    // Loading the same file again keeps no third copy.
    PositionBook::load(&path).expect("loads");
    assert!(!dir.path().join("book.json.bad.3").exists());
    assert_eq!(
        keep_bad_copy(&path, HAND_EDITED.as_bytes()).ok(),
        Some(second)
    );
}

#[test]
fn a_copy_that_cannot_be_kept_is_said_and_the_rest_still_loads() {
    let (dir, path) = book_file(HAND_EDITED);
    // A directory where the copies would go: none can be created.
    for n in 1..=MAX_BAD_COPIES {
        let name = if n == 1 {
            "book.json.bad".to_string()
        } else {
            format!("book.json.bad.{n}")
        };
        std::fs::create_dir(dir.path().join(name)).expect("in the way");
    }
    let mut book = PositionBook::load(&path).expect("loads");
    assert_eq!(book.len(), 2);
    let notes = book.take_load_notes();
    assert!(
        notes[0].contains("no copy of the file could be kept"),
        "{}",
        notes[0]
    );
}

#[test]
fn a_file_that_is_not_a_book_is_still_refused_whole() {
    for text in [
        "{ not json",
        "[1, 2]",
        r#"{"positions": {}}"#,
        r#"{"format": 1, "positions": []}"#,
    ] {
        assert!(parse(text).is_none(), "{text}");
        let (_dir, path) = book_file(text);
        let error = PositionBook::load(&path).expect_err(text).to_string();
        assert!(error.starts_with(&path.display().to_string()), "{error}");
    }
}

#[test]
fn a_newer_format_is_refused_even_with_bad_entries() {
    let (_dir, path) = book_file(r#"{"format": 9, "positions": {"a": null}}"#);
    let error = PositionBook::load(&path).expect_err("refused").to_string();
    assert!(error.contains("format 9 is newer"), "{error}");
}
