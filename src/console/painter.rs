//! The drawing thread: it owns the terminal's output and draws snapshots of the app, so the
//! task that reads keys never waits for a frame to be drawn (a release's STOP goes out while a
//! frame is being written).
//!
//! Only the newest snapshot is kept: a slow draw skips frames rather than queueing them.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::time::Duration;

use ratatui::Terminal;
use ratatui::backend::CrosstermBackend;
use tokio::sync::mpsc;

use super::app::App;
use super::ui::{self, Theme};

type Screen = Terminal<CrosstermBackend<std::io::Stdout>>;

#[derive(Default)]
struct Slot {
    next: Option<Box<App>>,
    closing: bool,
}

/// The handle on the drawing thread. Closing (or dropping) it ends the thread.
pub struct Painter {
    slot: Arc<(Mutex<Slot>, Condvar)>,
    /// Whether drawing is still allowed: cleared by the panic hook before it restores the
    /// terminal, so no frame lands on the restored screen.
    allowed: Arc<AtomicBool>,
    done: Option<std::sync::mpsc::Receiver<()>>,
}

impl Painter {
    /// Starts the thread; a draw that fails is reported on the returned receiver and ends it.
    pub fn start(
        terminal: Screen,
        theme: Theme,
        allowed: Arc<AtomicBool>,
    ) -> std::io::Result<(Painter, mpsc::UnboundedReceiver<std::io::Error>)> {
        let slot = Arc::new((Mutex::new(Slot::default()), Condvar::new()));
        let (errors_tx, errors) = mpsc::unbounded_channel();
        let (done_tx, done) = std::sync::mpsc::channel();
        let thread_slot = slot.clone();
        let thread_allowed = allowed.clone();
        std::thread::Builder::new()
            .name("armjog-draw".into())
            .spawn(move || {
                paint(terminal, theme, &thread_slot, &thread_allowed, &errors_tx);
                let _ = done_tx.send(());
            })?;
        Ok((
            Painter {
                slot,
                allowed,
                done: Some(done),
            },
            errors,
        ))
    }

    /// Hands the thread a snapshot to draw; replaces one not drawn yet. Never waits for a draw.
    pub fn paint(&self, app: App) {
        let (lock, ready) = &*self.slot;
        if let Ok(mut slot) = lock.lock() {
            slot.next = Some(Box::new(app));
            ready.notify_one();
        }
    }

    /// Ends the thread after the frame in progress, waiting for it at most `within`.
    pub fn close(&mut self, within: Duration) {
        let (lock, ready) = &*self.slot;
        if let Ok(mut slot) = lock.lock() {
            slot.closing = true;
            slot.next = None;
            ready.notify_one();
        }
        if let Some(done) = self.done.take()
            && done.recv_timeout(within).is_err()
        {
            // A terminal that does not take output: stop drawing and go on restoring it.
            self.allowed.store(false, Ordering::SeqCst);
            tracing::warn!("the drawing thread did not end within {within:?}");
        }
    }
}

impl Drop for Painter {
    fn drop(&mut self) {
        self.close(Duration::from_millis(500));
    }
}

fn paint(
    mut terminal: Screen,
    theme: Theme,
    slot: &(Mutex<Slot>, Condvar),
    allowed: &AtomicBool,
    errors: &mpsc::UnboundedSender<std::io::Error>,
) {
    let (lock, ready) = slot;
    loop {
        let app = {
            let Ok(mut guard) = lock.lock() else { return };
            loop {
                if guard.closing {
                    return;
                }
                if let Some(app) = guard.next.take() {
                    break app;
                }
                guard = match ready.wait(guard) {
                    Ok(guard) => guard,
                    Err(_) => return,
                };
            }
        };
        if !allowed.load(Ordering::SeqCst) {
            return;
        }
        if let Err(e) = terminal.draw(|frame| ui::draw(frame, &app, &theme)) {
            let _ = errors.send(e);
            return;
        }
    }
}
