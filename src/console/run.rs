//! The console's runtime: one `select!` over terminal, arm, timer and signal events, doing the
//! IO the app asks for. Frames are drawn on their own thread ([`super::painter`]), so keys never
//! wait for a draw. On quit, error, panic and signal the arm is told to stop, then the terminal
//! is restored.

use std::io::Write as _;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use futures::StreamExt;
use ratatui::Terminal;
use ratatui::backend::CrosstermBackend;

use super::app::{App, AppConfig, BookState, Effect, Input, Severity};
use super::audit::{self, AuditSession};
use super::book_io::{self, BookFiles};
use super::input;
use super::input_first;
use super::jog::ReleaseMode;
use super::keymap::Keymap;
use super::pacing::{self, FramePacer};
use super::painter::Painter;
use super::positions::{self, PositionBook};
use super::recorder::{self, Recorder};
use super::terminal;
use super::ui::{self, Theme};
use super::view::View;
use crate::link::driver::{Driver, DriverConfig, StopHandle};
use crate::link::interface::{ArmCommand, ArmEvent};
use crate::net::Deadline;

mod fence_writer;
mod inputs;

pub use inputs::key_input;
use inputs::{Signals, terminal_event};

/// Everything the console needs to start.
pub struct ConsoleSetup {
    pub driver: DriverConfig,
    pub keymap: Keymap,
    /// START re-send period while a jog key is held.
    pub refresh: Duration,
    /// `Some(true)` / `Some(false)` overrides the key-release probe.
    pub release_events: Option<bool>,
    pub positions_file: Option<PathBuf>,
    /// The book at `positions_file`, when it was read already (the built-in simulator's
    /// operator needed it before the console started): the console takes it instead of reading
    /// the file again.
    pub positions_read: Option<Result<positions::PositionBook, positions::BookError>>,
    /// The arm is the built-in simulator (no arm was named): the status bar says so.
    pub simulated: bool,
    /// The arm profile the console was opened with: its book and audit go by its name.
    pub arm_name: Option<String>,
    /// The arm profile's fence (`[arms.NAME.fence]`).
    pub fence: Option<Arc<crate::link::fence::Fence>>,
    /// Where the profiles are read from: a fence taught in the console is written there.
    pub config_file: Option<PathBuf>,
    /// A profile made by teaching a fence gets these settings (`AppConfig::new_profile`).
    pub new_profile: Vec<(String, String)>,
    /// Record the session (`recorder`), unless `--no-record`.
    pub record: bool,
}

/// Why the console could not run.
#[derive(Debug, thiserror::Error)]
pub enum ConsoleError {
    #[error("terminal: {0}")]
    Terminal(#[from] std::io::Error),
    #[error("{0}")]
    Positions(#[from] positions::BookError),
}

/// Runs the console until the technician quits.
pub async fn run(setup: ConsoleSetup) -> Result<(), ConsoleError> {
    let book_path = setup.positions_file.clone().or_else(|| {
        positions::default_path(&positions::book_key(
            setup.arm_name.as_deref(),
            &setup.driver.target(),
        ))
    });
    // Read off the event loop: the first frame and the keys do not wait for a big book.
    let book = match (book_path, setup.positions_read) {
        (Some(path), Some(read)) if Some(&path) == setup.positions_file.as_ref() => {
            BookFiles::open_read(path, read)?
        }
        (book_path, _) => BookFiles::open(book_path)?,
    };
    let frames = setup.driver.modbus.is_some() && setup.driver.talos.is_none();
    let positions_on_operator = setup.driver.positions_on_operator();
    let home_action = setup.driver.modbus_home();
    let max_jog_speed = setup.driver.max_jog_speed;
    let joint_jog_speed = setup.driver.joint_jog_speed;
    let arm = setup.driver.target();
    let (driver, arm_events) = Driver::spawn(setup.driver);

    let release_events = terminal::enter(setup.release_events)?;
    let drawing = Arc::new(AtomicBool::new(true));
    install_panic_hook(driver.stop_handle(), release_events, drawing.clone());
    let (result, book) = match start_painter(drawing) {
        Ok((painter, size, draw_errors)) => {
            let mut config = AppConfig {
                keymap: setup.keymap.into(),
                release_mode: if release_events {
                    ReleaseMode::Reported
                } else {
                    ReleaseMode::AutoRepeat
                },
                refresh: setup.refresh,
                positions_on_operator,
                max_jog_speed,
                joint_jog_speed,
                frames,
                simulated: setup.simulated,
                arm_name: setup.arm_name.clone(),
                home_action,
                fence: setup.fence.clone(),

                config_file: setup.config_file.clone(),

                new_profile: setup.new_profile.clone(),

                recording_off: false,
            };
            let mut recorder = setup
                .record
                .then(|| start_recorder(&config, &arm))
                .flatten();
            if let Some(recorder) = recorder.as_mut() {
                recorder.session(&config, &arm);
            }
            config.recording_off = recorder.is_none();
            let recording = recorder.as_ref().map(Recorder::path);
            let audit =
                AuditSession::start(&config, arm, setup.arm_name, audit::audit_dir(), recording);
            let parts = LoopParts {
                book,
                recorder,
                audit,
                driver: driver.clone(),
                arm_events,
                painter,
            };
            // A boxed task of its own: a key's wake-up polls the loop, not this set-up's deeper
            // stack frame, whose pages each cost a fault after a pause (`benches/key_pages.py`).
            let looped = tokio::spawn(Box::pin(loop_task(config, parts, size, draw_errors)));
            match looped.await {
                Ok((result, parts)) => {
                    // The arm is told to stop before waiting for the frame in progress.
                    driver.send(ArmCommand::Stop);
                    // Waited for off this thread: the driver and links on it carry the stop.
                    let mut painter = parts.painter;
                    let closed = tokio::task::spawn_blocking(move || {
                        painter.close(Duration::from_millis(500));
                    });
                    let _ = closed.await;
                    parts.audit.finish(Duration::from_secs(2)).await;
                    (result, Some(parts.book))
                }
                // The panic hook has stopped the arm and ends the process.
                Err(ended) if ended.is_panic() => std::panic::resume_unwind(ended.into_panic()),
                // Only a runtime shutting down cancels it; the book went with it.
                Err(ended) => (
                    Err(ConsoleError::Terminal(std::io::Error::other(format!(
                        "the console's loop ended early: {ended}"
                    )))),
                    None,
                ),
            }
        }
        Err(e) => (Err(e), Some(book)),
    };
    // Whatever happened, the arm is told to stop before the terminal is given back.
    driver.send(ArmCommand::Stop);
    terminal::restore(release_events);
    // A change saved just before quitting is written before the process ends.
    if let Some(book) = book {
        book.finish(Duration::from_secs(10)).await;
    }
    driver.shutdown().await;
    result
}

/// What the event loop's task owns while it runs, and gives back when it ends.
struct LoopParts {
    book: BookFiles,
    recorder: Option<Recorder>,
    audit: AuditSession,
    driver: Driver,
    arm_events: tokio::sync::mpsc::UnboundedReceiver<ArmEvent>,
    painter: Painter,
}

async fn loop_task(
    config: AppConfig,
    mut parts: LoopParts,
    size: (u16, u16),
    errors: tokio::sync::mpsc::UnboundedReceiver<std::io::Error>,
) -> (Result<(), ConsoleError>, LoopParts) {
    let result = event_loop(
        config,
        &mut parts.book,
        &mut parts.audit,
        &mut parts.recorder,
        &parts.driver,
        &mut parts.arm_events,
        Screen {
            painter: &parts.painter,
            size,
            errors,
        },
    )
    .await;
    (result, parts)
}

/// The drawing thread, the terminal's size, and the thread's draw errors.
type PainterStart = (
    Painter,
    (u16, u16),
    tokio::sync::mpsc::UnboundedReceiver<std::io::Error>,
);

fn start_painter(drawing: Arc<AtomicBool>) -> Result<PainterStart, ConsoleError> {
    let terminal = Terminal::new(CrosstermBackend::new(std::io::stdout()))?;
    let size = terminal.size()?;
    let theme = Theme::from_env();
    // Never dropped: ratatui's `Terminal` shows the cursor on drop and `eprintln!`s if it cannot,
    // which panics when the terminal has hung up (and stderr with it). `terminal::restore`
    // shows the cursor instead, whatever the terminal's state.
    let mut terminal = std::mem::ManuallyDrop::new(terminal);
    let draw = move |view: &View| {
        terminal
            .draw(|frame| ui::draw(frame, view, &theme))
            .map(|_| ())
    };
    let (painter, errors) = Painter::start(draw, drawing)?;
    Ok((painter, (size.width, size.height), errors))
}

/// What the event loop needs of the screen.
struct Screen<'a> {
    painter: &'a Painter,
    size: (u16, u16),
    errors: tokio::sync::mpsc::UnboundedReceiver<std::io::Error>,
}

/// On a panic anywhere: stop the arm, give the terminal back, report, and end the process; a
/// console that lost part of itself must not drive an arm. The hook does not wait on this thread
/// (it may be the driver's): a thread of its own waits while the runtime carries the stop.
fn install_panic_hook(stop: StopHandle, release_events: bool, drawing: Arc<AtomicBool>) {
    std::panic::set_hook(Box::new(move |info| {
        stop.stop();
        // No frame starts after this; one in progress ends within the wait.
        drawing.store(false, Ordering::SeqCst);
        let report = format!("armjog: {info}");
        let end = move || {
            std::thread::sleep(PANIC_STOP_WAIT);
            terminal::restore(release_events);
            tracing::error!("panic: {report}");
            // Not `eprintln!`, which panics when stderr is gone: this thread must reach the exit.
            let _ = writeln!(std::io::stderr(), "{report}");
            std::process::exit(101);
        };
        let started = std::thread::Builder::new()
            .name("armjog-panic".into())
            .spawn(end.clone());
        if started.is_err() {
            end();
        }
    }));
}

/// The session's recorder, in the audit folder, the old recordings pruned first; `None` (and a
/// warning in the log) when there is no folder or the file cannot be made.
fn start_recorder(config: &AppConfig, target: &str) -> Option<Recorder> {
    let dir = audit::audit_dir()?;
    let now = std::time::SystemTime::now();
    recorder::prune(&dir, time::OffsetDateTime::from(now).date());
    let arm = match (&config.arm_name, config.simulated) {
        (Some(name), _) => name.clone(),
        (None, true) => "sim".to_string(),
        (None, false) => target.replace(|c: char| !c.is_ascii_alphanumeric(), "-"),
    };
    let path = recorder::file_for(&dir, now, &arm);
    match Recorder::start(path.clone(), recorder::QUEUE) {
        Ok(recorder) => Some(recorder),
        Err(e) => {
            tracing::warn!("recording off: cannot record into {}: {e}", path.display());
            None
        }
    }
}

/// How long a panic waits for the stop before the terminal is restored and the process ends.
const PANIC_STOP_WAIT: Duration = Duration::from_millis(200);

async fn event_loop(
    config: AppConfig,
    book: &mut BookFiles,
    audit: &mut AuditSession,
    recorder: &mut Option<Recorder>,
    driver: &Driver,
    arm_events: &mut tokio::sync::mpsc::UnboundedReceiver<ArmEvent>,
    mut screen: Screen<'_>,
) -> Result<(), ConsoleError> {
    let mut app = App::new(config, PositionBook::new());
    if let Some(path) = &book.path {
        app.begin_loading_positions(path.display().to_string());
    }
    app.handle(
        Input::Resize {
            width: screen.size.0,
            height: screen.size.1,
        },
        Instant::now(),
    );
    // Read by the console itself: every readable byte is decoded on each wake (see `input`).
    let mut keys = input::open()?;
    let mut signals = Signals::new()?;
    let mut fence_writer = fence_writer::FenceWriter::new();
    let mut pacer = FramePacer::default();
    pacer.changed(false, &app, Instant::now());
    // One timer for the app's deadline, the next frame and the audit's hand-over: a key moves
    // two of them, and each timer moved earlier costs the runtime a wake-up of its own.
    let mut timer = Deadline::new();
    loop {
        let deadline = app.next_deadline();
        let paint_at = pacer.due_at();
        let audit_at = audit.hand_over_at();
        let earliest = [deadline, paint_at, audit_at].into_iter().flatten().min();
        timer.set(earliest.map(tokio::time::Instant::from_std));
        let input = tokio::select! {
            biased;
            signal = signals.next() => Some(Input::Signal(signal)),
            event = keys.next() => terminal_event(event),
            event = arm_events.recv() => match event {
                Some(event) => Some(Input::Arm(event)),
                None => Some(Input::Signal("arm driver ended")),
            },
            loaded = book_io::loaded(&mut book.loading) => Some(Input::PositionsLoaded(loaded)),
            _ = timer.fired(), if timer.armed() => {
                let now = Instant::now();
                // The timer fired for the earliest, whatever the clock's rounding.
                let fired = earliest.map_or(now, |earliest| now.max(earliest));
                let due = |at: Option<Instant>| at.is_some_and(|at| at <= fired);
                if due(deadline) {
                    // A release already typed goes before a refresh decided without it.
                    let refresh_due = app.jog().refresh_due(now);
                    // Read and not yet taken, or readable on the terminal now.
                    let arrived = refresh_due && keys.input_arrived();
                    match input_first::waiting_input(refresh_due, || arrived, &mut keys).await {
                        Some(event) => terminal_event(event),
                        None => Some(Input::Tick),
                    }
                } else {
                    // Not in a key's burst: its STOP's receiver runs first (see `audit::writer`).
                    if due(audit_at) {
                        audit.hand_over();
                    }
                    // Built once for the drawing thread: this task goes straight back to keys.
                    if due(paint_at)
                        && let Some(view) = pacer.frame(View::new(&app), now)
                    {
                        screen.painter.paint(view);
                    }
                    None
                }
            }
            Some(outcome) = book.save_outcomes.recv() => Some(Input::PositionsSaved(outcome)),
            Some(outcome) = fence_writer.outcomes.recv() => {
                fence_writer.ended();
                Some(Input::FenceSaved(outcome))
            }
            Some(e) = screen.errors.recv() => {
                audit.record_handled();
                return Err(ConsoleError::Terminal(e));
            }
            // Shown, and kept in the command log; the console goes on.
            Some(reason) = audit.next_error() => {
                app.say(reason.clone(), Severity::Warning, Instant::now());
                Some(Input::Arm(audit::session::failure_log_line(reason)))
            }
        };
        let Some(input) = input else {
            // The last input's frames went out while this task waited: its records are made now.
            audit.record_handled();
            continue;
        };
        // The records of the input before this one are made once this one's frames are out
        // (`handled`), or before anything this one records (`input`, `book_saved`).
        let report = pacing::is_routine_report(&input);
        let now = Instant::now();
        audit.input(&input);
        if let Some(recorder) = recorder.as_mut() {
            recorder.input(&input);
        }
        let mut sent = false;
        let effects = app.handle(input, now);
        for effect in effects {
            match effect {
                Effect::Arm(command) => {
                    if !driver.send(command.clone()) {
                        app.say("the arm driver has stopped", Severity::Error, now);
                    }
                    if let Some(recorder) = recorder.as_mut() {
                        recorder.command(&command);
                    }
                    audit.command(command);
                    sent = true;
                }
                // Written on the writer's thread; the outcome comes back as `save_outcomes`.
                Effect::SavePositions(save) => {
                    audit.book_saved(&save.book, &save.known);
                    book.save(save);
                }
                // Written off the loop, one at a time; the outcome comes back as `outcomes`.
                Effect::SaveFence(change) => {
                    audit.fence_changed(&change);
                    fence_writer.write(*change);
                }
                Effect::Quit => {
                    audit.handled(&app);
                    audit.record_handled();
                    // Changes made while the book loads are written once it has loaded.
                    if matches!(app.book_state(), BookState::Loading { .. }) {
                        book.hold_until_loaded(app.positions().clone());
                    }
                    return Ok(());
                }
            }
        }
        // The driver and the links (on this thread) write the frames before this loop polls
        // everything it waits on again (figures in docs/development.md).
        if sent {
            tokio::task::yield_now().await;
        }
        // After the frames: the recorder's queue never comes before one.
        if let Some(recorder) = recorder.as_mut() {
            recorder.said(app.message());
            recorder.fence(app.fence_text());
            recorder.hand_over();
        }
        audit.handled(&app);
        // Inputs that never let the loop rest (a flood) do not hold the records for ever.
        if audit.hand_over_at().is_some_and(|at| at <= now) {
            audit.hand_over();
        }
        // A report that made the app send something (a stop from the cap watch or another
        // client's motion) is not routine: drawn at the live rate, as any other change.
        pacer.changed(report && !sent, &app, now);
    }
}
