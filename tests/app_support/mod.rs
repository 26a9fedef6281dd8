//! The console's state machine set up for fake-clock tests: an app with its link up, key
//! events, and the effects tests compare against.
#![allow(dead_code)]

use std::time::{Duration, Instant};

use armjog::console::app::{App, AppConfig, Effect, Input, KeyInput};
use armjog::console::jog::{JogMotion, KeyKind, ReleaseMode};
use armjog::console::keymap::{KeyName, Keymap};
use armjog::console::positions::PositionBook;
use armjog::link::interface::{ArmCommand, ArmEvent, LinkStatus, StepMove};

/// The console's session facts as most tests want them: the default keymap, key releases
/// reported, a 100 ms refresh, positions on the operator, the default caps, a real arm. Tests
/// change what they are about: `AppConfig { max_jog_speed: 0.05, ..config() }`.
pub fn config() -> AppConfig {
    AppConfig {
        keymap: Keymap::builtin("default").expect("default keymap").into(),
        release_mode: ReleaseMode::Reported,
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
    }
}

pub fn app(mode: ReleaseMode, on_operator: bool) -> (App, Instant) {
    let config = AppConfig {
        release_mode: mode,
        positions_on_operator: on_operator,
        frames: !on_operator,
        ..config()
    };
    let mut app = App::new(config, PositionBook::new());
    let t0 = Instant::now();
    app.handle(
        Input::Arm(ArmEvent::Status(LinkStatus::Up {
            description: "test".into(),
        })),
        t0,
    );
    (app, t0)
}

pub fn key(name: &str, kind: KeyKind) -> Input {
    let key: KeyName = name.parse().expect("key name");
    let text = if name.chars().count() == 1 {
        name.chars().next()
    } else {
        None
    };
    Input::Key(KeyInput { key, text, kind })
}

pub fn press(app: &mut App, name: &str, now: Instant) -> Vec<Effect> {
    app.handle(key(name, KeyKind::Press), now)
}

pub fn release(app: &mut App, name: &str, now: Instant) -> Vec<Effect> {
    app.handle(key(name, KeyKind::Release), now)
}

pub fn jog(x: i8, y: i8, z: i8) -> Effect {
    Effect::Arm(ArmCommand::Jog(JogMotion::Cartesian { x, y, z }))
}

pub const STOP: Effect = Effect::Arm(ArmCommand::Stop);

/// Whether none of `effects` starts the arm moving.
pub fn no_motion(effects: &[Effect]) -> bool {
    !effects
        .iter()
        .any(|e| matches!(e, Effect::Arm(c) if c.starts_motion()))
}

pub fn step(dx: i32, dy: i32, dz: i32) -> Effect {
    Effect::Arm(ArmCommand::Step(StepMove::Cartesian { dx, dy, dz }))
}

/// The text on the bottom line, or "" when there is none.
pub fn message(app: &App) -> String {
    app.message()
        .map(|(text, _)| text.to_string())
        .unwrap_or_default()
}

pub fn ms(n: u64) -> Duration {
    Duration::from_millis(n)
}

/// Every cell's symbol of a drawn buffer, row after row, as one string.
pub fn buffer_text(buffer: &ratatui::buffer::Buffer) -> String {
    buffer.content().iter().map(|c| c.symbol()).collect()
}

/// A console over Modbus (key releases reported, the console's own book) that has had one
/// telemetry report, `t`.
pub fn with_telemetry(t: armjog::kortex::Telemetry) -> (App, Instant) {
    let (mut app, t0) = app(ReleaseMode::Reported, false);
    app.handle(
        Input::Arm(ArmEvent::TelemetrySource(
            armjog::link::interface::TelemetrySource::Modbus,
        )),
        t0,
    );
    app.handle(Input::Arm(ArmEvent::Telemetry(Box::new(t))), t0);
    (app, t0)
}

/// The whole console drawn from `app`'s view, in colour, at `width` x `height`.
pub fn screen(
    app: &App,
    width: u16,
    height: u16,
) -> ratatui::Terminal<ratatui::backend::TestBackend> {
    use armjog::console::ui::{self, Theme};
    let mut terminal = ratatui::Terminal::new(ratatui::backend::TestBackend::new(width, height))
        .expect("terminal");
    let view = armjog::console::view::View::new(app);
    terminal
        .draw(|f| ui::draw(f, &view, &Theme { color: true }))
        .expect("draw");
    terminal
}

/// Row `y` of a drawn terminal.
pub fn row(terminal: &ratatui::Terminal<ratatui::backend::TestBackend>, y: u16) -> String {
    let buffer = terminal.backend().buffer();
    (0..buffer.area.width)
        .map(|x| buffer[(x, y)].symbol().to_string())
        .collect()
}

/// The Gen3's home pose, degrees (the simulator's Home action, id 2).
pub const HOME_JOINTS: [f32; 7] = [0.0, 15.0, 180.0, 230.0, 0.0, 55.0, 90.0];

/// A ready arm without faults at `joints` (every joint turning at `velocity` deg/s), the tool at
/// the home pose, its action registers reporting `action`.
pub fn arm_telemetry(
    joints: [f32; 7],
    velocity: f32,
    action: armjog::kortex::ActionState,
) -> armjog::kortex::Telemetry {
    use armjog::kortex::{
        Coded, FlagSet, JointState, RobotState, SpeedLimits, Telemetry, ToolState, Twist, Wrench,
    };
    Telemetry {
        robot_state: Coded::Known(RobotState::Ready),
        faults: FlagSet::from_bits(0),
        warnings: FlagSet::from_bits(0),
        arm: Default::default(),
        joints: joints.map(|position| JointState {
            position,
            velocity,
            ..JointState::default()
        }),
        tcp: ToolState {
            pose: crate::common::home_tcp(),
            twist: Twist::ZERO,
            wrench: Wrench::default(),
        },
        action,
        speed_limits: SpeedLimits::default(),
        control: Coded::Unknown(u16::MAX),
        state_from_inputs: None,
    }
}
