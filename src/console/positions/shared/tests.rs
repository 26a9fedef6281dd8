//! Writes that share a file: what another writer put there since we read it survives.

use super::*;
use crate::console::positions::{BookEntry, Tour};

fn at(x: i32) -> BookEntry {
    BookEntry {
        cartesian: Some([x, 0, 0]),
        ..BookEntry::default()
    }
}

fn with(book: &PositionBook, name: &str, x: i32) -> PositionBook {
    let mut book = book.clone();
    *book.get_or_insert(name) = at(x);
    book
}

fn names(book: &PositionBook) -> Vec<String> {
    book.names().map(String::from).collect()
}

#[test]
fn two_writers_from_one_read_both_keep_their_positions() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("book.json");
    let read = with(&PositionBook::new(), "home", 0);
    read.save(&path).expect("first book");
    // Both consoles read the file; console 1 saves X1, then console 2 saves X3.
    let one = with(&read, "x1", 1);
    let written = one
        .save_shared(&read, &BTreeSet::new(), &path)
        .expect("console 1 writes");
    assert_eq!(written.taken, 0);
    let three = with(&read, "x3", 3);
    let written = three
        .save_shared(&read, &BTreeSet::new(), &path)
        .expect("console 2 writes");
    assert_eq!(written.taken, 1, "x1 came from the other console");
    assert!(written.found_others());
    assert_eq!(names(&written.book), ["home", "x1", "x3"]);
    let on_disk = PositionBook::load(&path).expect("reads");
    assert_eq!(names(&on_disk), ["home", "x1", "x3"]);
    assert!(
        lock_path(&path).exists(),
        "the lock file stays for the next writer"
    );
}

#[test]
fn a_tour_added_by_hand_while_a_console_runs_survives_its_next_save() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("book.json");
    let read = with(&PositionBook::new(), "bench", 1);
    read.save(&path).expect("book");
    let mut by_hand = read.clone();
    by_hand.set_tour(Tour {
        name: "rounds".into(),
        positions: vec!["bench".into()],
    });
    by_hand.save(&path).expect("hand edit");
    let ours = with(&read, "pick", 2);
    let written = ours
        .save_shared(&read, &BTreeSet::new(), &path)
        .expect("written");
    assert!(written.book.tour("rounds").is_some());
    let on_disk = PositionBook::load(&path).expect("reads");
    assert!(
        on_disk.tour("rounds").is_some(),
        "the hand-made tour is kept"
    );
    assert_eq!(names(&on_disk), ["bench", "pick"]);
}

#[test]
fn a_file_with_bad_entries_is_written_over_only_with_its_bytes_kept() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("book.json");
    let text = r#"{"format": 1, "positions": {"bench": {}, "pick": null}}"#;
    std::fs::write(&path, text).expect("book");
    let read = PositionBook::load(&path).expect("loads");
    let copy = dir.path().join("book.json.bad");
    std::fs::remove_file(&copy).expect("the load kept a copy");
    // The copy is gone (moved away) when the console saves: the save keeps one again first.
    let ours = with(&read, "place", 3);
    let written = ours
        .save_shared(&read, &BTreeSet::new(), &path)
        .expect("written");
    assert_eq!(std::fs::read_to_string(&copy).expect("copy"), text);
    assert_eq!(written.set_aside.len(), 1);
    assert!(
        written.notes[0].contains("position 'pick'"),
        "{:?}",
        written.notes
    );
    assert!(written.found_others());
    assert_eq!(
        names(&PositionBook::load(&path).expect("reads")),
        ["bench", "place"]
    );
}

#[test]
fn a_file_that_no_longer_reads_as_a_book_is_not_written_over() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("book.json");
    std::fs::write(&path, "{ half an edit").expect("book");
    let ours = with(&PositionBook::new(), "pick", 1);
    let error = ours
        .save_shared(&PositionBook::new(), &BTreeSet::new(), &path)
        .expect_err("refused")
        .to_string();
    assert!(error.starts_with(&path.display().to_string()), "{error}");
    assert!(error.contains("not written over"), "{error}");
    assert_eq!(
        std::fs::read_to_string(&path).expect("book"),
        "{ half an edit"
    );
}

#[test]
fn a_write_waits_for_another_writers_lock() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("book.json");
    let other = std::fs::File::create(lock_path(&path)).expect("lock file");
    other.lock().expect("the other writer's lock");
    let ours = with(&PositionBook::new(), "pick", 1);
    let writer = {
        let path = path.clone();
        std::thread::spawn(move || ours.save_shared(&PositionBook::new(), &BTreeSet::new(), &path))
    };
    std::thread::sleep(Duration::from_millis(300));
    assert!(!path.exists(), "nothing written while the lock is held");
    other.unlock().expect("unlocked");
    let written = writer.join().expect("writer").expect("written");
    assert_eq!(names(&written.book), ["pick"]);
    assert!(path.exists());
}
