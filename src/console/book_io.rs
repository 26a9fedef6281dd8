//! The position book read and written off the event loop, which must never wait for it.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

use tokio::sync::{mpsc, oneshot};

use std::io::Write as _;

use super::positions::shared::{self, Written};
use super::positions::{BookError, PositionBook};
use crate::link::failure::Shared;

/// What the loader hands back: the book, or the error naming the file and what was wrong.
pub type Loaded = Result<PositionBook, Shared<BookError>>;

/// Starts reading the book at `path` on a blocking thread.
pub fn load(path: &Path) -> oneshot::Receiver<Loaded> {
    let (tx, rx) = oneshot::channel();
    let path = path.to_path_buf();
    tokio::task::spawn_blocking(move || {
        let started = std::time::Instant::now();
        let result = PositionBook::load(&path).map_err(Shared::from);
        if let Ok(book) = &result {
            tracing::info!(
                "loaded {} positions from {} in {:?}",
                book.len(),
                path.display(),
                started.elapsed()
            );
        }
        // The console may have quit meanwhile: nobody wants the book then.
        let _ = tx.send(result);
    });
    rx
}

/// Reads the book on a blocking thread, for a caller that needs it before the console starts.
pub async fn read(path: &Path) -> Result<PositionBook, BookError> {
    let owned = path.to_path_buf();
    match tokio::task::spawn_blocking(move || PositionBook::load(&owned)).await {
        Ok(read) => read,
        Err(e) => Err(BookError::Io {
            path: path.display().to_string(),
            source: std::io::Error::other(format!("the positions reader failed: {e}")),
        }),
    }
}

/// Waits for the loader's answer (forever with none owed); a loader gone silent is an error.
pub async fn loaded(loading: &mut Option<oneshot::Receiver<Loaded>>) -> Loaded {
    let Some(rx) = loading.as_mut() else {
        return std::future::pending().await;
    };
    let result = rx
        .await
        .unwrap_or_else(|_| Err(BookError::LoaderEnded.into()));
    *loading = None;
    result
}

/// A book to write, with its base (the file as last known) to merge against.
#[derive(Debug, Clone, PartialEq)]
pub struct BookSave {
    pub book: PositionBook,
    pub known: PositionBook,
    /// Saved or edited since `known`, even at `known`'s value: a save over another's is a conflict.
    pub touched: BTreeSet<String>,
}

impl BookSave {
    /// This book written instead of unwritten `older`: from its base, with its changes.
    fn over(mut self, older: BookSave) -> BookSave {
        self.known = older.known;
        self.touched.extend(older.touched);
        self
    }
}

impl std::ops::Deref for BookSave {
    type Target = PositionBook;

    fn deref(&self) -> &PositionBook {
        &self.book
    }
}

/// The books up to the `upto`-th: written, or the newest failed; `found`: merged changes.
#[derive(Debug, Clone, PartialEq)]
pub struct SaveOutcome {
    pub upto: u64,
    pub error: Option<String>,
    pub found: Option<Box<Found>>,
}

/// Another writer's work found by a write: the book handed over and what was written.
#[derive(Debug, Clone, PartialEq)]
pub struct Found {
    pub handed: PositionBook,
    pub written: Written,
}

/// The writer thread: books in order; a newer book replaces any not yet written.
pub struct Saver {
    next: mpsc::UnboundedSender<(u64, BookSave)>,
    /// Books handed over so far.
    handed: AtomicU64,
    task: tokio::task::JoinHandle<()>,
}

impl Saver {
    /// Starts the writer for `path`; each write's outcome is reported on the returned receiver.
    pub fn start(path: PathBuf) -> (Saver, mpsc::UnboundedReceiver<SaveOutcome>) {
        let (next, mut books) = mpsc::unbounded_channel::<(u64, BookSave)>();
        let (outcomes_tx, outcomes) = mpsc::unbounded_channel();
        let task = tokio::spawn(async move {
            // Books are taken, not copied; `unwritten`: the last failed write (its base and changes).
            let mut unwritten: Option<BookSave> = None;
            while let Some(mut handed) = books.recv().await {
                while let Ok((upto, newer)) = books.try_recv() {
                    // The newer book holds the older's changes, merged from the older's base.
                    handed = (upto, newer.over(handed.1));
                }
                let (upto, mut save) = handed;
                if let Some(older) = unwritten.take() {
                    save = save.over(older);
                }
                let path = path.clone();
                let written = tokio::task::spawn_blocking(move || {
                    let written = save.book.save_shared(&save.known, &save.touched, &path);
                    (save, written)
                })
                .await;
                let (error, found) = match written {
                    Ok((_, Ok(written))) if !written.found_others() => (None, None),
                    Ok((save, Ok(written))) => {
                        let handed = save.book;
                        tracing::info!(
                            "positions: {} changes by another writer merged in, {} conflicts, \
                             {} entries set aside",
                            written.taken,
                            written.conflicts.len(),
                            written.set_aside.len()
                        );
                        (None, Some(Box::new(Found { handed, written })))
                    }
                    Ok((save, Err(e))) => {
                        unwritten = Some(save);
                        (Some(e.to_string()), None)
                    }
                    Err(e) => (Some(format!("the positions writer failed: {e}")), None),
                };
                if let Some(error) = &error {
                    tracing::error!("saving positions: {error}");
                }
                let _ = outcomes_tx.send(SaveOutcome { upto, error, found });
            }
        });
        let handed = AtomicU64::new(0);
        (Saver { next, handed, task }, outcomes)
    }

    /// Hands a book over to be written. Never waits for a write.
    pub fn save(&self, book: BookSave) {
        let upto = 1 + self.handed.fetch_add(1, Ordering::Relaxed);
        if self.next.send((upto, book)).is_err() {
            tracing::error!("the positions writer has ended: positions not saved");
        }
    }

    /// Writes the book handed over last, if not yet written, waiting at most `within`; `waiting` is
    /// called after [`TELL_WAIT_AFTER`]. Returns whether the writer ended in time.
    pub async fn finish(self, within: Duration, waiting: impl FnOnce()) -> bool {
        drop(self.next);
        let ended = tokio::time::timeout(within, self.task);
        tokio::pin!(ended);
        let ended = tokio::select! {
            ended = &mut ended => ended,
            () = tokio::time::sleep(TELL_WAIT_AFTER) => {
                waiting();
                ended.await
            }
        };
        if ended.is_err() {
            tracing::error!("the positions file was not written within {within:?}");
        }
        ended.is_ok()
    }
}

/// How long a write at quit may take before the technician is told what it waits for.
pub const TELL_WAIT_AFTER: Duration = Duration::from_millis(300);

/// The book's file as the event loop sees it: the load in progress, the writer, its errors.
pub struct BookFiles {
    /// Where the book lives; `None`: nowhere (nothing is loaded or saved).
    pub path: Option<PathBuf>,
    pub loading: Option<oneshot::Receiver<Loaded>>,
    saver: Option<Saver>,
    /// Each write's outcome, for the app to mark what was not saved.
    pub save_outcomes: mpsc::UnboundedReceiver<SaveOutcome>,
    /// Changes made while the book was loading, still to be merged into it and written.
    held: Option<PositionBook>,
}

impl BookFiles {
    /// Starts loading the book at `path` and its writer. A regular file within the size limit (or
    /// none) is read off the event loop; anything else (too big, a device, a FIFO, unopenable) is
    /// refused here, naming the file, before the console takes the terminal.
    pub fn open(path: Option<PathBuf>) -> Result<BookFiles, BookError> {
        BookFiles::open_with(path, None)
    }

    /// As [`BookFiles::open`], with the book already `read` (by [`read`]), so it is not read twice.
    pub fn open_read(
        path: PathBuf,
        read: Result<PositionBook, BookError>,
    ) -> Result<BookFiles, BookError> {
        BookFiles::open_with(Some(path), Some(read))
    }

    fn open_with(
        path: Option<PathBuf>,
        read: Option<Result<PositionBook, BookError>>,
    ) -> Result<BookFiles, BookError> {
        let Some(p) = &path else {
            return Ok(BookFiles {
                path,
                loading: None,
                saver: None,
                save_outcomes: mpsc::unbounded_channel().1,
                held: None,
            });
        };
        let regular_within_limit = match std::fs::metadata(p) {
            Ok(meta) => meta.is_file() && meta.len() <= crate::files::POSITIONS_LIMIT,
            Err(e) => e.kind() == std::io::ErrorKind::NotFound,
        };
        let loading = match (read, regular_within_limit) {
            (None, true) => load(p),
            (Some(read), true) => answered(read.map_err(Shared::from)),
            (read, false) => answered(Ok(match read {
                Some(read) => read?,
                None => PositionBook::load(p)?,
            })),
        };
        let (saver, save_outcomes) = Saver::start(p.clone());
        Ok(BookFiles {
            loading: Some(loading),
            path,
            saver: Some(saver),
            save_outcomes,
            held: None,
        })
    }

    /// Hands a book over to be written (nothing happens without a file).
    pub fn save(&self, book: BookSave) {
        if let Some(saver) = &self.saver {
            saver.save(book);
        }
    }

    /// Keeps changes made while the book still loads (quitting), for [`BookFiles::finish`].
    pub fn hold_until_loaded(&mut self, changes: PositionBook) {
        if self.loading.is_some() && !changes.is_empty() {
            self.held = Some(changes);
        }
    }

    /// Writes the last book (and held changes), at most `within`, telling stderr of delays.
    pub async fn finish(self, within: Duration) {
        self.finish_telling(within, |line| {
            // Not `eprintln!`, which panics when stderr is gone (a terminal that hung up).
            let _ = writeln!(std::io::stderr(), "armjog: {line}");
        })
        .await;
    }

    /// As [`BookFiles::finish`], telling `tell`.
    pub async fn finish_telling(mut self, within: Duration, mut tell: impl FnMut(String)) {
        let deadline = tokio::time::Instant::now() + within;
        if let Some(changes) = self.held.take() {
            match tokio::time::timeout_at(deadline, loaded(&mut self.loading)).await {
                Ok(Ok(known)) => {
                    let mut book = known.clone();
                    book.merge(&changes);
                    let touched = changes.names().map(String::from).collect();
                    self.save(BookSave {
                        book,
                        known,
                        touched,
                    });
                }
                Ok(Err(error)) => tracing::error!(
                    "{} changed positions not saved: the book was not loaded ({error})",
                    changes.len()
                ),
                Err(_) => tracing::error!(
                    "{} changed positions not saved: the book did not load within {within:?}",
                    changes.len()
                ),
            }
        }
        let Some(saver) = self.saver else {
            return;
        };
        let left = deadline.saturating_duration_since(tokio::time::Instant::now());
        let (shown, lock) = match self.path.as_deref() {
            Some(p) => (
                p.display().to_string(),
                shared::lock_path(p).display().to_string(),
            ),
            None => Default::default(),
        };
        let waiting = || {
            tell(format!(
                "writing the positions to {shown}: waiting up to {} s for its lock ({lock}), \
                 which another program may hold…",
                left.as_secs()
            ))
        };
        let in_time = saver.finish(left, waiting).await;
        // The last outcome covers every write before it (each writes the whole book).
        let last = std::iter::from_fn(|| self.save_outcomes.try_recv().ok()).last();
        if let Some(error) = last.and_then(|o| o.error) {
            tell(format!("positions not saved: {error}"));
        } else if !in_time {
            tell(format!(
                "positions not saved: {shown} was not written within {} s",
                within.as_secs()
            ));
        }
    }
}

/// A loader's answer that is already known.
fn answered(result: Loaded) -> oneshot::Receiver<Loaded> {
    let (tx, rx) = oneshot::channel();
    let _ = tx.send(result);
    rx
}

#[cfg(test)]
mod tests;
