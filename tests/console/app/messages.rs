//! The bottom-line message belongs to a state: it stays while that state holds and clears when
//! it ends (link up, fault gone, guard back, stop confirmed); a notice times out. Fake clock.

use std::time::{Duration, Instant};

use armjog::console::app::{App, AppConfig, Effect, Input};
use armjog::console::jog::{KeyKind, ReleaseMode};
use armjog::console::keymap::Keymap;
use armjog::console::positions::PositionBook;
use armjog::kortex::{
    ActionState, ActionStatus, Coded, Flag, FlagSet, JointState, MoveType, RobotState, SpeedLimits,
    Telemetry, ToolState, Twist, Wrench,
};
use armjog::link::interface::{
    ArmCommand, ArmError, ArmEvent, CommandKind, GuardStatus, LinkStatus, TelemetrySource,
};
use armjog::talos::ReturnCode;

use crate::app_support::{jog, key, ms, press, release};

/// Longer than any notice stays.
const LONG: Duration = Duration::from_secs(60);

/// A console whose driver said which telemetry to expect; the link not up yet.
fn app_before_link(source: TelemetrySource) -> (App, Instant) {
    let config = AppConfig {
        keymap: Keymap::builtin("default").expect("default keymap").into(),
        release_mode: ReleaseMode::Reported,
        refresh: ms(100),
        positions_on_operator: source != TelemetrySource::Modbus,
        max_jog_speed: 0.25,
        joint_jog_speed: armjog::link::driver::JOINT_JOG_SPEED,
        frames: source == TelemetrySource::Modbus,
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
    app.handle(Input::Arm(ArmEvent::TelemetrySource(source)), t0);
    (app, t0)
}

fn up() -> Input {
    Input::Arm(ArmEvent::Status(LinkStatus::Up {
        description: "test".into(),
    }))
}

fn app(source: TelemetrySource) -> (App, Instant) {
    let (mut app, t0) = app_before_link(source);
    app.handle(up(), t0);
    (app, t0)
}

fn message(app: &App) -> Option<String> {
    app.message().map(|(text, _)| text.to_string())
}

fn done(command: ArmCommand) -> Input {
    Input::Arm(ArmEvent::Done { command })
}

fn jog_refused_for_a_fault() -> Input {
    Input::Arm(ArmEvent::Failed {
        command: CommandKind::Jog,
        error: ArmError::ReturnCode(ReturnCode::ARM_FAULT),
    })
}

/// The arm at home and at rest, in fault or not.
fn telemetry(in_fault: bool) -> Input {
    let (robot_state, faults) = if in_fault {
        (RobotState::InFault, Flag::EmergencyStop.bit())
    } else {
        (RobotState::Ready, 0)
    };
    let home = [0.0, 15.0, 180.0, 230.0, 0.0, 55.0, 90.0];
    let t = Telemetry {
        robot_state: Coded::Known(robot_state),
        faults: FlagSet::from_bits(faults),
        warnings: FlagSet::from_bits(0),
        arm: Default::default(),
        joints: home.map(|position| JointState {
            position,
            ..JointState::default()
        }),
        tcp: ToolState {
            pose: crate::common::home_tcp(),
            twist: Twist::ZERO,
            wrench: Wrench::default(),
        },
        action: ActionState {
            status: Coded::Known(ActionStatus::Completed),
            id: 2,
            move_type: Coded::Known(MoveType::Action),
        },
        speed_limits: SpeedLimits::default(),
        control: Coded::Unknown(u16::MAX),
        state_from_inputs: None,
    };
    Input::Arm(ArmEvent::Telemetry(Box::new(t)))
}

#[test]
fn no_link_not_moving_stays_while_there_is_no_link_and_clears_when_it_comes_up() {
    let (mut app, t0) = app_before_link(TelemetrySource::None);
    assert!(press(&mut app, "w", t0).is_empty(), "no link: no motion");
    release(&mut app, "w", t0 + ms(100));
    let said = Some("no link to the arm: not moving".to_string());
    assert_eq!(message(&app), said);
    app.handle(Input::Tick, t0 + LONG);
    assert_eq!(message(&app), said, "still no link: still said");
    app.handle(up(), t0 + LONG + ms(10));
    assert_eq!(message(&app), None, "the link is up: the refusal is over");
    assert_eq!(press(&mut app, "w", t0 + LONG + ms(20)), [jog(1, 0, 0)]);
    assert_eq!(message(&app), None, "jogging shows no refusal");
}

#[test]
fn link_lost_stays_while_the_link_is_down_and_clears_when_it_is_up() {
    let (mut app, t0) = app(TelemetrySource::None);
    let lost = Input::Arm(ArmEvent::Status(LinkStatus::Down {
        reason: "connection refused".into(),
    }));
    app.handle(lost, t0 + ms(10));
    let said = Some("link lost: connection refused".to_string());
    assert_eq!(message(&app), said);
    app.handle(Input::Tick, t0 + LONG);
    assert_eq!(message(&app), said, "still down: still said");
    app.handle(up(), t0 + LONG + ms(10));
    assert_eq!(message(&app), None, "LINK UP and no 'link lost' under it");
}

#[test]
fn jog_failed_for_a_fault_stays_until_the_fault_reset_goes_through_without_telemetry() {
    let (mut app, t0) = app(TelemetrySource::None);
    press(&mut app, "w", t0);
    assert_eq!(
        app.handle(jog_refused_for_a_fault(), t0 + ms(10)),
        [Effect::Arm(ArmCommand::Stop)]
    );
    release(&mut app, "w", t0 + ms(50));
    let said = message(&app).expect("a message");
    assert!(
        said.starts_with("jog failed:") && said.contains("ARM_FAULT"),
        "{said}"
    );
    app.handle(Input::Tick, t0 + LONG);
    assert_eq!(
        message(&app).as_deref(),
        Some(said.as_str()),
        "the fault holds"
    );
    assert_eq!(
        press(&mut app, "c", t0 + LONG),
        [Effect::Arm(ArmCommand::FaultReset)]
    );
    assert_eq!(
        message(&app).as_deref(),
        Some(said.as_str()),
        "a reset asked for is not a reset done"
    );
    app.handle(done(ArmCommand::FaultReset), t0 + LONG + ms(20));
    assert_eq!(message(&app), None, "the reset went through");
}

#[test]
fn a_fault_message_with_telemetry_stays_until_telemetry_shows_the_fault_gone() {
    let (mut app, t0) = app(TelemetrySource::Modbus);
    app.handle(telemetry(false), t0);
    assert_eq!(
        press(&mut app, "x", t0),
        [Effect::Arm(ArmCommand::QuickStop)]
    );
    let said = Some("quick stop: reset the fault before moving again".to_string());
    // Telemetry from before the quick stop took effect ends nothing.
    app.handle(telemetry(false), t0 + ms(10));
    assert_eq!(message(&app), said);
    app.handle(telemetry(true), t0 + ms(40));
    app.handle(telemetry(true), t0 + LONG);
    assert_eq!(message(&app), said, "in fault: still said");
    press(&mut app, "c", t0 + LONG);
    app.handle(done(ArmCommand::FaultReset), t0 + LONG + ms(10));
    app.handle(telemetry(true), t0 + LONG + ms(20));
    assert_eq!(
        message(&app),
        said,
        "the reset was written but the arm still reports the fault"
    );
    app.handle(telemetry(false), t0 + LONG + ms(50));
    assert_eq!(message(&app), None, "the fault is gone");
}

#[test]
fn a_failed_jog_clears_when_a_jog_goes_through() {
    let (mut app, t0) = app(TelemetrySource::None);
    press(&mut app, "w", t0);
    app.handle(
        Input::Arm(ArmEvent::Failed {
            command: CommandKind::Jog,
            error: ArmError::Talos(
                armjog::link::TalosError::Timeout {
                    command: armjog::talos::CommandValue::CartesianMoveStart,
                    id: 3,
                    after: Duration::from_millis(500),
                }
                .into(),
            ),
        }),
        t0 + ms(10),
    );
    release(&mut app, "w", t0 + ms(20));
    assert!(message(&app).is_some_and(|m| m.starts_with("jog failed")));
    press(&mut app, "w", t0 + ms(500));
    app.handle(
        done(ArmCommand::Jog(
            armjog::link::interface::JogMotion::Cartesian { x: 1, y: 0, z: 0 },
        )),
        t0 + ms(520),
    );
    assert_eq!(message(&app), None);
}

#[test]
fn a_notice_times_out_and_uncovers_the_state_message_it_hid() {
    let (mut app, t0) = app(TelemetrySource::None);
    let lost = Input::Arm(ArmEvent::Status(LinkStatus::Down {
        reason: "timed out".into(),
    }));
    app.handle(lost, t0);
    press(&mut app, "space", t0 + ms(100));
    assert_eq!(
        message(&app).as_deref(),
        Some("stopped"),
        "the newer message shows"
    );
    let deadline = app.next_deadline().expect("the notice's end is a deadline");
    assert!(deadline <= t0 + ms(100) + Duration::from_secs(10));
    let later = t0 + Duration::from_secs(11);
    app.handle(Input::Tick, later);
    assert_eq!(
        message(&app).as_deref(),
        Some("link lost: timed out"),
        "the link is still down: said again"
    );
    app.handle(up(), later + ms(10));
    assert_eq!(message(&app), None);
}

#[test]
fn a_notice_alone_times_out() {
    let (mut app, t0) = app(TelemetrySource::None);
    press(&mut app, "t", t0);
    assert!(message(&app).is_some_and(|m| m.starts_with("step mode")));
    app.handle(Input::Tick, t0 + ms(1000));
    assert!(message(&app).is_some(), "a notice stays a while");
    app.handle(Input::Tick, t0 + LONG);
    assert_eq!(message(&app), None);
}

#[test]
fn guard_down_stays_until_the_guard_is_back() {
    let (mut app, t0) = app(TelemetrySource::Modbus);
    let guard = |status| Input::Arm(ArmEvent::Guard(status));
    app.handle(
        guard(GuardStatus::Down {
            reason: "the guard process exited".into(),
        }),
        t0,
    );
    app.handle(Input::Tick, t0 + LONG);
    assert!(message(&app).is_some_and(|m| m.starts_with("stop guard down")));
    app.handle(guard(GuardStatus::Ready { pid: 42 }), t0 + LONG);
    assert_eq!(message(&app), None);
}

#[test]
fn stop_not_confirmed_stays_until_a_stop_is_confirmed() {
    let (mut app, t0) = app(TelemetrySource::None);
    press(&mut app, "space", t0);
    app.handle(
        Input::Arm(ArmEvent::StopUnconfirmed {
            reason: "no reply".into(),
        }),
        t0 + ms(10),
    );
    app.handle(Input::Tick, t0 + LONG);
    assert!(message(&app).is_some_and(|m| m.starts_with("STOP NOT CONFIRMED")));
    press(&mut app, "space", t0 + LONG);
    app.handle(done(ArmCommand::Stop), t0 + LONG + ms(10));
    assert_eq!(
        message(&app).as_deref(),
        Some("stopped"),
        "the new stop's notice hides it"
    );
    app.handle(Input::Tick, t0 + 2 * LONG);
    assert!(
        message(&app).is_some_and(|m| m.starts_with("STOP NOT CONFIRMED")),
        "not confirmed yet: said again once the notice is gone"
    );
    app.handle(Input::Arm(ArmEvent::StopConfirmed), t0 + 2 * LONG);
    assert_eq!(message(&app), None, "confirmed: nothing left to say");
}

#[test]
fn a_key_that_is_not_bound_is_only_a_notice() {
    let (mut app, t0) = app(TelemetrySource::None);
    app.handle(key("Z", KeyKind::Press), t0);
    assert!(message(&app).is_some_and(|m| m.contains("not bound")));
    app.handle(Input::Tick, t0 + LONG);
    assert_eq!(message(&app), None);
}
