//! The whole screen at every size from the minimum to 200x60: no number is ever cut. Each
//! number either shows whole or its column or panel is absent; snapshots at 62x20, 80x24,
//! 120x40 and 200x60, and the status bar using the full width in step mode.
//!
//! The state is built through `App::handle` on a fake clock, from realistic telemetry with
//! numbers a cut would change: J3 at 180.00, J1 just below zero (359.66 reported), a TCP at
//! x -1234.56 mm, a link on port 44718.

use std::collections::BTreeSet;
use std::time::{Duration, Instant};

use armjog::console::app::{App, AppConfig, Input, MIN_HEIGHT, MIN_WIDTH};
use armjog::console::jog::{JogMotion, ReleaseMode};
use armjog::console::keymap::Keymap;
use armjog::console::positions::PositionBook;
use armjog::console::ui::{self, Theme};
use armjog::console::view::View;
use armjog::kortex::{
    ActionState, ActionStatus, ArmHealth, Coded, ControlCoil, FlagSet, JointState, MoveType, Pose,
    RobotState, SpeedLimits, Telemetry, ToolState, Twist, Wrench,
};
use armjog::link::interface::{
    ArmCommand, ArmEvent, LinkStatus, LogEntry, TelemetrySource, Traffic,
};
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use ratatui::buffer::Buffer;

use crate::app_support::{ms, press};

const LINK: &str = "talos 127.0.0.1:44718 (icd, crc16), operator 1.0";

/// The arm a little off home, J1 just below zero, the TCP at negative x and z; `moving`: on
/// its way along +X.
fn telemetry(moving: bool) -> Telemetry {
    let speed = if moving { 1.0 } else { 0.0 };
    let positions = [359.66, 15.0, 180.0, 230.0, 0.0, 55.0, 90.0];
    let joints = std::array::from_fn(|i| JointState {
        position: positions[i],
        velocity: [-0.001, 0.0, 0.25 * speed, 0.0, -12.5 * speed, 0.0, 0.0][i],
        torque: [0.0, -12.5, 0.25, 6.75, -0.004, 1.5, 0.0][i],
        current: [0.1, 1.2, 0.3, 0.9, 0.1, 0.4, 0.05][i],
        temperature: 30.0 + i as f32 * 0.5,
    });
    Telemetry {
        robot_state: Coded::Known(RobotState::Ready),
        faults: FlagSet::EMPTY,
        warnings: FlagSet::EMPTY,
        arm: ArmHealth {
            current: 1.25,
            voltage: 24.1,
            cpu_temperature: 45.5,
            ambient_temperature: 28.0,
        },
        joints,
        tcp: ToolState {
            pose: Pose {
                x: -1.23456,
                y: 0.3456,
                z: -0.0789,
                theta_x: 90.0,
                theta_y: -0.001,
                theta_z: 179.5,
            },
            twist: Twist {
                x: 0.0321 * speed,
                y: -0.0004,
                ..Twist::ZERO
            },
            wrench: Wrench {
                force_x: 0.02,
                force_y: -4.91,
                force_z: 0.11,
                torque_x: 0.0,
                torque_y: -0.002,
                torque_z: 0.03,
            },
        },
        action: ActionState {
            status: Coded::Known(ActionStatus::Completed),
            id: 7,
            move_type: Coded::Known(MoveType::Twist),
        },
        speed_limits: SpeedLimits {
            linear: 0.25,
            angular: 30.0,
        },
        control: Coded::Known(ControlCoil::Abort),
        state_from_inputs: Some(RobotState::Ready),
    }
}

fn log_entry(id: u32, name: &str, outcome: &str, ok: bool, micros: Option<u64>) -> LogEntry {
    LogEntry {
        count: 1,
        id: Some(id),
        name: name.into(),
        outcome: outcome.into(),
        ok,
        latency: micros.map(Duration::from_micros),
        traffic: Traffic::None,
        ..LogEntry::default()
    }
}

/// A console on a live arm: link up, telemetry, speed, a log and a book of positions.
fn live_app(mode: ReleaseMode, frames: bool) -> (App, Instant) {
    let config = AppConfig {
        keymap: Keymap::builtin("default").expect("default keymap").into(),
        release_mode: mode,
        refresh: ms(100),
        positions_on_operator: !frames,
        max_jog_speed: 0.25,
        joint_jog_speed: armjog::link::driver::JOINT_JOG_SPEED,
        frames,
        simulated: false,
        arm_name: None,
        home_action: None,
        fence: None,

        config_file: None,

        new_profile: Vec::new(),

        recording_off: false,
    };
    let mut app = App::new(config, PositionBook::new());
    let t0 = Instant::now();
    let mut book = PositionBook::new();
    book.get_or_insert("home").cartesian = Some([4566, 10, 4338]);
    book.get_or_insert("tray").cartesian = Some([-12346, -5432, 1234]);
    let long = book.get_or_insert("a-very-long-position-name-over-the-tray");
    long.cartesian = Some([-3000, 2999, -45]);
    long.anchor = true;
    long.parent = Some("tray".into());
    app.handle(Input::PositionsLoaded(Ok(book)), t0);
    let events = [
        ArmEvent::Status(LinkStatus::Up {
            description: LINK.into(),
        }),
        ArmEvent::TelemetrySource(TelemetrySource::TalosHardware),
        ArmEvent::Telemetry(Box::new(telemetry(false))),
        ArmEvent::Latency(Duration::from_micros(1234)),
        ArmEvent::Speed(50),
        ArmEvent::Log(log_entry(1, "get_speed", "OK", true, Some(812))),
        ArmEvent::Log(log_entry(2, "goto", "UNKNOWN_POSITION", false, Some(977))),
        ArmEvent::Log(log_entry(
            3,
            "cart_stop",
            "no reply within 500 ms",
            false,
            None,
        )),
    ];
    for event in events {
        app.handle(Input::Arm(event), t0);
    }
    (app, t0)
}

/// `w` held with no release events: a 500 ms onset and 40 ms repeats (25 Hz), the arm
/// answering and reporting meanwhile.
fn jogging_app() -> (App, Instant) {
    let (mut app, t0) = live_app(ReleaseMode::AutoRepeat, false);
    for at in [0, 500, 540, 580, 620] {
        let now = t0 + ms(at);
        app.handle(
            Input::Arm(ArmEvent::Telemetry(Box::new(telemetry(true)))),
            now,
        );
        press(&mut app, "w", now);
        let start = ArmCommand::Jog(JogMotion::Cartesian { x: 1, y: 0, z: 0 });
        app.handle(Input::Arm(ArmEvent::Done { command: start }), now);
    }
    assert!(app.jog().is_jogging());
    (app, t0 + ms(620))
}

/// Over Modbus (frames shown) in step mode with the largest step, full speed, mixed frame and
/// a measured auto-repeat.
fn step_app() -> (App, Instant) {
    let (mut app, t0) = live_app(ReleaseMode::AutoRepeat, true);
    app.handle(Input::Arm(ArmEvent::Speed(100)), t0);
    for at in [0, 500, 540, 580] {
        let now = t0 + ms(at);
        app.handle(
            Input::Arm(ArmEvent::Telemetry(Box::new(telemetry(true)))),
            now,
        );
        press(&mut app, "w", now);
        let start = ArmCommand::Jog(JogMotion::Cartesian { x: 1, y: 0, z: 0 });
        app.handle(Input::Arm(ArmEvent::Done { command: start }), now);
    }
    let later = t0 + ms(2000);
    app.handle(Input::Tick, later);
    app.handle(Input::Arm(ArmEvent::StopConfirmed), later);
    app.handle(
        Input::Arm(ArmEvent::Telemetry(Box::new(telemetry(false)))),
        later,
    );
    for key in ["g", "g", "t", ".", ".", ".", ".", ".", "."] {
        press(&mut app, key, later);
    }
    assert!(!app.jog().is_jogging());
    (app, later)
}

fn screen(app: &App, width: u16, height: u16) -> Terminal<TestBackend> {
    let mut terminal = Terminal::new(TestBackend::new(width, height)).expect("terminal");
    terminal
        .draw(|f| ui::draw(f, &View::new(app), &Theme { color: true }))
        .expect("draw");
    terminal
}

fn rows(buffer: &Buffer) -> Vec<String> {
    let width = usize::from(buffer.area.width);
    buffer
        .content()
        .chunks(width)
        .map(|row| row.iter().map(|c| c.symbol()).collect())
        .collect()
}

/// Every run of digits, points and minus signs with a digit in it: the numbers on screen.
fn numbers_in(row: &str) -> Vec<String> {
    let mut tokens = Vec::new();
    let mut current = String::new();
    for c in row.chars().chain([' ']) {
        if c.is_ascii_digit() || c == '.' || c == '-' {
            current.push(c);
        } else {
            let token = current.trim_end_matches('.').trim_start_matches('.');
            if token.chars().any(|c| c.is_ascii_digit()) {
                tokens.push(token.to_string());
            }
            current.clear();
        }
    }
    tokens
}

/// The numbers on a screen.
fn numbers_on(rows: &[String]) -> BTreeSet<String> {
    rows.iter().flat_map(|r| numbers_in(r)).collect()
}

/// Every size from the minimum to 200 wide, at a few heights.
fn sizes() -> impl Iterator<Item = (u16, u16)> {
    [MIN_HEIGHT, 13, 20, 24, 40]
        .into_iter()
        .flat_map(|h| (MIN_WIDTH..=200).map(move |w| (w, h)))
}

/// At every size, each number on screen is one the full-size screen shows whole (a cut
/// number is a number the full screen does not show: `80.00` from `180.00`, `447` from
/// `44718`); the figures of a panel on screen are all there; and the status bar always shows
/// the motion and the key-release mode.
fn check_every_size(app: &App, motion: &str, mode: &str, link: &str) {
    let whole = numbers_on(&rows(screen(app, 200, 60).backend().buffer()));
    for expected in [
        "180.00", "-0.34", "-1234.6", "345.6", "-78.9", "44718", "-4.91",
    ] {
        assert!(
            whole.contains(expected),
            "{expected} not at 200x60: {whole:?}"
        );
    }
    for (width, height) in sizes() {
        let rows = rows(screen(app, width, height).backend().buffer());
        let text = rows.join("\n");
        for number in numbers_on(&rows) {
            assert!(
                whole.contains(&number),
                "{width}x{height}: {number} is not a whole number of the screen:\n{text}"
            );
            assert!(
                !number.starts_with("-0") || !number.trim_start_matches(['-', '0', '.']).is_empty(),
                "{width}x{height}: negative zero {number}:\n{text}"
            );
        }
        // A row of the tool panel on screen shows its three figures.
        for row in &rows {
            let figures: &[&str] = if row.contains("│pos mm") || row.contains("│mm ") {
                &["-1234.6", "345.6", "-78.9"]
            } else if row.contains("│force N") || row.contains("│N ") {
                &["0.02", "-4.91", "0.11"]
            } else {
                &[]
            };
            for figure in figures {
                assert!(
                    row.contains(figure),
                    "{width}x{height}: no {figure}:\n{text}"
                );
            }
        }
        if text.contains("│J3") {
            assert!(text.contains("180.00"), "{width}x{height}: J3 cut:\n{text}");
        }
        if text.contains("│J1") {
            assert!(text.contains("-0.34"), "{width}x{height}: J1 cut:\n{text}");
        }
        assert!(rows[1].contains(motion), "{width}x{height}: {}", rows[1]);
        assert!(rows[1].contains(mode), "{width}x{height}: {}", rows[1]);
        assert!(rows[0].contains(link), "{width}x{height}: {}", rows[0]);
    }
}

#[test]
fn no_number_is_cut_at_any_size_while_jogging() {
    let (app, _) = jogging_app();
    check_every_size(&app, "JOG +X", "auto-repeat", "LINK UP");
}

#[test]
fn no_number_is_cut_at_any_size_in_step_mode() {
    let (app, _) = step_app();
    check_every_size(&app, "STEP 100.0 mm / 30 deg", "auto-repeat", "LINK UP");
}

/// The link went silent mid-jog: the link, the telemetry and the motion are all in doubt, and
/// every panel title carries an age.
#[test]
fn no_number_is_cut_at_any_size_with_a_stale_link() {
    let (mut app, t) = jogging_app();
    app.handle(Input::Tick, t + ms(2500));
    assert!(!app.jog().is_jogging());
    check_every_size(&app, "MAY BE MOVING", "auto-repeat", "LINK STALE 2.5 s");
}

#[test]
fn the_link_line_is_never_cut_inside_the_port() {
    let (app, _) = jogging_app();
    for width in MIN_WIDTH..=200 {
        let rows = rows(screen(&app, width, 24).backend().buffer());
        // The address fits from the minimum width on; the rest of the line gives way.
        assert!(rows[0].contains("127.0.0.1:44718"), "{width}: {}", rows[0]);
    }
}

#[test]
fn the_status_bar_uses_the_full_width_in_step_mode() {
    let (app, _) = step_app();
    let terminal = screen(&app, 160, 40);
    let rows = rows(terminal.backend().buffer());
    assert_eq!(
        rows[1].trim_end(),
        " STEP 100.0 mm / 30 deg  | keys: auto-repeat fallback (500 ms, 25 Hz) | speed 100% \
         (≤250 mm/s) | frame mixed"
    );
    assert!(rows[0].contains(&format!("{LINK} 1.2 ms")), "{}", rows[0]);
    insta::assert_snapshot!("screen_160x40_step", terminal.backend());
}

#[test]
fn snapshots_at_the_four_sizes() {
    let (app, t0) = jogging_app();
    for (width, height) in [(62, 20), (80, 24), (120, 40), (200, 60)] {
        let mut app = app.clone();
        app.handle(Input::Resize { width, height }, t0);
        assert!(app.jog().is_jogging(), "{width}x{height} stopped the jog");
        insta::assert_snapshot!(
            format!("screen_{width}x{height}"),
            screen(&app, width, height).backend()
        );
    }
}

#[test]
fn the_joints_title_states_the_angle_convention() {
    let (app, _) = jogging_app();
    let rows = rows(screen(&app, 120, 40).backend().buffer());
    assert!(
        rows[2].contains("Joints, deg in (-180, 180]"),
        "{}",
        rows[2]
    );
    // J1 reported at 359.66 reads as just below zero.
    assert!(
        rows[4].starts_with("│J1") && rows[4].contains("-0.34"),
        "{}",
        rows[4]
    );
}

#[test]
fn the_wrench_is_labelled_in_the_tool_frame_and_the_pose_in_the_base_frame() {
    let (app, _) = jogging_app();
    let text = rows(screen(&app, 120, 40).backend().buffer()).join("\n");
    let base = text.find("base frame").expect("base frame named");
    let tool = text.find("tool frame").expect("tool frame named");
    let pose = text.find("pos mm").expect("pose row");
    let force = text.find("force N").expect("force row");
    assert!(base < pose && pose < tool && tool < force, "{text}");
}
