//! Snapshots of every console panel, and of the whole screen, on ratatui's `TestBackend`.
//!
//! The state is built by hand and through `App::handle` on a fake clock: `Instant::now()` is
//! only the base of that clock, and every number that reaches the screen (telemetry, latency,
//! auto-repeat timing) is fixed here, so the snapshots never depend on the wall clock.

use std::time::{Duration, Instant};

use armjog::console::app::{App, AppConfig, Input, KeyInput, Overlay};
use armjog::console::jog::{JogMotion, KeyKind, ReleaseMode};
use armjog::console::keymap::{KeyName, Keymap};
use armjog::console::positions::{BookError, PositionBook};
use armjog::console::ui::{self, Theme};
use armjog::console::view::View;
use armjog::kortex::{
    ActionState, ActionStatus, ArmHealth, Coded, ControlCoil, Flag, FlagSet, JointState, MoveType,
    Pose, RobotState, SpeedLimits, Telemetry, ToolState, Twist, Wrench, Write,
};
use armjog::link::interface::{
    ArmCommand, ArmError, ArmEvent, CommandKind, LinkStatus, LogEntry, PositionCoordinates,
    TelemetrySource, Traffic,
};
use armjog::talos::ReturnCode;
use ratatui::Frame;
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use ratatui::layout::Rect;
use ratatui::style::{Color, Modifier};

const LINK: &str = "talos 127.0.0.1:61616 (icd, crc16), operator 1.0";

fn ms(n: u64) -> Duration {
    Duration::from_millis(n)
}

/// The arm at its home pose, in fault (joint fault) with a core temperature warning.
fn home_telemetry() -> Telemetry {
    let positions = [0.0, 15.0, 180.0, 230.0, 0.0, 55.0, 90.0];
    let joints = std::array::from_fn(|i| JointState {
        position: positions[i],
        velocity: 0.0,
        torque: [0.0, -12.5, 0.25, 6.75, 0.0, 1.5, 0.0][i],
        current: [0.1, 1.2, 0.3, 0.9, 0.1, 0.4, 0.05][i],
        temperature: 30.0 + i as f32 * 0.5,
    });
    Telemetry {
        robot_state: Coded::Known(RobotState::InFault),
        faults: FlagSet::from_bits(Flag::JointFault.bit()),
        warnings: FlagSet::from_bits(Flag::MaximumCoreTemperature.bit()),
        arm: ArmHealth {
            current: 1.25,
            voltage: 24.1,
            cpu_temperature: 45.5,
            ambient_temperature: 28.0,
        },
        joints,
        tcp: ToolState {
            pose: Pose {
                x: 0.4566,
                y: 0.0010,
                z: 0.4338,
                theta_x: 90.0,
                theta_y: 0.0,
                theta_z: 90.0,
            },
            twist: Twist::ZERO,
            wrench: Wrench {
                force_x: 0.5,
                force_y: -1.25,
                force_z: 9.75,
                torque_x: 0.0,
                torque_y: 0.12,
                torque_z: -0.03,
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
        state_from_inputs: Some(RobotState::InFault),
    }
}

fn log_entry(id: u32, name: &str, outcome: &str, ok: bool, micros: u64) -> LogEntry {
    LogEntry {
        poll: false,
        count: 1,
        id: Some(id),
        name: name.into(),
        outcome: outcome.into(),
        ok,
        latency: Some(Duration::from_micros(micros)),
        traffic: Traffic::Talos {
            request: vec![
                0xa5, 0x5a, 0x00, id as u8, 0x00, 0x06, 0x00, 0x03, 0x01, 0x00, 0x00,
            ],
            reply: Some(vec![
                0xa5,
                0x5a,
                0x00,
                id as u8,
                0x80,
                0x06,
                0x00,
                0x02,
                0x00,
                u8::from(!ok) * 4,
            ]),
        },
    }
}

/// A console with nothing from the arm yet.
fn bare_app(mode: ReleaseMode, on_operator: bool) -> (App, Instant) {
    let config = AppConfig {
        keymap: Keymap::builtin("default").expect("default keymap").into(),
        release_mode: mode,
        refresh: ms(100),
        positions_on_operator: on_operator,
        max_jog_speed: 0.25,
        joint_jog_speed: armjog::link::driver::JOINT_JOG_SPEED,
        frames: !on_operator,
        simulated: false,
        arm_name: None,
        home_action: None,
        fence: None,

        config_file: None,

        new_profile: Vec::new(),

        recording_off: false,
    };
    (App::new(config, PositionBook::new()), Instant::now())
}

/// A console fed by a live arm: link up with a latency, telemetry, speed, log, positions.
fn live_app(mode: ReleaseMode) -> (App, Instant) {
    let (mut app, t0) = bare_app(mode, true);
    let events = [
        ArmEvent::Status(LinkStatus::Up {
            description: LINK.into(),
        }),
        ArmEvent::TelemetrySource(TelemetrySource::TalosHardware),
        ArmEvent::Telemetry(Box::new(home_telemetry())),
        ArmEvent::Latency(Duration::from_micros(1234)),
        ArmEvent::Speed(50),
        ArmEvent::Log(log_entry(1, "get_speed", "OK", true, 812)),
        ArmEvent::Log(log_entry(2, "save", "OK", true, 1530)),
        ArmEvent::Log(log_entry(3, "goto", "UNKNOWN_POSITION", false, 977)),
        ArmEvent::Log(log_entry(4, "cart_start", "OK", true, 640)),
        ArmEvent::Log(LogEntry {
            poll: false,
            count: 1,
            id: Some(5),
            name: "cart_stop".into(),
            outcome: "no reply within 500 ms".into(),
            ok: false,
            latency: None,
            traffic: Traffic::Talos {
                request: vec![0xa5, 0x5a, 0x00, 0x05, 0x00, 0x07, 0x00, 0x00],
                reply: None,
            },
        }),
    ];
    // The book as read from its file, before the link comes up.
    let mut book = PositionBook::new();
    book.get_or_insert("home").cartesian = Some([4566, 10, 4338]);
    let pick = book.get_or_insert("pick");
    pick.cartesian = Some([5000, -1205, 2500]);
    pick.anchor = true;
    pick.parent = Some("table".into());
    book.get_or_insert("table").cartesian = Some([6000, 0, 1000]);
    book.get_or_insert("bench").cartesian = Some([3000, 3000, 800]);
    app.handle(Input::PositionsLoaded(Ok(book)), t0);
    for event in events {
        app.handle(Input::Arm(event), t0);
    }
    app.handle(
        Input::Arm(ArmEvent::UnknownPosition {
            name: "bench".into(),
        }),
        t0,
    );
    // Sorted: bench, home, pick, table; "pick" selected.
    press(&mut app, "pagedown", t0);
    press(&mut app, "pagedown", t0);
    assert_eq!(app.selected_name(), Some("pick"));
    (app, t0)
}

fn key(name: &str, kind: KeyKind) -> Input {
    let key: KeyName = name.parse().expect("key name");
    let text = if name.chars().count() == 1 {
        name.chars().next()
    } else {
        None
    };
    Input::Key(KeyInput { key, text, kind })
}

fn press(app: &mut App, name: &str, now: Instant) {
    app.handle(key(name, KeyKind::Press), now);
}

fn type_text(app: &mut App, text: &str, now: Instant) {
    for c in text.chars() {
        press(app, &c.to_string(), now);
    }
}

/// `w` held, releases reported: the status says "JOG +X".
/// [`home_telemetry`] with the fault gone and the arm ready: no motion starts on a faulted arm.
fn ready_telemetry() -> Telemetry {
    Telemetry {
        robot_state: Coded::Known(RobotState::Ready),
        faults: FlagSet::EMPTY,
        ..home_telemetry()
    }
}

fn ready(app: &mut App, now: Instant) {
    app.handle(
        Input::Arm(ArmEvent::Telemetry(Box::new(ready_telemetry()))),
        now,
    );
}

fn jogging_app() -> (App, Instant) {
    let (mut app, t0) = live_app(ReleaseMode::Reported);
    ready(&mut app, t0);
    press(&mut app, "w", t0);
    (app, t0)
}

/// `w` held with no release events: one press, a 500 ms onset and 40 ms repeats (25 Hz). The
/// arm keeps answering and sending telemetry meanwhile, so the link stays fresh.
fn auto_repeat_app() -> (App, Instant) {
    let (mut app, t0) = live_app(ReleaseMode::AutoRepeat);
    for at in [0, 500, 540, 580, 620] {
        let now = t0 + ms(at);
        app.handle(
            Input::Arm(ArmEvent::Telemetry(Box::new(ready_telemetry()))),
            now,
        );
        press(&mut app, "w", now);
        let start = ArmCommand::Jog(JogMotion::Cartesian { x: 1, y: 0, z: 0 });
        app.handle(Input::Arm(ArmEvent::Done { command: start }), now);
    }
    (app, t0)
}

type Panel = fn(&mut Frame, Rect, &View, &Theme);

/// One panel alone on a `width` x `height` terminal.
fn render(panel: Panel, app: &App, width: u16, height: u16) -> Terminal<TestBackend> {
    render_with(panel, app, width, height, Theme { color: true })
}

fn render_with(
    panel: Panel,
    app: &App,
    width: u16,
    height: u16,
    theme: Theme,
) -> Terminal<TestBackend> {
    draw_view(panel, &View::new(app), width, height, theme)
}

fn draw_view(
    panel: Panel,
    view: &View,
    width: u16,
    height: u16,
    theme: Theme,
) -> Terminal<TestBackend> {
    let mut terminal = Terminal::new(TestBackend::new(width, height)).expect("terminal");
    terminal
        .draw(|f| panel(f, f.area(), view, &theme))
        .expect("draw");
    terminal
}

/// The whole screen.
fn screen(app: &App, width: u16, height: u16, theme: Theme) -> Terminal<TestBackend> {
    let mut terminal = Terminal::new(TestBackend::new(width, height)).expect("terminal");
    terminal
        .draw(|f| ui::draw(f, &View::new(app), &theme))
        .expect("draw");
    terminal
}

fn sized(mut app: App, width: u16, height: u16, t0: Instant) -> App {
    app.handle(Input::Resize { width, height }, t0);
    app
}

// ---- Panels, one by one ----

#[test]
fn status_jogging_with_release_events() {
    let (app, _) = jogging_app();
    insta::assert_snapshot!(render(ui::status::draw, &app, 80, 2).backend());
}

#[test]
fn status_jogging_with_the_auto_repeat_fallback() {
    let (app, _) = auto_repeat_app();
    assert!(app.jog().is_jogging());
    insta::assert_snapshot!(render(ui::status::draw, &app, 80, 2).backend());
}

#[test]
fn status_auto_repeat_before_any_repeat_was_measured_in_step_mode_over_modbus() {
    let (mut app, t0) = bare_app(ReleaseMode::AutoRepeat, false);
    app.handle(
        Input::Arm(ArmEvent::Status(LinkStatus::Up {
            description: "modbus 127.0.0.1:502 unit 1".into(),
        })),
        t0,
    );
    press(&mut app, "t", t0);
    press(&mut app, "]", t0);
    insta::assert_snapshot!(render(ui::status::draw, &app, 80, 2).backend());
}

#[test]
fn status_link_down_and_connecting() {
    let (mut app, t0) = jogging_app();
    app.handle(
        Input::Arm(ArmEvent::Status(LinkStatus::Down {
            reason: "connection reset by peer".into(),
        })),
        t0 + ms(10),
    );
    insta::assert_snapshot!(
        "status_link_down",
        render(ui::status::draw, &app, 80, 2).backend()
    );
    let (app, _) = bare_app(ReleaseMode::Reported, true);
    insta::assert_snapshot!(
        "status_connecting",
        render(ui::status::draw, &app, 80, 2).backend()
    );
}

#[test]
fn status_step_mode_with_measured_auto_repeat_fits_80_columns() {
    // Over Modbus (frames shown), step mode with the largest step, full speed, mixed frame and
    // a measured auto-repeat: the mode and every setting still fit; the timing gives way.
    let (mut app, t0) = bare_app(ReleaseMode::AutoRepeat, false);
    app.handle(
        Input::Arm(ArmEvent::Status(LinkStatus::Up {
            description: "modbus 127.0.0.1:502 unit 1".into(),
        })),
        t0,
    );
    app.handle(Input::Arm(ArmEvent::Speed(100)), t0);
    for at in [0, 500, 540, 580] {
        press(&mut app, "w", t0 + ms(at));
    }
    app.handle(Input::Tick, t0 + ms(2000));
    assert!(!app.jog().is_jogging());
    // The driver confirms the STOP, or the status would say STOPPING.
    app.handle(Input::Arm(ArmEvent::StopConfirmed), t0 + ms(2000));
    press(&mut app, "g", t0 + ms(2000));
    press(&mut app, "g", t0 + ms(2000));
    press(&mut app, "t", t0 + ms(2000));
    for _ in 0..6 {
        press(&mut app, ".", t0 + ms(2000));
    }
    insta::assert_snapshot!(
        "status_step_modbus_80",
        render(ui::status::draw, &app, 80, 2).backend()
    );
    insta::assert_snapshot!(
        "status_step_modbus_120",
        render(ui::status::draw, &app, 120, 2).backend()
    );
}

#[test]
fn log_over_modbus_has_no_ids() {
    let (mut app, t0) = bare_app(ReleaseMode::Reported, false);
    for entry in [
        LogEntry {
            poll: false,
            count: 1,
            id: None,
            name: "jog".into(),
            outcome: "OK (3 writes)".into(),
            ok: true,
            latency: Some(Duration::from_micros(2150)),
            traffic: Traffic::Modbus(vec![
                Write::Registers {
                    addr: 200,
                    values: vec![1],
                },
                Write::Coil {
                    addr: 203,
                    value: true,
                },
            ]),
        },
        LogEntry {
            poll: false,
            count: 1,
            id: None,
            name: "fault reset".into(),
            outcome: "Modbus exception: illegal data address".into(),
            ok: false,
            latency: None,
            traffic: Traffic::None,
        },
    ] {
        app.handle(Input::Arm(ArmEvent::Log(entry)), t0);
    }
    insta::assert_snapshot!(render(ui::log::draw, &app, 80, 4).backend());
}

#[test]
fn log_in_hex_formats_talos_frames_and_modbus_writes() {
    let talos = Traffic::Talos {
        request: vec![0xA5, 0x5A, 0x00, 0x07],
        reply: Some(vec![0xA5, 0x5A, 0x80, 0x0f]),
    };
    assert_eq!(
        ui::log::traffic_lines(&talos),
        ["  > A5 5A 00 07", "  < A5 5A 80 0F"]
    );
    let unanswered = Traffic::Talos {
        request: vec![0x01],
        reply: None,
    };
    assert_eq!(ui::log::traffic_lines(&unanswered), ["  > 01"]);
    let writes = Traffic::Modbus(vec![
        Write::Registers {
            addr: 200,
            values: vec![1, 0xFFFF],
        },
        Write::Coil {
            addr: 203,
            value: true,
        },
    ]);
    assert_eq!(
        ui::log::traffic_lines(&writes),
        ["  > write holding registers 200-201 = [0x0001, 0xFFFF] (FC16); write coil 203 on (FC05)"]
    );
    assert!(ui::log::traffic_lines(&Traffic::None).is_empty());
    assert!(ui::log::traffic_lines(&Traffic::Modbus(Vec::new())).is_empty());

    let (mut app, t0) = bare_app(ReleaseMode::Reported, false);
    let entry = LogEntry {
        count: 1,
        name: "jog".into(),
        outcome: "OK (2 writes)".into(),
        ok: true,
        latency: Some(Duration::from_micros(2150)),
        traffic: writes,
        ..LogEntry::default()
    };
    app.handle(Input::Arm(ArmEvent::Log(entry)), t0);
    press(&mut app, "H", t0);
    insta::assert_snapshot!(render(ui::log::draw, &app, 100, 4).backend());
}

#[test]
fn joints_narrow_and_wide() {
    let (app, _) = live_app(ReleaseMode::Reported);
    insta::assert_snapshot!(
        "joints_narrow",
        render(ui::joints::draw, &app, 46, 10).backend()
    );
    insta::assert_snapshot!(
        "joints_wide",
        render(ui::joints::draw, &app, 80, 10).backend()
    );
}

#[test]
fn tcp_wide_and_narrow() {
    let (app, _) = live_app(ReleaseMode::Reported);
    insta::assert_snapshot!("tcp_wide", render(ui::tcp::draw, &app, 40, 10).backend());
    // Narrower than the long labels need: unit labels, the figures whole.
    insta::assert_snapshot!("tcp_narrow", render(ui::tcp::draw, &app, 34, 10).backend());
}

#[test]
fn arm_with_a_fault_and_a_warning() {
    let (app, _) = live_app(ReleaseMode::Reported);
    insta::assert_snapshot!(render(ui::arm::draw, &app, 60, 7).backend());
}

#[test]
fn arm_all_clear() {
    let (mut app, t0) = live_app(ReleaseMode::Reported);
    let mut t = home_telemetry();
    t.robot_state = Coded::Known(RobotState::Ready);
    t.faults = FlagSet::EMPTY;
    t.warnings = FlagSet::EMPTY;
    app.handle(Input::Arm(ArmEvent::Telemetry(Box::new(t))), t0);
    insta::assert_snapshot!(render(ui::arm::draw, &app, 60, 7).backend());
}

#[test]
fn positions_with_an_anchored_and_an_unknown_name() {
    let (app, _) = live_app(ReleaseMode::Reported);
    insta::assert_snapshot!(render(ui::positions::draw, &app, 50, 7).backend());
}

#[test]
fn positions_empty_over_modbus() {
    let (app, _) = bare_app(ReleaseMode::Reported, false);
    insta::assert_snapshot!(render(ui::positions::draw, &app, 50, 4).backend());
}

#[test]
fn positions_while_loading_a_big_book() {
    let (mut app, _) = bare_app(ReleaseMode::Reported, false);
    app.begin_loading_positions("/data/book.json");
    insta::assert_snapshot!(render(ui::positions::draw, &app, 50, 4).backend());
}

#[test]
fn positions_that_could_not_be_read_with_one_kept_in_memory() {
    let (mut app, t0) = bare_app(ReleaseMode::Reported, false);
    app.begin_loading_positions("/data/book.json");
    // Set while the book loads: kept in memory.
    app.handle(
        Input::Arm(ArmEvent::Done {
            command: ArmCommand::SetCartesianPosition {
                name: "pick".into(),
                x: 5000,
                y: -1205,
                z: 2500,
            },
        }),
        t0,
    );
    app.handle(
        Input::PositionsLoaded(Err(BookError::Parse {
            path: "/data/book.json".into(),
            line: 3,
            column: 7,
            message: "expected `:`".into(),
        }
        .into())),
        t0,
    );
    insta::assert_snapshot!(render(ui::positions::draw, &app, 60, 5).backend());
}

/// The panel scrolled deep into a big book, drawn from the view (a window of the book) and
/// from the whole book: identical.
#[test]
fn positions_scrolled_in_a_big_book_and_its_view_draw_the_same() {
    let (mut app, t0) = bare_app(ReleaseMode::Reported, false);
    app = sized(app, 80, 24, t0);
    let mut book = PositionBook::new();
    for i in 0..5000 {
        book.get_or_insert(&format!("pos-{i:05}")).cartesian = Some([i, 0, 0]);
    }
    app.handle(Input::PositionsLoaded(Ok(book)), t0);
    for _ in 0..3210 {
        press(&mut app, "pagedown", t0);
    }
    assert_eq!(app.selected(), 3210);
    let view = View::new(&app);
    assert!(
        view.book.positions.len() <= 2 * 24 + 1,
        "a window, not the book"
    );
    let mut whole_book = view.clone();
    whole_book.book.positions = app.positions().clone();
    whole_book.book.selected = app.selected();
    let whole = draw_view(
        ui::positions::draw,
        &whole_book,
        50,
        8,
        Theme { color: true },
    );
    assert_eq!(
        render(ui::positions::draw, &app, 50, 8).backend().buffer(),
        whole.backend().buffer()
    );
    insta::assert_snapshot!(whole.backend());
}

#[test]
fn log_with_a_failure() {
    let (app, _) = live_app(ReleaseMode::Reported);
    insta::assert_snapshot!(render(ui::log::draw, &app, 80, 7).backend());
}

#[test]
fn log_in_hex_keeps_the_newest_lines() {
    let (mut app, t0) = live_app(ReleaseMode::Reported);
    press(&mut app, "H", t0);
    assert!(app.hex());
    insta::assert_snapshot!(render(ui::log::draw, &app, 80, 7).backend());
}

#[test]
fn dialog_confirm_go_to() {
    let (mut app, t0) = live_app(ReleaseMode::Reported);
    ready(&mut app, t0);
    press(&mut app, "o", t0);
    assert!(matches!(app.overlay(), Overlay::Confirm(_)));
    insta::assert_snapshot!(render(ui::dialog::draw, &app, 80, 9).backend());
}

#[test]
fn dialog_form_with_an_error() {
    let (mut app, t0) = live_app(ReleaseMode::Reported);
    press(&mut app, "C", t0);
    for value in ["400", "abc", "300"] {
        press(&mut app, "tab", t0);
        type_text(&mut app, value, t0);
    }
    press(&mut app, "enter", t0);
    let Overlay::Form(form) = &app.overlay() else {
        panic!("the form closed")
    };
    assert!(form.error.is_some());
    insta::assert_snapshot!(render(ui::dialog::draw, &app, 80, 12).backend());
}

#[test]
fn dialog_save_form() {
    let (mut app, t0) = live_app(ReleaseMode::Reported);
    press(&mut app, "p", t0);
    press(&mut app, "tab", t0);
    type_text(&mut app, "table", t0);
    press(&mut app, "tab", t0);
    press(&mut app, "space", t0);
    insta::assert_snapshot!(render(ui::dialog::draw, &app, 80, 9).backend());
}

#[test]
fn dialog_position_coordinates() {
    let (mut app, t0) = live_app(ReleaseMode::Reported);
    press(&mut app, "v", t0);
    insta::assert_snapshot!(
        "dialog_position_asking",
        render(ui::dialog::draw, &app, 80, 7).backend()
    );
    app.handle(
        Input::Arm(ArmEvent::Position {
            name: "pick".into(),
            coordinates: PositionCoordinates {
                cartesian: Some([5000, -1205, 2500]),
                polar: Some([245, -136, 5713]),
            },
        }),
        t0,
    );
    insta::assert_snapshot!(
        "dialog_position_coordinates",
        render(ui::dialog::draw, &app, 80, 12).backend()
    );
}

#[test]
fn hints_keys_and_a_message() {
    let (app, _) = live_app(ReleaseMode::Reported);
    insta::assert_snapshot!("hints_keys", render(ui::hints::draw, &app, 80, 1).backend());
    let (mut app, t0) = live_app(ReleaseMode::Reported);
    app.handle(
        Input::Arm(ArmEvent::Failed {
            command: CommandKind::GoToPosition,
            error: ArmError::ReturnCode(ReturnCode::UNKNOWN_POSITION),
        }),
        t0,
    );
    insta::assert_snapshot!(
        "hints_message",
        render(ui::hints::draw, &app, 80, 1).backend()
    );
}

// ---- No telemetry ----

#[test]
fn no_telemetry_yet_says_waiting() {
    let (mut app, t0) = bare_app(ReleaseMode::Reported, false);
    app.handle(
        Input::Arm(ArmEvent::TelemetrySource(TelemetrySource::Modbus)),
        t0,
    );
    insta::assert_snapshot!(
        "no_telemetry_waiting_joints",
        render(ui::joints::draw, &app, 46, 4).backend()
    );
    insta::assert_snapshot!(
        "no_telemetry_waiting_screen",
        screen(&app, 80, 24, Theme { color: true }).backend()
    );
}

#[test]
fn the_ack_dialect_says_there_is_no_telemetry() {
    let (mut app, t0) = bare_app(ReleaseMode::Reported, true);
    app.handle(
        Input::Arm(ArmEvent::Status(LinkStatus::Up {
            description: "talos 127.0.0.1:61616 (ack, none)".into(),
        })),
        t0,
    );
    app.handle(
        Input::Arm(ArmEvent::TelemetrySource(TelemetrySource::None)),
        t0,
    );
    insta::assert_snapshot!(
        "no_telemetry_ack_arm",
        render(ui::arm::draw, &app, 60, 4).backend()
    );
    insta::assert_snapshot!(
        "no_telemetry_ack_screen",
        screen(&app, 80, 24, Theme { color: true }).backend()
    );
}

// ---- The whole screen ----

#[test]
fn screen_80x24_jogging() {
    let (app, t0) = jogging_app();
    let app = sized(app, 80, 24, t0);
    assert!(app.jog().is_jogging());
    insta::assert_snapshot!(screen(&app, 80, 24, Theme { color: true }).backend());
}

#[test]
fn screen_200x60_auto_repeat() {
    let (app, t0) = auto_repeat_app();
    let app = sized(app, 200, 60, t0);
    insta::assert_snapshot!(screen(&app, 200, 60, Theme { color: true }).backend());
}

#[test]
fn screen_80x24_with_help() {
    let (mut app, t0) = live_app(ReleaseMode::Reported);
    press(&mut app, "?", t0);
    insta::assert_snapshot!(screen(&app, 80, 24, Theme { color: true }).backend());
}

#[test]
fn screen_80x24_with_a_form() {
    let (mut app, t0) = live_app(ReleaseMode::Reported);
    press(&mut app, "P", t0);
    insta::assert_snapshot!(screen(&app, 80, 24, Theme { color: true }).backend());
}

#[test]
fn screen_too_small() {
    let (app, t0) = jogging_app();
    let app = sized(app, 30, 8, t0);
    assert!(!app.jog().is_jogging(), "too small stops the jog");
    insta::assert_snapshot!(screen(&app, 30, 8, Theme { color: true }).backend());
}

// ---- NO_COLOR ----

#[test]
fn no_color_draws_no_colour_at_all() {
    let plain = Theme { color: false };
    let mut states = Vec::new();
    let (jogging, _) = jogging_app();
    states.push(jogging);
    let (mut help, t0) = live_app(ReleaseMode::Reported);
    press(&mut help, "?", t0);
    states.push(help);
    let (mut form, t0) = live_app(ReleaseMode::Reported);
    press(&mut form, "C", t0);
    press(&mut form, "enter", t0);
    press(&mut form, "enter", t0);
    states.push(form);
    let (mut down, t0) = live_app(ReleaseMode::AutoRepeat);
    down.handle(
        Input::Arm(ArmEvent::Status(LinkStatus::Down {
            reason: "gone".into(),
        })),
        t0,
    );
    states.push(down);
    for app in &states {
        for (w, h) in [(80, 24), (200, 60), (30, 8)] {
            let terminal = screen(app, w, h, plain);
            for (i, cell) in terminal.backend().buffer().content().iter().enumerate() {
                assert!(
                    cell.fg == Color::Reset && cell.bg == Color::Reset,
                    "{w}x{h}: cell {i} ({:?}) is coloured: fg {:?} bg {:?}",
                    cell.symbol(),
                    cell.fg,
                    cell.bg
                );
            }
        }
    }
}

/// The cell index where `word` starts on screen (cells of one character each).
fn find(buffer: &ratatui::buffer::Buffer, word: &str) -> Option<usize> {
    let cells = buffer.content();
    let letters: Vec<String> = word.chars().map(String::from).collect();
    (0..cells.len().saturating_sub(letters.len())).find(|&i| {
        letters
            .iter()
            .enumerate()
            .all(|(k, l)| cells[i + k].symbol() == l)
    })
}

#[test]
fn with_colour_a_fault_is_highlighted_in_red() {
    let (app, _) = live_app(ReleaseMode::Reported);
    let terminal = screen(&app, 80, 24, Theme { color: true });
    let buffer = terminal.backend().buffer();
    let at = find(buffer, "FAULTS").expect("FAULTS shown");
    let cells = buffer.content();
    assert!(
        (at..at + "FAULTS".len()).all(|i| cells[i].bg == Color::Red),
        "FAULTS is not on red"
    );
    assert!(find(buffer, "joint_fault").is_some(), "the fault is named");
    assert!(
        find(buffer, "maximum_core_temperature").is_some(),
        "the warning is named"
    );

    // Without colour it still stands out: reversed.
    let plain = screen(&app, 80, 24, Theme { color: false });
    let cells = plain.backend().buffer().content();
    assert!(
        (at..at + "FAULTS".len()).all(|i| cells[i].modifier.contains(Modifier::REVERSED)),
        "FAULTS is not reversed without colour"
    );
}
