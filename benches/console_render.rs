//! Render time of a full console frame (target: under 2 ms at 200x60, the arm view drawn with
//! a full 10 s trail).

use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group, criterion_main};
use ratatui::Terminal;
use ratatui::backend::TestBackend;

use armjog::console::app::{App, AppConfig, Input, KeyInput};
use armjog::console::jog::{KeyKind, ReleaseMode};
use armjog::console::keymap::{KeyName, Keymap};
use armjog::console::positions::PositionBook;
use armjog::console::ui::{self, Theme};
use armjog::console::view::View;
use armjog::kortex::ReferenceFrame;
use armjog::link::driver::hw_telemetry;
use armjog::link::interface::{ArmEvent, LinkStatus, LogEntry, Traffic};
use armjog::sim::arm_model::{Arm, SimMotion};
use armjog::sim::telemetry::{actuator_feedback, arm_state};
use nalgebra::Vector3;

/// A busy console: telemetry, a full log, positions, a jog in progress.
fn busy_app() -> App {
    let mut app = App::new(
        AppConfig {
            keymap: Keymap::builtin("default").expect("keymap"),
            release_mode: ReleaseMode::AutoRepeat,
            refresh: Duration::from_millis(100),
            positions_on_operator: true,
            max_jog_speed: 0.25,
            frames: false,
        },
        PositionBook::new(),
    );
    let now = Instant::now();
    let snapshot = Arm::default().snapshot();
    let feedback: Vec<_> = (1..=7).map(|j| actuator_feedback(&snapshot, j)).collect();
    let telemetry = hw_telemetry::telemetry(&arm_state(&snapshot), &feedback);
    let events = [
        ArmEvent::Status(LinkStatus::Up {
            description: "talos 127.0.0.1:61616 (icd, crc16), operator 1.0".into(),
        }),
        ArmEvent::Telemetry(Box::new(telemetry)),
        ArmEvent::Speed(50),
        ArmEvent::Latency(Duration::from_micros(420)),
    ];
    for event in events {
        app.handle(Input::Arm(event), now);
    }
    // 10 s of motion at 20 Hz: the arm view draws a full trail.
    let mut arm = Arm::default();
    let twist = SimMotion::Twist {
        linear: Vector3::new(0.02, 0.03, -0.02),
        angular: Vector3::zeros(),
        frame: ReferenceFrame::Base,
    };
    arm.command(twist, 0.0, false).expect("a reachable twist");
    for step in 1..=200u64 {
        arm.advance(0.05);
        let snapshot = arm.snapshot();
        let feedback: Vec<_> = (1..=7).map(|j| actuator_feedback(&snapshot, j)).collect();
        let telemetry = hw_telemetry::telemetry(&arm_state(&snapshot), &feedback);
        let at = now + Duration::from_millis(50 * step);
        app.handle(Input::Arm(ArmEvent::Telemetry(Box::new(telemetry))), at);
    }
    let now = now + Duration::from_secs(10);
    for i in 0..200u32 {
        let entry = LogEntry {
            poll: false,
            count: 1,
            id: Some(i * 2),
            name: "cart_start".into(),
            outcome: "OK".into(),
            ok: true,
            latency: Some(Duration::from_micros(400)),
            traffic: Traffic::Talos {
                request: vec![
                    0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x06, 0x00, 0x03, 0x01, 0x00, 0x00,
                    0x4A, 0x9D,
                ],
                reply: Some(vec![
                    0x00, 0x00, 0x00, 0x03, 0x00, 0x00, 0x80, 0x06, 0x00, 0x02, 0x00, 0x00, 0x55,
                    0x21,
                ]),
            },
        };
        app.handle(Input::Arm(ArmEvent::Log(entry)), now);
    }
    let mut book = PositionBook::new();
    for name in ["bench", "pick", "place", "home2", "camera"] {
        book.get_or_insert(name).cartesian = Some([4566, 10, 4338]);
    }
    app.handle(Input::PositionsLoaded(Ok(book)), now);
    app.handle(
        Input::Key(KeyInput {
            key: KeyName::char('H'),
            text: Some('H'),
            kind: KeyKind::Press,
        }),
        now,
    );
    assert!(app.hex());
    app
}

fn render(c: &mut Criterion) {
    let app = busy_app();
    let theme = Theme { color: true };
    for (w, h) in [(200u16, 60u16), (80, 24)] {
        let mut terminal = Terminal::new(TestBackend::new(w, h)).expect("terminal");
        if w == 200 {
            terminal
                .draw(|frame| ui::draw(frame, &View::new(&app), &theme))
                .expect("draw");
            let text: String = terminal
                .backend()
                .buffer()
                .content()
                .iter()
                .map(|c| c.symbol())
                .collect();
            assert!(
                text.contains("Arm view"),
                "the 200x60 frame draws the arm view"
            );
            assert!(View::new(&app).trail.len() >= 190, "a full trail");
        }
        c.bench_function(&format!("render full frame {w}x{h}"), |b| {
            b.iter(|| {
                terminal
                    .draw(|frame| ui::draw(frame, &View::new(&app), &theme))
                    .expect("draw");
            })
        });
    }
}

criterion_group!(benches, render);
criterion_main!(benches);
