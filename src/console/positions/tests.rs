//! Unit tests of the position book and its file.

use std::path::Path;

use super::*;

fn dir() -> tempfile::TempDir {
    tempfile::tempdir().unwrap()
}

#[test]
#[cfg(unix)]
fn a_save_keeps_the_books_permissions_and_a_new_book_is_not_private() {
    use std::os::unix::fs::{OpenOptionsExt, PermissionsExt};
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("book.json");
    let mut book = PositionBook::default();
    book.get_or_insert("pick");
    book.save(&path).expect("saved");
    let mode = |p: &Path| std::fs::metadata(p).expect("metadata").permissions().mode() & 0o777;
    // What any new 0644 file gets under this process's umask.
    let probe = dir.path().join("probe");
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .mode(0o644)
        .open(&probe)
        .expect("probe file");
    assert_eq!(mode(&path), mode(&probe), "a new book follows the umask");
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o640)).expect("chmod");
    book.save(&path).expect("saved again");
    assert_eq!(mode(&path), 0o640, "the book keeps its permissions");
}

#[test]
fn saves_and_loads_and_leaves_no_temporary_file() {
    let d = dir();
    let path = d.path().join("book.json");
    let mut book = PositionBook::new();
    let e = book.get_or_insert("pick");
    e.cartesian = Some([4566, 10, 4338]);
    e.anchor = true;
    e.parent = Some("table".into());
    book.get_or_insert("table");
    book.save(&path).unwrap();
    assert_eq!(PositionBook::load(&path).unwrap(), book);
    let files: Vec<_> = std::fs::read_dir(d.path()).unwrap().collect();
    assert_eq!(files.len(), 1, "only the book itself");
}

#[test]
fn a_save_that_cannot_rename_leaves_no_temporary_file_and_names_the_book() {
    let d = dir();
    // A non-empty directory where the book should go: the final rename fails.
    let path = d.path().join("book.json");
    std::fs::create_dir_all(path.join("in-the-way")).unwrap();
    let mut book = PositionBook::new();
    book.get_or_insert("pick");
    let err = book.save(&path).unwrap_err().to_string();
    assert!(err.starts_with(&path.display().to_string()), "{err}");
    let names: Vec<_> = std::fs::read_dir(d.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, ["book.json"], "the temporary file is removed");
    assert!(
        path.join("in-the-way").is_dir(),
        "what was there is untouched"
    );
}

#[test]
fn saving_over_an_old_book_replaces_it_whole() {
    let d = dir();
    let path = d.path().join("nested").join("book.json");
    let mut old = PositionBook::new();
    for i in 0..50 {
        old.get_or_insert(&format!("p{i:02}"));
    }
    old.save(&path).unwrap();
    let mut new = PositionBook::new();
    new.get_or_insert("only");
    new.save(&path).unwrap();
    assert_eq!(PositionBook::load(&path).unwrap(), new);
}

#[test]
fn a_book_too_big_to_indent_is_written_compact_and_one_too_big_for_that_is_refused() {
    let mut book = PositionBook::new();
    for i in 0..100 {
        book.get_or_insert(&format!("p{i:03}")).cartesian = Some([i, 0, 0]);
    }
    let text = |limit: u64| {
        let mut out = Vec::new();
        book.write_to(&mut out, "b.json", limit).map(|()| out)
    };
    let pretty = text(u64::MAX).unwrap();
    assert_eq!(
        pretty,
        format!("{}\n", serde_json::to_string_pretty(&book).unwrap()).into_bytes()
    );
    let compact = format!("{}\n", serde_json::to_string(&book).unwrap()).into_bytes();
    assert!(
        pretty.len() > compact.len() + 100,
        "the test needs a difference"
    );
    let limit = compact.len() as u64;
    assert_eq!(text(limit).unwrap(), compact);
    let parsed: PositionBook = serde_json::from_slice(&compact).unwrap();
    assert_eq!(parsed, book);
    let err = text(limit - 1).unwrap_err().to_string();
    assert!(err.starts_with("b.json: not written"), "{err}");
    assert!(err.contains(&format!("takes {limit} bytes")), "{err}");
}

#[test]
fn names_stay_in_order_through_changes_and_are_found_by_index_and_by_name() {
    let mut book = PositionBook::new();
    for name in ["pick", "bench", "table", "home"] {
        book.get_or_insert(name);
    }
    book.get_or_insert("pick").anchor = true;
    assert_eq!(book.remove("table").map(|e| e.anchor), Some(false));
    assert_eq!(book.remove("table"), None);
    let names: Vec<&str> = book.names().collect();
    assert_eq!(names, ["bench", "home", "pick"]);
    assert_eq!(book.name_at(2), Some("pick"));
    assert_eq!(book.name_at(3), None);
    assert_eq!(book.index_of("home"), Some(1));
    assert_eq!(book.index_of("nope"), None);
    assert!(book.get("pick").is_some_and(|e| e.anchor));
    let tail: Vec<&str> = book.entries_from(1).map(|(n, _)| n).collect();
    assert_eq!(tail, ["home", "pick"]);
    assert_eq!(book.entries_from(9).count(), 0);
    let window: Vec<String> = book.window(1, 1).names().map(String::from).collect();
    assert_eq!(window, ["home"]);
    // A file in any order, a name given twice: sorted, the last one kept.
    let parsed: PositionBook = serde_json::from_str(
        r#"{"format":1,"positions":{"b":{},"a":{"anchor":true},"b":{"anchor":true}}}"#,
    )
    .unwrap();
    let names: Vec<&str> = parsed.names().collect();
    assert_eq!(names, ["a", "b"]);
    assert!(parsed.get("b").is_some_and(|e| e.anchor));
}

#[test]
fn looking_a_name_up_adds_nothing() {
    let mut book = PositionBook::new();
    book.get_or_insert("bench");
    book.get_or_insert("table");
    assert!(book.get_mut("apple").is_none());
    assert!(book.get_mut("zebra").is_none());
    let names: Vec<&str> = book.names().collect();
    assert_eq!(names, ["bench", "table"]);
    if let Some(bench) = book.get_mut("bench") {
        bench.anchor = true;
    }
    assert!(book.get("bench").is_some_and(|e| e.anchor));
    assert_eq!(book.len(), 2);
}

#[test]
fn a_missing_file_is_an_empty_book() {
    let book = PositionBook::load(&dir().path().join("none.json")).unwrap();
    assert!(book.is_empty());
}

#[test]
fn a_file_that_is_not_json_is_refused_with_its_name_line_and_column() {
    // A misspelt field only sets its entry aside (see `lenient`); broken JSON refuses the file.
    let d = dir();
    let path = d.path().join("bad.json");
    std::fs::write(
        &path,
        "{\n  \"format\": 1,\n  \"positions\": {\n    \"a\": { \"anchor\" true }\n  }\n}\n",
    )
    .unwrap();
    let err = PositionBook::load(&path).unwrap_err().to_string();
    assert!(err.starts_with(&format!("{}:4:", path.display())), "{err}");
    assert!(err.contains("expected `:`"), "{err}");
}

#[test]
fn target_names_become_safe_file_names() {
    let p = default_path("talos 10.0.0.2:61616").unwrap();
    assert!(
        p.ends_with("positions/talos_10.0.0.2_61616.json"),
        "{}",
        p.display()
    );
}
