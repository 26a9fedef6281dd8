//! The console runtime's event loop, for tests that drive the state machine with a real arm
//! driver: arm events and ticks go into the app as the runtime would deliver them.

use tokio::sync::mpsc::UnboundedReceiver;
use tokio::time::Instant;

use std::time::Duration;

use armjog::console::app::{App, AppConfig, Effect, Input, KeyInput};
use armjog::console::jog::{KeyKind, ReleaseMode};
use armjog::console::keymap::{KeyName, Keymap};
use armjog::console::positions::PositionBook;
use armjog::link::driver::{Driver, DriverConfig};
use armjog::link::interface::ArmEvent;

/// The app the console's runtime builds for `config` (default keymap, key releases reported),
/// starting with `book`.
pub fn app_for(config: &DriverConfig, book: PositionBook) -> App {
    app_fenced(config, book, None)
}

/// [`app_for`] with an arm profile's fence.
pub fn app_fenced(
    config: &DriverConfig,
    book: PositionBook,
    fence: Option<armjog::link::fence::Fence>,
) -> App {
    App::new(
        AppConfig {
            keymap: Keymap::builtin("default").expect("keymap").into(),
            release_mode: ReleaseMode::Reported,
            refresh: Duration::from_millis(100),
            positions_on_operator: config.positions_on_operator(),
            max_jog_speed: config.max_jog_speed,
            joint_jog_speed: config.joint_jog_speed,
            frames: config.talos.is_none(),
            simulated: false,
            arm_name: None,
            home_action: config.modbus_home(),
            fence: fence.map(std::sync::Arc::new),

            config_file: None,

            new_profile: Vec::new(),

            recording_off: false,
        },
        book,
    )
}

/// A test console: an app, the driver's events, and what becomes of the app's effects.
pub trait Drives: Sized {
    fn app(&self) -> &App;
    fn events(&mut self) -> &mut UnboundedReceiver<ArmEvent>;
    /// Hands `input` to the app and carries out its effects.
    fn input(&mut self, input: Input);

    /// A key event, by the key's keymap name.
    fn key(&mut self, name: &str, kind: KeyKind) {
        let key: KeyName = name.parse().expect("key name");
        self.input(Input::Key(KeyInput {
            key,
            text: None,
            kind,
        }));
    }

    /// Runs the event loop (arm events and ticks) for `duration`, as the runtime would.
    async fn run_for(&mut self, duration: Duration) {
        let until = Instant::now() + duration;
        run_until_instant(self, until, |_| false).await;
    }

    /// Runs the event loop until `done` holds; panics after `within`.
    async fn run_until(&mut self, within: Duration, done: impl Fn(&Self) -> bool) {
        let until = Instant::now() + within;
        let met = run_until_instant(self, until, done).await;
        assert!(
            met,
            "condition not met within {within:?}; link {:?}",
            self.app().link()
        );
    }
}

/// Hands `input` to `app` and sends the commands it makes to `driver`, which must be running.
pub fn carry_out(app: &mut App, driver: &Driver, input: Input) {
    for effect in app.handle(input, std::time::Instant::now()) {
        if let Effect::Arm(command) = effect {
            assert!(driver.send(command), "driver alive");
        }
    }
}

/// Runs the loop until `done` holds (true) or `until` passes (false).
pub async fn run_until_instant<C: Drives>(
    console: &mut C,
    until: Instant,
    done: impl Fn(&C) -> bool,
) -> bool {
    loop {
        if done(console) {
            return true;
        }
        if Instant::now() >= until {
            return false;
        }
        let deadline = console
            .app()
            .next_deadline()
            .map(Instant::from_std)
            .unwrap_or(until)
            .min(until);
        // As the runtime does: events already in before a deadline are taken first, so a busy
        // machine does not make the link look stale.
        let input = tokio::select! {
            biased;
            event = console.events().recv() => Input::Arm(event.expect("driver events")),
            _ = tokio::time::sleep_until(deadline) => Input::Tick,
        };
        console.input(input);
    }
}

/// Row 1 of the whole console drawn at 120x30 from `view`: the status line.
pub fn status_line(view: &armjog::console::view::View) -> String {
    row_at_120(view, 1)
}

/// Row 0 of the whole console drawn at 120x30 from `view`: the link line and its badges.
pub fn status_line_0(view: &armjog::console::view::View) -> String {
    row_at_120(view, 0)
}

fn row_at_120(view: &armjog::console::view::View, row: u16) -> String {
    use armjog::console::ui::{self, Theme};
    use ratatui::{Terminal, backend::TestBackend};
    let mut terminal = Terminal::new(TestBackend::new(120, 30)).expect("terminal");
    terminal
        .draw(|f| ui::draw(f, view, &Theme { color: true }))
        .expect("draw");
    let buffer = terminal.backend().buffer();
    (0..120).map(|x| buffer[(x, row)].symbol()).collect()
}
