//! The arm view: snapshots at home and at a pose the simulated arm was jogged to, the drawn
//! tool point against the forward-kinematics tool point in both drawings, the trail's bounds
//! and ageing, and the notice over a link without telemetry.
//!
//! The app is driven through `App::handle` on a fake clock; the joint angles come from the
//! simulator's arm model (degrees 0-360, as the telemetry reports them).

use std::time::{Duration, Instant};

use armjog::console::app::{App, Input, TRAIL_CAPACITY, TRAIL_SPAN, TrailShade};
use armjog::console::jog::ReleaseMode;
use armjog::console::positions::PositionBook;
use armjog::console::ui::{self, Theme, arm_view};
use armjog::console::view::View;
use armjog::kortex::{ReferenceFrame, RegisterImage, Telemetry, gen3};
use armjog::link::interface::{ArmEvent, TelemetrySource};
use armjog::sim::arm_model::{Arm, SimMotion};
use nalgebra::Vector3;
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use ratatui::buffer::Buffer;
use ratatui::layout::Rect;

use crate::app_support::{self, app, ms, press};

/// The panel's size in the snapshots: the arm view's place at 160x48.
const WIDTH: u16 = 86;
const HEIGHT: u16 = 19;

/// Telemetry with the joints at `deg` (0-360) and nothing else of note.
fn telemetry(deg: [f64; 7]) -> Telemetry {
    let mut t = Telemetry::decode(&RegisterImage::default());
    t.robot_state = armjog::kortex::Coded::Known(armjog::kortex::RobotState::Ready);
    for (joint, angle) in t.joints.iter_mut().zip(deg) {
        joint.position = angle.rem_euclid(360.0) as f32;
    }
    t
}

/// The simulated arm at home, given a twist down, forward and to the left.
fn twisted_arm() -> Arm {
    let mut arm = Arm::default();
    let twist = SimMotion::Twist {
        linear: Vector3::new(0.05, 0.08, -0.1),
        angular: Vector3::zeros(),
        frame: ReferenceFrame::Base,
    };
    arm.command(twist, 0.0, false).expect("a reachable twist");
    arm
}

/// The simulated arm after 2 s of that twist.
fn jogged_joints() -> [f64; 7] {
    let mut arm = twisted_arm();
    arm.advance(2.0);
    arm.joints().map(f64::to_degrees)
}

/// A console over Modbus with telemetry at `deg` and two saved positions.
fn console_at(deg: [f64; 7]) -> (App, Instant) {
    let (mut app, t0) = app(ReleaseMode::Reported, false);
    let mut book = PositionBook::new();
    book.get_or_insert("pick").cartesian = Some([3000, -4000, 1000]);
    book.get_or_insert("tray").cartesian = Some([-2000, 5000, 2000]);
    app.handle(Input::PositionsLoaded(Ok(book)), t0);
    let events = [
        ArmEvent::TelemetrySource(TelemetrySource::Modbus),
        ArmEvent::Telemetry(Box::new(telemetry(deg))),
    ];
    for event in events {
        app.handle(Input::Arm(event), t0);
    }
    (app, t0)
}

fn panel(app: &App, width: u16, height: u16, theme: Theme) -> Terminal<TestBackend> {
    let mut terminal = Terminal::new(TestBackend::new(width, height)).expect("terminal");
    terminal
        .draw(|f| arm_view::draw(f, f.area(), &View::new(app), &theme))
        .expect("draw");
    terminal
}

const COLOR: Theme = Theme { color: true };

#[test]
fn at_home() {
    let (app, _) = console_at(gen3::HOME_DEG);
    insta::assert_snapshot!("arm_view_home", panel(&app, WIDTH, HEIGHT, COLOR).backend());
}

/// The arm jogged for 2 s, still jogging +X +Y: the trail behind the tool, the arrow ahead.
#[test]
fn at_a_jogged_pose_while_jogging() {
    let (mut app, t0) = console_at(gen3::HOME_DEG);
    // The path there, one telemetry snapshot every 100 ms.
    let mut arm = twisted_arm();
    for step in 1..=20 {
        arm.advance(0.1);
        let deg = arm.joints().map(f64::to_degrees);
        let t = Box::new(telemetry(deg));
        app.handle(Input::Arm(ArmEvent::Telemetry(t)), t0 + ms(100 * step));
    }
    let now = t0 + ms(2000);
    press(&mut app, "w", now);
    press(&mut app, "a", now);
    assert!(app.jog().is_jogging());
    assert_eq!(View::new(&app).arm.trail.len(), 21);
    let terminal = panel(&app, WIDTH, HEIGHT, COLOR);
    insta::assert_snapshot!("arm_view_jogged", terminal.backend());
    // The same pose as the 2 s twist in one go.
    let direct = gen3::tool_position(&jogged_joints().map(f64::to_radians));
    let stepped = gen3::tool_position(&arm.joints());
    assert!((direct - stepped).norm() < 1e-3);
}

/// The cells whose symbol is a full braille cell in the tool point's colour.
fn tool_cells(buffer: &Buffer, area: Rect) -> Vec<(u16, u16)> {
    let mut cells = Vec::new();
    for y in area.top()..area.bottom() {
        for x in area.left()..area.right() {
            let cell = &buffer[(x, y)];
            if cell.symbol() == "⣿" && cell.fg == arm_view::TOOL_COLOR {
                cells.push((x, y));
            }
        }
    }
    cells
}

/// The drawn tool point is in the cell the forward-kinematics tool point projects to, give or
/// take one, in both drawings, at several poses and panel sizes. The expected cell is worked
/// out here from the drawing's window alone, not with the panel's own mapping.
#[test]
fn the_drawn_tool_point_is_the_forward_kinematics_tool_point() {
    let poses = [
        gen3::HOME_DEG,
        jogged_joints(),
        [30.0, 40.0, 170.0, 250.0, 20.0, 70.0, 10.0],
        [300.0, 330.0, 180.0, 270.0, 0.0, 300.0, 0.0],
    ];
    for deg in poses {
        let tcp = gen3::tool_position(&deg.map(f64::to_radians));
        let (app, _) = console_at(deg);
        for (width, height) in [(WIDTH, HEIGHT), (116, 25), (60, 12)] {
            let terminal = panel(&app, width, height, COLOR);
            let inner = Rect::new(1, 1, width - 2, height - 2);
            for drawing in arm_view::drawings(inner) {
                let (x, y) = match drawing.projection {
                    arm_view::Projection::Top => (tcp.x, tcp.y),
                    arm_view::Projection::Side => (tcp.x, tcp.z),
                };
                let [left, right] = drawing.x_bounds;
                let [bottom, top] = drawing.y_bounds;
                let a = drawing.area;
                let column = f64::from(a.x) + (x - left) / (right - left) * f64::from(a.width);
                let row = f64::from(a.y) + (top - y) / (top - bottom) * f64::from(a.height);
                let found = tool_cells(terminal.backend().buffer(), a);
                assert_eq!(found.len(), 1, "{deg:?} {width}x{height}: {found:?}");
                let (cx, cy) = found[0];
                // The cell's centre within one cell of the point.
                assert!(
                    (f64::from(cx) + 0.5 - column).abs() <= 1.0
                        && (f64::from(cy) + 0.5 - row).abs() <= 1.0,
                    "{deg:?} {width}x{height} {:?}: drawn at {cx},{cy}, expected {column:.2},{row:.2}",
                    drawing.projection
                );
            }
        }
    }
}

#[test]
fn the_trail_keeps_the_last_ten_seconds_and_stays_bounded() {
    let (mut app, t0) = console_at(gen3::HOME_DEG);
    // 1 kHz telemetry for 15 s of motion along J1.
    for step in 1..=15_000u64 {
        let mut deg = gen3::HOME_DEG;
        deg[0] = step as f64 * 0.002;
        let t = Box::new(telemetry(deg));
        app.handle(Input::Arm(ArmEvent::Telemetry(t)), t0 + ms(step));
        assert!(app.trail_buffer().len() <= TRAIL_CAPACITY);
    }
    let now = t0 + ms(15_000);
    let trail = app.trail();
    assert!(
        trail.len() >= 190 && trail.len() <= TRAIL_CAPACITY,
        "{}",
        trail.len()
    );
    assert!(trail.iter().all(|(age, _)| *age <= TRAIL_SPAN));
    // The oldest point about 10 s old, the newest the last snapshot's tool point.
    let oldest = trail.first().expect("a trail").0;
    assert!(oldest >= TRAIL_SPAN - ms(100), "{oldest:?}");
    let (age, newest) = *trail.last().expect("a trail");
    assert!(age <= ms(50));
    let mut deg = gen3::HOME_DEG;
    deg[0] = 14_950.0 * 0.002;
    let tcp = gen3::tool_position(&deg.map(f64::to_radians));
    assert!(
        (Vector3::from(newest) - tcp).norm() < 0.01,
        "{newest:?} vs {tcp:?}"
    );
    // Without telemetry, the points age out as time goes by, the last after 10 s.
    app.handle(Input::Tick, now + Duration::from_secs(5));
    let half = app.trail().len();
    assert!(half > 80 && half < 120, "{half}");
    app.handle(Input::Tick, now + TRAIL_SPAN + ms(1));
    assert!(View::new(&app).arm.trail.is_empty());
}

#[test]
fn a_still_arms_trail_reads_the_same_from_one_report_to_the_next() {
    let (mut app, t0) = console_at(gen3::HOME_DEG);
    // 12 s of the same report at 30 Hz: the buffer holds 10 s of points, all in one place.
    let mut views = Vec::new();
    for step in 1..=360u64 {
        let report = ArmEvent::Telemetry(Box::new(telemetry(gen3::HOME_DEG)));
        app.handle(Input::Arm(report), t0 + ms(step * 33));
        if step > 300 {
            views.push(View::new(&app).arm.trail);
        }
    }
    assert!(app.trail_buffer().len() > 150);
    // One point per shade, oldest first, and the same in every frame.
    let shades: Vec<TrailShade> = views[0].iter().map(|(shade, _)| *shade).collect();
    assert_eq!(shades, [TrailShade::Old, TrailShade::Mid, TrailShade::New]);
    assert!(views.iter().all(|trail| *trail == views[0]));
    // Once the arm moves, the new points are there.
    let mut moved = gen3::HOME_DEG;
    moved[0] += 5.0;
    app.handle(
        Input::Arm(ArmEvent::Telemetry(Box::new(telemetry(moved)))),
        t0 + ms(360 * 33 + 50),
    );
    let trail = View::new(&app).arm.trail;
    assert_eq!(trail.len(), 4);
    assert_ne!(trail[3].1, trail[2].1);
}

#[test]
fn without_telemetry_the_arm_is_not_drawn() {
    let (mut app, t0) = app(ReleaseMode::AutoRepeat, true);
    app.handle(
        Input::Arm(ArmEvent::TelemetrySource(TelemetrySource::None)),
        t0,
    );
    let terminal = panel(&app, WIDTH, HEIGHT, COLOR);
    let text = app_support::buffer_text(terminal.backend().buffer());
    assert!(text.contains(arm_view::NO_TELEMETRY), "{text}");
    assert!(!text.chars().any(|c| ('\u{2801}'..='\u{28ff}').contains(&c)));
    insta::assert_snapshot!("arm_view_no_telemetry", terminal.backend());
}

/// On the whole screen at 200x60 the view is there, beside the arm and positions panels.
#[test]
fn the_full_screen_draws_the_view_on_a_large_terminal() {
    let (mut app, t0) = console_at(gen3::HOME_DEG);
    app.handle(
        Input::Resize {
            width: 200,
            height: 60,
        },
        t0,
    );
    let mut terminal = Terminal::new(TestBackend::new(200, 60)).expect("terminal");
    terminal
        .draw(|f| ui::draw(f, &View::new(&app), &COLOR))
        .expect("draw");
    let buffer = terminal.backend().buffer();
    let all = Rect::new(0, 0, 200, 60);
    assert_eq!(tool_cells(buffer, all).len(), 2);
    let text = app_support::buffer_text(buffer);
    assert!(text.contains("Arm view"));
}

/// A joint angle that is not a number draws nothing either: no arm at a made-up place.
#[test]
fn a_joint_angle_that_is_not_a_number_draws_no_arm() {
    let (mut app, t0) = console_at(gen3::HOME_DEG);
    let mut t = telemetry(gen3::HOME_DEG);
    t.joints[2].position = f32::NAN;
    app.handle(Input::Arm(ArmEvent::Telemetry(Box::new(t))), t0 + ms(100));
    let terminal = panel(&app, WIDTH, HEIGHT, COLOR);
    let text = app_support::buffer_text(terminal.backend().buffer());
    assert!(text.contains("not drawn"), "{text}");
    assert!(!text.chars().any(|c| ('\u{2801}'..='\u{28ff}').contains(&c)));
}
