//! Snapshots of what the screen says when the link goes quiet or the arm may be moving: the
//! status bar (LINK STALE, MAY BE MOVING, MOVING: HOME / GOTO) and greyed stale panels. Fake
//! clock: every age on screen comes from the inputs' `now`.

use armjog::console::app::QUESTION_QUIET;
use std::time::{Duration, Instant};

use armjog::console::app::{App, AppConfig, Input, KeyInput};
use armjog::console::jog::{KeyKind, ReleaseMode};
use armjog::console::keymap::{KeyName, Keymap};
use armjog::console::positions::PositionBook;
use armjog::console::ui::{self, Theme};
use armjog::console::view::View;
use armjog::kortex::{
    ActionState, ActionStatus, Coded, FlagSet, JointState, MoveType, RobotState, SpeedLimits,
    Telemetry, ToolState, Twist, Wrench,
};
use armjog::link::interface::{ArmEvent, LinkStatus, TelemetrySource};
use ratatui::Frame;
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use ratatui::layout::Rect;
use ratatui::style::Color;

fn ms(n: u64) -> Duration {
    Duration::from_millis(n)
}

fn telemetry(velocity: f32, status: ActionStatus) -> Telemetry {
    let positions = [0.0, 15.0, 180.0, 230.0, 0.0, 55.0, 90.0];
    Telemetry {
        robot_state: Coded::Known(RobotState::Ready),
        faults: FlagSet::from_bits(0),
        warnings: FlagSet::from_bits(0),
        arm: Default::default(),
        joints: std::array::from_fn(|i| JointState {
            position: positions[i],
            velocity,
            torque: 1.5,
            current: 0.5,
            temperature: 31.0,
        }),
        tcp: ToolState {
            pose: crate::common::home_tcp(),
            twist: Twist::ZERO,
            wrench: Wrench::default(),
        },
        action: ActionState {
            status: Coded::Known(status),
            id: 2,
            move_type: Coded::Known(MoveType::Action),
        },
        speed_limits: SpeedLimits {
            linear: 0.125,
            angular: 50.0,
        },
        control: Coded::Unknown(u16::MAX),
        state_from_inputs: None,
    }
}

/// A Modbus console with the link up and telemetry at rest at `t0`.
fn modbus_app() -> (App, Instant) {
    let config = AppConfig {
        keymap: Keymap::builtin("default").expect("default keymap").into(),
        release_mode: ReleaseMode::Reported,
        refresh: ms(100),
        positions_on_operator: false,
        max_jog_speed: 0.25,
        joint_jog_speed: armjog::link::driver::JOINT_JOG_SPEED,
        frames: true,
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
    for event in [
        ArmEvent::TelemetrySource(TelemetrySource::Modbus),
        ArmEvent::Status(LinkStatus::Up {
            description: "modbus 127.0.0.1:502 unit 1".into(),
        }),
        ArmEvent::Speed(50),
        ArmEvent::Latency(Duration::from_micros(2100)),
        ArmEvent::Telemetry(Box::new(telemetry(0.0, ActionStatus::Completed))),
    ] {
        app.handle(Input::Arm(event), t0);
    }
    (app, t0)
}

fn press(app: &mut App, name: &str, now: Instant) {
    let key: KeyName = name.parse().expect("key name");
    app.handle(
        Input::Key(KeyInput {
            key,
            text: name.chars().next(),
            kind: KeyKind::Press,
        }),
        now,
    );
}

type Panel = fn(&mut Frame, Rect, &View, &Theme);

fn render(panel: Panel, app: &App, width: u16, height: u16) -> Terminal<TestBackend> {
    let mut terminal = Terminal::new(TestBackend::new(width, height)).expect("terminal");
    terminal
        .draw(|f| panel(f, f.area(), &View::new(app), &Theme { color: true }))
        .expect("draw");
    terminal
}

/// Jogging +X when the telemetry stops: 1.8 s later the link is stale, the jog was stopped and
/// its STOP is unanswered.
fn frozen_mid_jog() -> (App, Instant) {
    let (mut app, t0) = modbus_app();
    press(&mut app, "w", t0);
    app.handle(
        Input::Arm(ArmEvent::Telemetry(Box::new(telemetry(
            15.0,
            ActionStatus::Started,
        )))),
        t0 + ms(30),
    );
    app.handle(Input::Tick, t0 + ms(530));
    app.handle(Input::Tick, t0 + ms(1830));
    (app, t0)
}

#[test]
fn status_link_stale_and_may_be_moving() {
    let (app, _) = frozen_mid_jog();
    assert!(!app.jog().is_jogging(), "the stale link stopped the jog");
    insta::assert_snapshot!(
        "status_stale_80",
        render(ui::status::draw, &app, 80, 2).backend()
    );
    insta::assert_snapshot!(
        "status_stale_120",
        render(ui::status::draw, &app, 120, 2).backend()
    );
}

#[test]
fn link_stale_and_may_be_moving_are_red() {
    let (app, _) = frozen_mid_jog();
    let terminal = render(ui::status::draw, &app, 80, 2);
    let cells = terminal.backend().buffer().content();
    let text: String = cells.iter().map(|c| c.symbol()).collect();
    for word in ["LINK STALE", "MAY BE MOVING"] {
        let at = text.find(word).expect(word);
        assert!(
            (at..at + word.len()).all(|i| cells[i].bg == Color::Red),
            "{word} is not on red"
        );
    }
}

#[test]
fn status_moving_home_and_go_to() {
    let (mut app, t0) = modbus_app();
    press(&mut app, "h", t0);
    press(&mut app, "y", t0 + QUESTION_QUIET);
    insta::assert_snapshot!(
        "status_moving_home",
        render(ui::status::draw, &app, 80, 2).backend()
    );
    let (mut app, t0) = modbus_app();
    let mut book = PositionBook::new();
    book.get_or_insert("bench").cartesian = Some([4000, 1000, 3000]);
    app.handle(Input::PositionsLoaded(Ok(book)), t0);
    press(&mut app, "o", t0);
    press(&mut app, "y", t0 + QUESTION_QUIET);
    insta::assert_snapshot!(
        "status_moving_goto",
        render(ui::status::draw, &app, 80, 2).backend()
    );
}

#[test]
fn status_stopping_then_idle() {
    let (mut app, t0) = modbus_app();
    press(&mut app, "space", t0);
    insta::assert_snapshot!(
        "status_stopping",
        render(ui::status::draw, &app, 80, 2).backend()
    );
    app.handle(Input::Arm(ArmEvent::StopConfirmed), t0 + ms(5));
    app.handle(
        Input::Arm(ArmEvent::Telemetry(Box::new(telemetry(
            0.0,
            ActionStatus::Aborted,
        )))),
        t0 + ms(30),
    );
    let terminal = render(ui::status::draw, &app, 80, 2);
    let text = crate::app_support::buffer_text(terminal.backend().buffer());
    assert!(text.contains(" idle "), "{text}");
}

#[test]
fn stale_panels_are_grey_and_show_their_age() {
    let (app, _) = frozen_mid_jog();
    insta::assert_snapshot!(
        "joints_stale",
        render(ui::joints::draw, &app, 60, 10).backend()
    );
    insta::assert_snapshot!("tcp_stale", render(ui::tcp::draw, &app, 40, 10).backend());
    insta::assert_snapshot!("arm_stale", render(ui::arm::draw, &app, 60, 7).backend());
    let terminal = render(ui::tcp::draw, &app, 40, 9);
    let cells = terminal.backend().buffer().content();
    // Inside the border every value is grey.
    for row in 1..8 {
        for col in 1..39 {
            let cell = &cells[row * 40 + col];
            assert_eq!(cell.fg, Color::DarkGray, "row {row} col {col}");
        }
    }
    let (fresh, _) = modbus_app();
    let terminal = render(ui::tcp::draw, &fresh, 40, 9);
    let title: String = terminal.backend().buffer().content()[..40]
        .iter()
        .map(|c| c.symbol())
        .collect();
    assert!(!title.contains("stale"), "{title}");
    assert_ne!(
        terminal.backend().buffer().content()[2 * 40 + 15].fg,
        Color::DarkGray
    );
}

#[test]
fn a_go_to_command_is_named_the_position_it_goes_to() {
    let (mut app, t0) = modbus_app();
    let mut book = PositionBook::new();
    book.get_or_insert("bench").cartesian = Some([4000, 1000, 3000]);
    app.handle(Input::PositionsLoaded(Ok(book)), t0);
    press(&mut app, "o", t0);
    press(&mut app, "y", t0 + QUESTION_QUIET);
    assert!(matches!(
        app.motion_truth().action().map(|a| a.kind.label()),
        Some(label) if label == "GOTO bench"
    ));
}
