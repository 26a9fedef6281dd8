//! Two consoles on one book file, each with its own writer (the runtime's `BookFiles`), as two
//! processes would have: neither write drops what the other wrote, each console is told and
//! shows the other's positions; a tour added by hand while a console runs survives its save; a
//! name changed on both sides keeps both and says so; a hand-edited book with a bad entry loads
//! the rest and names it.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use armjog::console::app::{App, Effect, Input, Overlay, QUESTION_QUIET, Severity};
use armjog::console::book_io::{self, BookFiles, SaveOutcome};
use armjog::console::form::Confirm;
use armjog::console::jog::ReleaseMode;
use armjog::console::positions::{PositionBook, Tour};

use crate::app_support::{app, press};

/// One console: its app (positions in its book, as over Modbus) and its book's files.
struct Console {
    app: App,
    files: BookFiles,
    t0: Instant,
}

impl Console {
    async fn open(path: &Path) -> Console {
        let mut files = BookFiles::open(Some(path.to_path_buf())).expect("opened");
        let (mut app, t0) = app(ReleaseMode::Reported, false);
        app.begin_loading_positions(path.display().to_string());
        let loaded = book_io::loaded(&mut files.loading).await;
        app.handle(Input::PositionsLoaded(loaded), t0);
        Console { app, files, t0 }
    }

    /// Carries out the saves among `effects` as the runtime does, and hands the app each
    /// write's outcome.
    async fn saved(&mut self, effects: Vec<Effect>) {
        let mut saves = 0;
        for effect in effects {
            if let Effect::SavePositions(save) = effect {
                self.files.save(save);
                saves += 1;
            }
        }
        assert!(saves > 0, "a save was asked for");
        let outcome =
            tokio::time::timeout(Duration::from_secs(10), self.files.save_outcomes.recv())
                .await
                .expect("the writer answers in time")
                .expect("an outcome");
        assert_eq!(outcome.error, None);
        self.app.handle(Input::PositionsSaved(outcome), self.t0);
    }

    fn press(&mut self, key: &str) -> Vec<Effect> {
        press(&mut self.app, key, self.t0)
    }

    /// Defines `name` at (x, 0, 300) mm through the cartesian form; returns its effects.
    fn define(&mut self, name: &str, x_mm: u32) -> Vec<Effect> {
        self.press("C");
        for _ in 0..40 {
            self.press("backspace");
        }
        for c in name.chars() {
            self.press(&c.to_string());
        }
        for value in [x_mm.to_string(), "0".into(), "300".into()] {
            self.press("tab");
            for c in value.chars() {
                self.press(&c.to_string());
            }
        }
        let mut effects = self.press("enter");
        if matches!(self.app.overlay(), Overlay::Confirm(_)) {
            // Over a name that exists: yes, overwrite.
            effects = self.answer("y");
        }
        effects
    }

    /// Defines `name` as `define` does and saves it.
    async fn define_saved(&mut self, name: &str, x_mm: u32) {
        let effects = self.define(name, x_mm);
        self.saved(effects).await;
    }

    /// Answers the question on screen with `key`, once it takes keys.
    fn answer(&mut self, key: &str) -> Vec<Effect> {
        self.t0 += QUESTION_QUIET;
        self.press(key)
    }

    fn names(&self) -> Vec<String> {
        self.app.positions().names().map(String::from).collect()
    }

    fn message(&self) -> (String, Severity) {
        self.app
            .message()
            .map(|(text, severity)| (text.to_string(), severity))
            .expect("a message")
    }

    async fn close(self) {
        self.files.finish(Duration::from_secs(10)).await;
    }
}

fn x_of(book: &PositionBook, name: &str) -> Option<i32> {
    book.get(name).and_then(|e| e.cartesian).map(|c| c[0])
}

/// A book of one position, `name`, at (0, 0, 300) mm.
fn book_of(name: &str) -> PositionBook {
    let mut book = PositionBook::new();
    book.get_or_insert(name).cartesian = Some([0, 0, 3000]);
    book
}

fn book_file(book: &PositionBook) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("book.json");
    book.save(&path).expect("book");
    (dir, path)
}

fn on_disk(path: &Path) -> Vec<String> {
    let book = PositionBook::load(path).expect("the book reads");
    book.names().map(String::from).collect()
}

#[tokio::test]
async fn two_consoles_on_one_book_keep_each_others_positions_and_say_so() {
    let start = book_of("home");
    let (_dir, path) = book_file(&start);
    let mut one = Console::open(&path).await;
    let mut two = Console::open(&path).await;

    one.define_saved("x1", 100).await;
    assert_eq!(on_disk(&path), ["home", "x1"]);
    two.define_saved("x3", 300).await;
    assert_eq!(on_disk(&path), ["home", "x1", "x3"], "console 1's X1 kept");
    assert_eq!(two.names(), ["home", "x1", "x3"], "and shown on console 2");
    let (said, severity) = two.message();
    assert!(
        said.starts_with("saved 'x3'; ") && said.contains("changed by another program"),
        "{said}"
    );
    assert_eq!(severity, Severity::Info);

    // A delete is a delete, on either console, and does not come back with the other's save.
    assert_eq!(
        one.app.selected_name(),
        Some("x1"),
        "the saved name is selected"
    );
    one.press("delete");
    let effects = one.answer("y");
    one.saved(effects).await;
    assert_eq!(one.names(), ["home", "x3"], "console 2's X3 came in");
    assert_eq!(on_disk(&path), ["home", "x3"]);
    two.define_saved("x4", 400).await;
    assert_eq!(on_disk(&path), ["home", "x3", "x4"], "x1 stays deleted");
    assert_eq!(two.names(), ["home", "x3", "x4"]);
    one.close().await;
    two.close().await;
}

#[tokio::test]
async fn a_tour_added_by_hand_while_the_console_runs_survives_its_save() {
    let start = book_of("bench");
    let (_dir, path) = book_file(&start);
    let mut console = Console::open(&path).await;
    let mut by_hand = start.clone();
    by_hand.set_tour(Tour {
        name: "rounds".into(),
        positions: vec!["bench".into()],
    });
    by_hand.save(&path).expect("the hand edit");
    console.define_saved("pick", 100).await;
    let saved = PositionBook::load(&path).expect("reads");
    assert!(saved.tour("rounds").is_some(), "the hand-made tour is kept");
    assert!(
        console.app.positions().tour("rounds").is_some(),
        "and shown"
    );
    console.close().await;
}

/// Two consoles on one book with 'pick', each saving its own 'pick': console 1's first (x
/// 100 mm), then console 2's (x 200 mm).
async fn pick_saved_on_both() -> (tempfile::TempDir, PathBuf, Console, Console) {
    let (dir, path) = book_file(&book_of("pick"));
    let mut one = Console::open(&path).await;
    let mut two = Console::open(&path).await;
    one.define_saved("pick", 100).await;
    two.define_saved("pick", 200).await;
    (dir, path, one, two)
}

#[tokio::test]
async fn a_name_saved_on_both_consoles_keeps_both_and_names_them() {
    let (_dir, path, mut one, mut two) = pick_saved_on_both().await;
    let saved = PositionBook::load(&path).expect("reads");
    assert_eq!(x_of(&saved, "pick"), Some(1000), "console 1's pick kept");
    assert_eq!(x_of(&saved, "pick~2"), Some(2000), "console 2's beside it");
    assert_eq!(x_of(two.app.positions(), "pick~2"), Some(2000));
    let (said, severity) = two.message();
    assert!(
        said.contains("'pick'") && said.contains("'pick~2'"),
        "{said}"
    );
    assert_eq!(severity, Severity::Warning);

    // Console 2's technician is asked which is 'pick'; enter does not answer, y swaps them.
    let Overlay::Confirm(question) = two.app.overlay().clone() else {
        panic!("no question: {:?}", two.app.overlay())
    };
    assert_eq!(
        question,
        Confirm::BothChanged {
            name: "pick".into(),
            copy: "pick~2".into()
        }
    );
    assert!(
        question
            .question()
            .contains("changed here and by another program")
    );
    let effects = two.answer("y");
    two.saved(effects).await;
    let saved = PositionBook::load(&path).expect("reads");
    assert_eq!(x_of(&saved, "pick"), Some(2000), "console 2's has the name");
    assert_eq!(x_of(&saved, "pick~2"), Some(1000), "console 1's beside it");
    assert_eq!(two.app.selected_name(), Some("pick"));

    // Console 1 sees the swap with its next save, as another program's change: no question,
    // but it is told its 'pick' is 'pick~2' now.
    one.define_saved("other", 300).await;
    assert_eq!(x_of(one.app.positions(), "pick"), Some(2000));
    assert_eq!(x_of(one.app.positions(), "pick~2"), Some(1000));
    assert_eq!(one.app.overlay(), &Overlay::None);
    let (said, severity) = one.message();
    assert!(
        said.contains("'pick' was kept as 'pick~2' by another program"),
        "{said}"
    );
    assert_eq!(severity, Severity::Warning);
    one.close().await;
    two.close().await;
}

#[tokio::test]
async fn keeping_both_after_a_conflict_changes_nothing() {
    let (_dir, _path, one, mut two) = pick_saved_on_both().await;
    let effects = two.answer("n");
    assert!(effects.is_empty(), "{effects:?}");
    assert_eq!(two.app.overlay(), &Overlay::None);
    assert_eq!(
        two.message().0,
        "both kept: theirs as 'pick', this console's as 'pick~2'"
    );
    assert_eq!(x_of(two.app.positions(), "pick"), Some(1000));
    assert_eq!(x_of(two.app.positions(), "pick~2"), Some(2000));
    one.close().await;
    two.close().await;
}

#[tokio::test]
async fn a_save_at_the_value_read_over_another_programs_change_keeps_both_and_asks() {
    // Console 2 read x3 at (0, 0, 300) mm; another program moves x3 in the file to x 500 mm.
    let (_dir, path) = book_file(&book_of("x3"));
    let mut two = Console::open(&path).await;
    let mut edited = book_of("x3");
    edited.get_or_insert("x3").cartesian = Some([5000, 0, 3000]);
    edited.save(&path).expect("the other program's edit");
    // The technician saves x3 where console 2 has it, and says yes to "overwrite 'x3'?".
    two.define_saved("x3", 0).await;
    let saved = PositionBook::load(&path).expect("reads");
    assert_eq!(
        x_of(&saved, "x3"),
        Some(5000),
        "the other program's x3 kept"
    );
    assert_eq!(
        x_of(&saved, "x3~2"),
        Some(0),
        "this console's save kept beside it"
    );
    assert_eq!(x_of(two.app.positions(), "x3~2"), Some(0));
    let (said, severity) = two.message();
    assert!(
        said.contains("'x3'") && said.contains("'x3~2'") && !said.contains("nothing lost"),
        "{said}"
    );
    assert_eq!(severity, Severity::Warning);
    assert_eq!(
        two.app.overlay(),
        &Overlay::Confirm(Confirm::BothChanged {
            name: "x3".into(),
            copy: "x3~2".into()
        }),
        "the technician is asked which is 'x3'"
    );
    two.close().await;
}

/// Hands the saves among `effects` to the console's writer, as the runtime does.
fn hand_over(console: &Console, effects: Vec<Effect>) {
    for effect in effects {
        if let Effect::SavePositions(save) = effect {
            console.files.save(save);
        }
    }
}

#[tokio::test]
async fn a_save_waiting_for_the_books_lock_says_saving_until_it_is_written() {
    let (_dir, path) = book_file(&book_of("home"));
    let mut console = Console::open(&path).await;
    // Another program holds the book's lock.
    let lock = std::fs::File::create(path.with_extension("json.lock")).expect("lock file");
    lock.lock().expect("the other program's lock");
    let effects = console.define("s3", 300);
    let saving = ("saving 's3'…".to_string(), Severity::Info);
    assert_eq!(console.message(), saving);
    hand_over(&console, effects);
    let waited = tokio::time::timeout(
        Duration::from_millis(300),
        console.files.save_outcomes.recv(),
    )
    .await;
    assert!(waited.is_err(), "nothing written while the lock is held");
    // Past a notice's time, the write still waiting: still saving, never "saved".
    console.t0 += Duration::from_secs(8);
    console.app.handle(Input::Tick, console.t0);
    assert_eq!(console.message(), saving);
    lock.unlock().expect("unlocked");
    let outcome = tokio::time::timeout(Duration::from_secs(10), console.files.save_outcomes.recv())
        .await
        .expect("the writer answers in time")
        .expect("an outcome");
    assert_eq!(outcome.error, None);
    console
        .app
        .handle(Input::PositionsSaved(outcome), console.t0);
    assert_eq!(
        console.message(),
        ("saved 's3'".to_string(), Severity::Info)
    );
    assert_eq!(on_disk(&path), ["home", "s3"]);
    console.close().await;
}

#[tokio::test]
async fn a_save_whose_write_failed_is_never_said_saved() {
    let (_dir, path) = book_file(&book_of("home"));
    let mut console = Console::open(&path).await;
    console.define("s3", 300);
    assert_eq!(console.message().0, "saving 's3'…");
    let failed = SaveOutcome {
        upto: 1,
        error: Some("book.json: the book's lock is held by another program".into()),
        found: None,
    };
    console
        .app
        .handle(Input::PositionsSaved(failed), console.t0);
    let (said, severity) = console.message();
    assert!(said.starts_with("positions not saved: book.json"), "{said}");
    assert_eq!(severity, Severity::Error);
    console.close().await;
}

#[tokio::test]
async fn a_hand_edited_book_with_a_bad_entry_loads_the_rest_and_a_save_keeps_its_bytes() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("book.json");
    let text = r#"{"format": 1, "positions": {
        "bench": {"cartesian": [1000, 0, 3000]},
        "gone": null,
        "pick": {"cartesian": [1, 2, 3], "frame": "tool"}}}"#;
    std::fs::write(&path, text).expect("book");
    let mut console = Console::open(&path).await;
    assert_eq!(console.names(), ["bench"]);
    let (said, severity) = console.message();
    assert_eq!(severity, Severity::Warning);
    for named in ["'gone'", "'pick'", "book.json.bad"] {
        assert!(said.contains(named), "{named} in {said}");
    }
    let copy = dir.path().join("book.json.bad");
    assert_eq!(std::fs::read_to_string(&copy).expect("copy"), text);
    console.define_saved("place", 200).await;
    assert_eq!(on_disk(&path), ["bench", "place"]);
    assert_eq!(
        std::fs::read_to_string(&copy).expect("copy"),
        text,
        "the hand edit is kept"
    );
    console.close().await;
}
