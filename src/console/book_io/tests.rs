//! The book's reader and writer off the event loop: loads, writes in order, the writes at quit.

use super::*;

fn dir() -> tempfile::TempDir {
    tempfile::tempdir().unwrap()
}

#[tokio::test]
async fn the_last_book_handed_over_is_written_before_finish_returns() {
    let d = dir();
    let path = d.path().join("book.json");
    let (saver, _errors) = Saver::start(path.clone());
    let mut book = PositionBook::new();
    for i in 0..5 {
        book.get_or_insert(&format!("p{i}")).cartesian = Some([i, 0, 0]);
        saver.save(BookSave {
            book: book.clone(),
            known: PositionBook::new(),
            touched: BTreeSet::new(),
        });
    }
    saver.finish(Duration::from_secs(10), || {}).await;
    assert_eq!(PositionBook::load(&path).unwrap(), book);
}

#[tokio::test]
async fn a_failed_write_is_reported_with_the_file() {
    let d = dir();
    let blocker = d.path().join("not-a-dir");
    std::fs::write(&blocker, "x").unwrap();
    let path = blocker.join("book.json");
    let (saver, mut errors) = Saver::start(path.clone());
    saver.save(BookSave {
        book: PositionBook::new(),
        known: PositionBook::new(),
        touched: BTreeSet::new(),
    });
    let outcome = tokio::time::timeout(Duration::from_secs(10), errors.recv())
        .await
        .expect("reported in time")
        .expect("an outcome");
    assert_eq!(outcome.upto, 1);
    let error = outcome.error.expect("an error");
    assert!(error.contains(&path.display().to_string()), "{error}");
    saver.finish(Duration::from_secs(10), || {}).await;
}

#[tokio::test]
async fn a_failed_writes_saved_names_are_changes_of_the_next_write() {
    let d = dir();
    let folder = d.path().join("folder");
    std::fs::write(&folder, "not a folder yet").unwrap();
    let path = folder.join("book.json");
    let at = |x: i32| {
        let mut book = PositionBook::new();
        book.get_or_insert("x3").cartesian = Some([x, 0, 0]);
        book
    };
    let (saver, mut outcomes) = Saver::start(path.clone());
    let outcome = async |outcomes: &mut mpsc::UnboundedReceiver<SaveOutcome>| {
        tokio::time::timeout(Duration::from_secs(10), outcomes.recv())
            .await
            .expect("reported in time")
            .expect("an outcome")
    };
    // x3 saved here at the value read (1): the write fails.
    saver.save(BookSave {
        book: at(1),
        known: at(1),
        touched: ["x3".to_string()].into(),
    });
    assert!(outcome(&mut outcomes).await.error.is_some());
    // Meanwhile another program puts x3 at 2; the next save here changes nothing more.
    std::fs::remove_file(&folder).unwrap();
    std::fs::create_dir(&folder).unwrap();
    at(2).save(&path).unwrap();
    saver.save(BookSave {
        book: at(1),
        known: at(1),
        touched: BTreeSet::new(),
    });
    let found = outcome(&mut outcomes)
        .await
        .found
        .expect("a conflict found");
    assert_eq!(found.written.conflicts.len(), 1, "{found:?}");
    let saved = PositionBook::load(&path).unwrap();
    let names: Vec<&str> = saved.names().collect();
    assert_eq!(
        names,
        ["x3", "x3~2"],
        "the failed write's save kept, beside theirs"
    );
    saver.finish(Duration::from_secs(10), || {}).await;
}

#[tokio::test]
async fn a_write_at_quit_waiting_for_the_lock_says_what_it_waits_for_and_a_failure_is_told() {
    let d = dir();
    let path = d.path().join("book.json");
    let lock = std::fs::File::create(shared::lock_path(&path)).unwrap();
    lock.lock().unwrap();
    let files = BookFiles::open(Some(path.clone())).expect("opened");
    let mut book = PositionBook::new();
    book.get_or_insert("s3");
    files.save(BookSave {
        book: book.clone(),
        known: PositionBook::new(),
        touched: ["s3".to_string()].into(),
    });
    let (told_tx, mut told) = mpsc::unbounded_channel();
    let quitting = tokio::spawn(files.finish_telling(Duration::from_secs(10), move |line| {
        let _ = told_tx.send(line);
    }));
    let line = tokio::time::timeout(Duration::from_secs(5), told.recv())
        .await
        .expect("told in time")
        .expect("a line");
    let lock_shown = shared::lock_path(&path).display().to_string();
    assert!(
        line.contains("waiting") && line.contains(&lock_shown),
        "{line}"
    );
    lock.unlock().unwrap();
    quitting.await.unwrap();
    assert_eq!(told.recv().await, None, "nothing more to tell: written");
    assert_eq!(PositionBook::load(&path).unwrap(), book);

    // A write at quit that fails is told, naming the file (a folder now, by mistake).
    let path = d.path().join("other.json");
    let mut files = BookFiles::open(Some(path.clone())).expect("opened");
    assert_eq!(loaded(&mut files.loading).await, Ok(PositionBook::new()));
    std::fs::create_dir(&path).unwrap();
    files.save(BookSave {
        book,
        known: PositionBook::new(),
        touched: BTreeSet::new(),
    });
    let mut lines = Vec::new();
    files
        .finish_telling(Duration::from_secs(10), |line| lines.push(line))
        .await;
    let shown = path.display().to_string();
    assert!(
        lines
            .last()
            .is_some_and(|l| l.starts_with("positions not saved: ") && l.contains(&shown)),
        "{lines:?}"
    );
}

#[tokio::test]
async fn a_file_over_the_limit_or_a_device_is_refused_at_once_and_a_book_loads_later() {
    let d = dir();
    let big = d.path().join("big.json");
    std::fs::write(&big, vec![b' '; 17 * 1024 * 1024]).unwrap();
    let error = BookFiles::open(Some(big.clone())).err().expect("refused");
    assert!(error.to_string().contains("16 MB"), "{error}");
    #[cfg(unix)]
    {
        let error = BookFiles::open(Some("/dev/zero".into()))
            .err()
            .expect("refused");
        assert!(error.to_string().starts_with("/dev/zero"), "{error}");
    }
    let path = d.path().join("book.json");
    let mut book = PositionBook::new();
    book.get_or_insert("pick");
    book.save(&path).unwrap();
    let mut files = BookFiles::open(Some(path)).expect("opened");
    assert_eq!(loaded(&mut files.loading).await, Ok(book));
    let mut none = BookFiles::open(Some(d.path().join("missing.json"))).expect("opened");
    assert_eq!(loaded(&mut none.loading).await, Ok(PositionBook::new()));
    files.finish(Duration::from_secs(10)).await;
}

#[tokio::test]
async fn changes_held_at_quit_while_loading_are_merged_into_the_book_and_written() {
    let d = dir();
    let path = d.path().join("book.json");
    let mut on_disk = PositionBook::new();
    on_disk.get_or_insert("home");
    on_disk.save(&path).unwrap();
    let mut files = BookFiles::open(Some(path.clone())).expect("opened");
    let mut changes = PositionBook::new();
    changes.get_or_insert("pick").anchor = true;
    files.hold_until_loaded(changes);
    files.finish(Duration::from_secs(10)).await;
    let saved = PositionBook::load(&path).unwrap();
    let names: Vec<&str> = saved.names().collect();
    assert_eq!(names, ["home", "pick"]);
    assert!(saved.get("pick").is_some_and(|e| e.anchor));
}

#[tokio::test]
async fn a_book_loads_off_the_loop_and_an_unreadable_one_names_its_file() {
    let d = dir();
    let path = d.path().join("book.json");
    let mut book = PositionBook::new();
    book.get_or_insert("pick").cartesian = Some([1, 2, 3]);
    book.save(&path).unwrap();
    let mut loading = Some(load(&path));
    assert_eq!(loaded(&mut loading).await, Ok(book));
    assert!(loading.is_none(), "nothing left to wait for");

    let bad = d.path().join("bad.json");
    std::fs::write(&bad, "{ not json").unwrap();
    let mut loading = Some(load(&bad));
    let error = loaded(&mut loading).await.unwrap_err();
    assert!(
        error.to_string().starts_with(&bad.display().to_string()),
        "{error}"
    );
}

#[tokio::test]
async fn a_book_read_already_is_handed_over_and_not_read_again() {
    let d = dir();
    let path = d.path().join("book.json");
    let mut book = PositionBook::new();
    book.get_or_insert("pick").cartesian = Some([1, 2, 3]);
    book.save(&path).unwrap();
    let read_once = read(&path).await;
    // Whatever the file holds now, the console gets the book that was read.
    std::fs::write(&path, "{ not json").unwrap();
    let mut files = BookFiles::open_read(path, read_once).expect("opened");
    assert_eq!(loaded(&mut files.loading).await, Ok(book));
    files.finish(Duration::from_secs(10)).await;
}

#[tokio::test]
async fn a_bad_book_read_already_reports_as_opening_it_would() {
    let d = dir();
    let bad = d.path().join("bad.json");
    std::fs::write(&bad, "{ not json").unwrap();
    let mut opened = BookFiles::open(Some(bad.clone())).expect("opened");
    let mut handed = BookFiles::open_read(bad.clone(), read(&bad).await).expect("opened");
    let error = loaded(&mut handed.loading).await.unwrap_err();
    assert!(
        error.to_string().starts_with(&bad.display().to_string()),
        "{error}"
    );
    assert_eq!(loaded(&mut opened.loading).await, Err(error));

    let missing = d.path().join("missing.json");
    let mut none = BookFiles::open_read(missing.clone(), read(&missing).await).expect("opened");
    assert_eq!(loaded(&mut none.loading).await, Ok(PositionBook::new()));

    let big = d.path().join("big.json");
    std::fs::write(&big, vec![b' '; 17 * 1024 * 1024]).unwrap();
    let refused = BookFiles::open(Some(big.clone())).err().expect("refused");
    let refused_read = BookFiles::open_read(big.clone(), read(&big).await)
        .err()
        .expect("refused");
    assert_eq!(refused_read.to_string(), refused.to_string());
    assert!(refused_read.to_string().contains("16 MB"), "{refused_read}");
    #[cfg(unix)]
    {
        let device = PathBuf::from("/dev/zero");
        let error = BookFiles::open_read(device.clone(), read(&device).await)
            .err()
            .expect("refused");
        assert!(error.to_string().starts_with("/dev/zero"), "{error}");
    }
}
