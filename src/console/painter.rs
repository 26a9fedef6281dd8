//! The drawing thread: it owns the terminal's output and draws [`View`]s, so the task that reads
//! keys never waits for a frame (a release's STOP goes out while one is written). Only the
//! newest view is kept: a slow draw skips frames, and the thread rests in proportion to its cost.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::time::{Duration, Instant};

use tokio::sync::mpsc;

use super::view::View;

#[derive(Default)]
struct Slot {
    next: Option<Box<View>>,
    closing: bool,
}

/// The handle on the drawing thread. Closing (or dropping) it ends the thread.
pub struct Painter {
    slot: Arc<(Mutex<Slot>, Condvar)>,
    /// Whether drawing is still allowed: cleared by the panic hook before it restores the
    /// terminal, so no frame lands on the restored screen.
    allowed: Arc<AtomicBool>,
    /// Told when the thread ends. In a mutex only so the painter can be shared with the
    /// runtime's tasks (a receiver is not `Sync`); only `close` takes it.
    done: Mutex<Option<std::sync::mpsc::Receiver<()>>>,
}

impl Painter {
    /// Starts the thread that calls `draw` with each view (the console's: a ratatui draw
    /// on the terminal). A draw that fails is reported on the returned receiver and ends it.
    pub fn start(
        draw: impl FnMut(&View) -> std::io::Result<()> + Send + 'static,
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
                paint(draw, &thread_slot, &thread_allowed, &errors_tx);
                let _ = done_tx.send(());
            })?;
        Ok((
            Painter {
                slot,
                allowed,
                done: Mutex::new(Some(done)),
            },
            errors,
        ))
    }

    /// Hands the thread a view to draw; replaces one not drawn yet. Never waits for a draw.
    pub fn paint(&self, view: View) {
        let (lock, ready) = &*self.slot;
        if let Ok(mut slot) = lock.lock() {
            slot.next = Some(Box::new(view));
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
        let done = self.done.get_mut().ok().and_then(Option::take);
        if let Some(done) = done
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

/// After a draw that took `d`, the thread rests `REST_FACTOR * d` (at most `MAX_REST`): a draw
/// slowed down by a busy machine then takes at most a third of a core, leaving the rest to the
/// key path rather than competing with it for every frame.
const REST_FACTOR: u32 = 2;
const MAX_REST: Duration = Duration::from_millis(200);

fn paint(
    mut draw: impl FnMut(&View) -> std::io::Result<()>,
    slot: &(Mutex<Slot>, Condvar),
    allowed: &AtomicBool,
    errors: &mpsc::UnboundedSender<std::io::Error>,
) {
    let (lock, ready) = slot;
    let mut rest_until = Instant::now();
    loop {
        let app = {
            let Ok(mut guard) = lock.lock() else { return };
            loop {
                if guard.closing {
                    return;
                }
                let resting = rest_until.saturating_duration_since(Instant::now());
                if resting.is_zero()
                    && let Some(app) = guard.next.take()
                {
                    break app;
                }
                // Resting with a view waiting: until the rest is over; else until one comes.
                let waited = match guard.next.is_some() {
                    true => ready.wait_timeout(guard, resting).ok().map(|(g, _)| g),
                    false => ready.wait(guard).ok(),
                };
                let Some(waited) = waited else { return };
                guard = waited;
            }
        };
        if !allowed.load(Ordering::SeqCst) {
            return;
        }
        let started = Instant::now();
        if let Err(e) = draw(&app) {
            let _ = errors.send(e);
            return;
        }
        let took = started.elapsed();
        rest_until = Instant::now() + (took * REST_FACTOR).min(MAX_REST);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::console::app::{App, AppConfig, Input};
    use crate::console::positions::PositionBook;

    fn view(width: u16) -> View {
        let mut app = App::new(AppConfig::for_tests(), PositionBook::new());
        app.handle(Input::Resize { width, height: 40 }, Instant::now());
        View::new(&app)
    }

    #[test]
    fn handing_over_a_view_never_waits_for_a_draw_and_the_newest_is_drawn() {
        let drawn = Arc::new(Mutex::new(Vec::new()));
        let seen = drawn.clone();
        let (started_tx, started) = std::sync::mpsc::channel();
        // Each draw holds until the test lets it finish.
        let (finish, finish_rx) = std::sync::mpsc::channel::<()>();
        let draw = move |view: &View| {
            let _ = started_tx.send(());
            let _ = finish_rx.recv_timeout(Duration::from_secs(5));
            seen.lock().expect("lock").push(view.screen.size.0);
            Ok(())
        };
        let (mut painter, _errors) =
            Painter::start(draw, Arc::new(AtomicBool::new(true))).expect("thread");
        painter.paint(view(1));
        started
            .recv_timeout(Duration::from_secs(5))
            .expect("the first draw began");
        // While that draw runs, two more views: handing them over does not wait for it.
        let handed = Instant::now();
        painter.paint(view(2));
        painter.paint(view(3));
        let took = handed.elapsed();
        assert!(took < Duration::from_millis(100), "paint waited {took:?}");
        finish.send(()).expect("draw 1");
        started
            .recv_timeout(Duration::from_secs(5))
            .expect("the next draw began");
        finish.send(()).expect("draw 2");
        painter.close(Duration::from_secs(5));
        assert_eq!(
            *drawn.lock().expect("lock"),
            [1, 3],
            "the view overtaken before it was drawn is skipped"
        );
    }

    #[test]
    fn a_failed_draw_is_reported_and_nothing_is_drawn_once_drawing_is_halted() {
        let draws = Arc::new(Mutex::new(0));
        let count = draws.clone();
        let draw = move |_: &View| {
            *count.lock().expect("lock") += 1;
            Err(std::io::Error::other("terminal gone"))
        };
        let (mut painter, mut errors) =
            Painter::start(draw, Arc::new(AtomicBool::new(true))).expect("thread");
        painter.paint(view(1));
        let error = errors.blocking_recv().expect("the error is reported");
        assert_eq!(error.to_string(), "terminal gone");
        painter.close(Duration::from_secs(5));
        assert_eq!(*draws.lock().expect("lock"), 1);

        let halted_draws = Arc::new(Mutex::new(0));
        let count = halted_draws.clone();
        let draw = move |_: &View| {
            *count.lock().expect("lock") += 1;
            Ok(())
        };
        let (mut painter, _errors) =
            Painter::start(draw, Arc::new(AtomicBool::new(false))).expect("thread");
        painter.paint(view(1));
        // Time for the thread to take the view before it is told to close.
        std::thread::sleep(Duration::from_millis(50));
        painter.close(Duration::from_secs(5));
        assert_eq!(
            *halted_draws.lock().expect("lock"),
            0,
            "drew after the halt"
        );
    }
}
