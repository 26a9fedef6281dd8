//! Render time of a full console frame (target: under 2 ms at 200x60), on a console that
//! changes every frame as it does while an arm moves: each frame feeds the app what the driver
//! sends per telemetry poll (a new telemetry snapshot from the simulated Gen3 orbiting its base,
//! a latency, a counted poll log line) and a jog key's auto-repeat, at a fake clock advancing
//! 33 ms, then builds the [`View`] and draws the whole screen through the same ratatui path the
//! console's painter uses (crossterm escape sequences, here written into memory).
//!
//! It draws whatever `ui::draw` draws: panels added later are measured without a change here.

use std::cell::Cell;
use std::io::Write;
use std::rc::Rc;
use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group, criterion_main};
use ratatui::backend::CrosstermBackend;
use ratatui::layout::Rect;
use ratatui::{Terminal, TerminalOptions, Viewport};

use armjog::console::app::{App, AppConfig, Input, KeyInput};
use armjog::console::jog::{KeyKind, ReleaseMode};
use armjog::console::keymap::{KeyName, Keymap};
use armjog::console::positions::PositionBook;
use armjog::console::ui::{self, Theme};
use armjog::console::view::View;
use armjog::kortex::Telemetry;
use armjog::link::driver::hw_telemetry;
use armjog::link::interface::{ArmEvent, LinkStatus, LogEntry, Traffic};
use armjog::sim::arm_model::{Arm, SimMotion};
use armjog::sim::telemetry::{actuator_feedback, arm_state};

/// The telemetry period the console sees at 30 Hz, and the fake clock's step per frame.
const PERIOD: Duration = Duration::from_millis(33);
/// Precomputed telemetry: 10 s of the arm orbiting its base, replayed in a loop.
const SNAPSHOTS: usize = 300;

/// What the simulated arm reports every 33 ms while it orbits its base at 0.6 rad/s (about a
/// full turn in the 10 s replayed), so every joint angle, the tool pose and the efforts change.
fn orbiting_telemetry() -> Vec<Telemetry> {
    let mut arm = Arm::default();
    arm.command(
        SimMotion::Polar {
            azimuth: 0.6,
            altitude: 0.0,
        },
        0.0,
        false,
    )
    .expect("the orbit is reachable from home");
    (0..SNAPSHOTS)
        .map(|_| {
            arm.advance(PERIOD.as_secs_f64());
            let snapshot = arm.snapshot();
            let feedback: Vec<_> = (1..=7).map(|j| actuator_feedback(&snapshot, j)).collect();
            hw_telemetry::telemetry(&arm_state(&snapshot), &feedback)
        })
        .collect()
}

/// A busy console replaying telemetry: a full log, positions, hex frames, a jog key held.
struct Scene {
    app: App,
    now: Instant,
    telemetry: Vec<Telemetry>,
    frame: usize,
}

impl Scene {
    fn new() -> Scene {
        let mut app = App::new(
            AppConfig {
                keymap: Keymap::builtin("default").expect("keymap").into(),
                release_mode: ReleaseMode::AutoRepeat,
                refresh: Duration::from_millis(100),
                positions_on_operator: true,
                max_jog_speed: 0.25,
                joint_jog_speed: armjog::link::driver::JOINT_JOG_SPEED,
                frames: false,
                simulated: false,
                arm_name: None,
                home_action: None,
                fence: None,

                config_file: None,

                new_profile: Vec::new(),

                recording_off: false,
            },
            PositionBook::new(),
        );
        let now = Instant::now();
        let telemetry = orbiting_telemetry();
        let events = [
            ArmEvent::Status(LinkStatus::Up {
                description: "talos 127.0.0.1:61616 (icd, crc16), operator 1.0".into(),
            }),
            ArmEvent::Telemetry(Box::new(telemetry[0].clone())),
            ArmEvent::Speed(50),
            ArmEvent::Latency(Duration::from_micros(420)),
        ];
        for event in events {
            app.handle(Input::Arm(event), now);
        }
        for i in 0..200u32 {
            app.handle(Input::Arm(ArmEvent::Log(command_line(i))), now);
        }
        let mut book = PositionBook::new();
        for name in ["bench", "pick", "place", "home2", "camera"] {
            book.get_or_insert(name).cartesian = Some([4566, 10, 4338]);
        }
        app.handle(Input::PositionsLoaded(Ok(book)), now);
        app.handle(key('H'), now);
        assert!(app.hex());
        Scene {
            app,
            now,
            telemetry,
            frame: 0,
        }
    }

    /// One telemetry period later: what the driver sends per poll, and the held key's repeat.
    fn advance(&mut self) {
        self.frame += 1;
        self.now += PERIOD;
        let i = self.frame % self.telemetry.len();
        let latency = Duration::from_micros(300 + (self.frame as u64 * 37) % 400);
        let poll = LogEntry {
            poll: true,
            count: 1,
            name: "modbus poll".into(),
            outcome: "OK".into(),
            ok: true,
            latency: Some(latency),
            ..LogEntry::default()
        };
        let inputs = [
            Input::Arm(ArmEvent::Log(poll)),
            Input::Arm(ArmEvent::Telemetry(Box::new(self.telemetry[i].clone()))),
            Input::Arm(ArmEvent::Latency(latency)),
            key('w'),
            Input::Tick,
        ];
        for input in inputs {
            self.app.handle(input, self.now);
        }
    }
}

fn key(c: char) -> Input {
    Input::Key(KeyInput {
        key: KeyName::char(c),
        text: Some(c),
        kind: KeyKind::Press,
    })
}

/// A technician's command and its reply, as the Talos link logs them.
fn command_line(i: u32) -> LogEntry {
    LogEntry {
        poll: false,
        count: 1,
        id: Some(i * 2),
        name: "cart_start".into(),
        outcome: "OK".into(),
        ok: true,
        latency: Some(Duration::from_micros(400)),
        traffic: Traffic::Talos {
            request: vec![
                0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x06, 0x00, 0x03, 0x01, 0x00, 0x00, 0x4A,
                0x9D,
            ],
            reply: Some(vec![
                0x00, 0x00, 0x00, 0x03, 0x00, 0x00, 0x80, 0x06, 0x00, 0x02, 0x00, 0x00, 0x55, 0x21,
            ]),
        },
    }
}

/// The terminal's output, counted (in a count the bench keeps) and then dropped.
struct Output {
    bytes: Rc<Cell<usize>>,
}

impl Write for Output {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.bytes.set(self.bytes.get() + buf.len());
        Ok(buf.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// A terminal of a fixed size drawing through crossterm, as the console's painter does.
fn terminal(width: u16, height: u16, bytes: Rc<Cell<usize>>) -> Terminal<CrosstermBackend<Output>> {
    Terminal::with_options(
        CrosstermBackend::new(Output { bytes }),
        TerminalOptions {
            viewport: Viewport::Fixed(Rect::new(0, 0, width, height)),
        },
    )
    .expect("terminal")
}

fn draw(terminal: &mut Terminal<CrosstermBackend<Output>>, scene: &Scene, theme: &Theme) {
    terminal
        .draw(|frame| ui::draw(frame, &View::new(&scene.app), theme))
        .expect("draw");
}

fn render(c: &mut Criterion) {
    let theme = Theme { color: true };
    for (w, h) in [(200u16, 60u16), (80, 24)] {
        let mut scene = Scene::new();
        scene.app.handle(
            Input::Resize {
                width: w,
                height: h,
            },
            scene.now,
        );
        let bytes = Rc::new(Cell::new(0));
        let mut terminal = terminal(w, h, bytes.clone());
        // The screen's share of each frame: how much of it changes, in bytes sent.
        draw(&mut terminal, &scene, &theme);
        let first = bytes.get();
        for _ in 0..SNAPSHOTS {
            scene.advance();
            draw(&mut terminal, &scene, &theme);
        }
        let per_frame = (bytes.get() - first) / SNAPSHOTS;
        println!("{w}x{h}: first frame {first} bytes, then {per_frame} bytes a frame on average");
        c.bench_function(
            &format!("changing frame {w}x{h} (feed + view + draw)"),
            |b| {
                b.iter(|| {
                    scene.advance();
                    draw(&mut terminal, &scene, &theme);
                })
            },
        );
        c.bench_function(&format!("feed only {w}x{h}"), |b| {
            b.iter(|| scene.advance())
        });
    }
}

criterion_group!(benches, render);
criterion_main!(benches);
