//! The state machine never says stopped when the arm may not be: LINK STALE, STOPPING, MAY BE
//! MOVING, MOVING: HOME / GOTO and their failures. Fake clock, no sockets.

use crate::app_support::message;
use armjog::console::app::QUESTION_QUIET;
use std::time::{Duration, Instant};

use armjog::console::app::{
    App, AppConfig, Effect, Input, KeyInput, MotionShown, NO_TELEMETRY_ACTION_TIME, Overlay,
    STOP_GRACE, Severity, abort_reason,
};
use armjog::console::jog::{KeyKind, ReleaseMode};
use armjog::console::keymap::{KeyName, Keymap};
use armjog::console::positions::PositionBook;
use armjog::kortex::{
    ActionState, ActionStatus, Coded, Flag, FlagSet, MoveType, RobotState, Telemetry,
};
use armjog::link::interface::{
    ArmCommand, ArmError, ArmEvent, CommandKind, LinkStatus, LogEntry, TelemetrySource,
};

const STOP: Effect = Effect::Arm(ArmCommand::Stop);

fn ms(n: u64) -> Duration {
    Duration::from_millis(n)
}

/// A console whose driver said which telemetry to expect, with the link up at `t0`.
fn app(source: TelemetrySource) -> (App, Instant) {
    let over_modbus = source == TelemetrySource::Modbus;
    let config = AppConfig {
        keymap: Keymap::builtin("default").expect("default keymap").into(),
        release_mode: ReleaseMode::Reported,
        refresh: ms(100),
        positions_on_operator: !over_modbus,
        max_jog_speed: 0.25,
        joint_jog_speed: armjog::link::driver::JOINT_JOG_SPEED,
        frames: over_modbus,
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
    app.handle(
        Input::Arm(ArmEvent::Status(LinkStatus::Up {
            description: "test".into(),
        })),
        t0,
    );
    (app, t0)
}

/// The arm at `positions` (deg), every joint turning at `velocity` deg/s, action `status`.
fn telemetry(positions: [f32; 7], velocity: f32, status: Coded<ActionStatus>) -> Telemetry {
    let action = ActionState {
        status,
        id: 2,
        move_type: Coded::Known(MoveType::Action),
    };
    crate::app_support::arm_telemetry(positions, velocity, action)
}

const HOME: [f32; 7] = [0.0, 15.0, 180.0, 230.0, 0.0, 55.0, 90.0];

fn at_rest() -> Telemetry {
    telemetry(HOME, 0.0, Coded::Known(ActionStatus::Completed))
}

fn moving() -> Telemetry {
    telemetry(HOME, 12.0, Coded::Known(ActionStatus::Started))
}

fn feed(app: &mut App, t: Telemetry, now: Instant) -> Vec<Effect> {
    app.handle(Input::Arm(ArmEvent::Telemetry(Box::new(t))), now)
}

fn key(name: &str, kind: KeyKind) -> Input {
    let key: KeyName = name.parse().expect("key name");
    let text = name.chars().next().filter(|_| name.chars().count() == 1);
    Input::Key(KeyInput { key, text, kind })
}

fn press(app: &mut App, name: &str, now: Instant) -> Vec<Effect> {
    app.handle(key(name, KeyKind::Press), now)
}

fn may_be_moving(app: &App) -> bool {
    matches!(app.motion_shown(), MotionShown::MayBeMoving(_))
}

fn ack() -> Input {
    Input::Arm(ArmEvent::Log(LogEntry {
        name: "polar_start".into(),
        outcome: "ACK".into(),
        ok: true,
        count: 1,
        ..LogEntry::default()
    }))
}

// ---- LINK STALE ----

#[test]
fn telemetry_that_stops_makes_the_link_stale_after_500_ms_and_resuming_makes_it_fresh() {
    let (mut app, t0) = app(TelemetrySource::Modbus);
    for n in 0..10 {
        feed(&mut app, at_rest(), t0 + ms(33 * n));
    }
    let last = t0 + ms(33 * 9);
    app.handle(Input::Tick, last + ms(499));
    assert_eq!(app.link_stale(), None, "499 ms is not stale");
    assert_eq!(app.telemetry_stale(), None);
    let deadline = app.next_deadline().expect("a deadline at the stale onset");
    assert!(deadline <= last + ms(500), "woken in time to say it");
    app.handle(Input::Tick, last + ms(500));
    assert_eq!(app.link_stale(), Some(ms(500)));
    app.handle(Input::Tick, last + ms(1800));
    assert_eq!(app.link_stale(), Some(ms(1800)), "the age counts up");
    assert_eq!(app.telemetry_stale(), Some(ms(1800)), "panels show the age");
    feed(&mut app, at_rest(), last + ms(1850));
    assert_eq!(app.link_stale(), None, "telemetry again: up");
    assert_eq!(app.telemetry_stale(), None);
}

#[test]
fn a_link_polling_slower_than_500_ms_is_stale_after_three_of_its_intervals() {
    let (mut app, t0) = app(TelemetrySource::Modbus);
    for n in 0..5 {
        feed(&mut app, at_rest(), t0 + ms(1000 * n));
    }
    app.handle(Input::Tick, t0 + ms(4000 + 900));
    assert_eq!(app.link_stale(), None, "a 1 Hz poll is late only after 3 s");
    app.handle(Input::Tick, t0 + ms(4000 + 3000));
    assert!(app.link_stale().is_some());
}

#[test]
fn a_stale_link_while_jogging_stops_the_jog_and_starts_nothing_new() {
    let (mut app, t0) = app(TelemetrySource::Modbus);
    feed(&mut app, at_rest(), t0);
    assert!(!press(&mut app, "w", t0 + ms(10)).is_empty());
    feed(&mut app, moving(), t0 + ms(40));
    let mut effects = Vec::new();
    let mut now = t0 + ms(40);
    while now < t0 + ms(600) {
        now = app.next_deadline().expect("ticks while jogging").max(now);
        effects.extend(app.handle(Input::Tick, now));
        app.handle(
            Input::Arm(ArmEvent::Done {
                command: ArmCommand::Stop,
            }),
            now,
        );
        if effects.contains(&STOP) {
            break;
        }
    }
    assert!(effects.contains(&STOP), "stopped by the stale link");
    assert!(now <= t0 + ms(540 + 1), "at the stale onset, {now:?}");
    assert!(!app.jog().is_jogging());
    assert!(message(&app).contains("link stale"), "{}", message(&app));
    assert!(
        may_be_moving(&app),
        "{:?}: the STOP may not get through",
        app.motion_shown()
    );
    assert!(
        press(&mut app, "w", now + ms(10)).is_empty(),
        "no new motion on a stale link"
    );
    assert!(message(&app).contains("link stale: not moving"));
}

#[test]
fn an_ack_link_without_telemetry_is_stale_only_while_something_waits_for_an_answer() {
    let (mut app, t0) = app(TelemetrySource::None);
    app.handle(Input::Tick, t0 + ms(5000));
    assert_eq!(app.link_stale(), None, "idle and asked nothing: not stale");
    // Jogging: each START refresh is ACKed.
    let start = t0 + ms(5000);
    press(&mut app, "right", start);
    for n in 1..=10 {
        app.handle(ack(), start + ms(100 * n - 95));
        // The held key keeps auto-repeating, as a terminal with release events reports it.
        app.handle(key("right", KeyKind::Repeat), start + ms(100 * n - 50));
        app.handle(Input::Tick, start + ms(100 * n));
    }
    assert_eq!(app.link_stale(), None);
    assert!(app.jog().is_jogging(), "ACKed refreshes keep it going");
    // The ACKs stop: stale half a second after the first unanswered START (sent at 1000 ms).
    let mut stopped = None;
    for n in 11..=20 {
        let now = start + ms(100 * n);
        app.handle(key("right", KeyKind::Repeat), now - ms(50));
        if app.handle(Input::Tick, now).contains(&STOP) {
            stopped = Some(now);
            break;
        }
    }
    assert_eq!(stopped, Some(start + ms(1500)), "{:?}", app.link_stale());
}

// ---- MAY BE MOVING ----

#[test]
fn an_unconfirmed_stop_says_may_be_moving_on_screen_until_a_confirmed_stop_and_rest() {
    let (mut app, t0) = app(TelemetrySource::Modbus);
    feed(&mut app, at_rest(), t0);
    press(&mut app, "w", t0);
    feed(&mut app, moving(), t0 + ms(30));
    assert_eq!(app.handle(key("w", KeyKind::Release), t0 + ms(50)), [STOP]);
    assert_eq!(app.motion_shown(), MotionShown::Stopping);
    app.handle(
        Input::Arm(ArmEvent::StopUnconfirmed {
            reason: "the Modbus arm: no reply within 500ms".into(),
        }),
        t0 + ms(60),
    );
    let MotionShown::MayBeMoving(why) = app.motion_shown() else {
        panic!("{:?}", app.motion_shown());
    };
    assert!(why.contains("stop not confirmed"), "{why}");
    let (text, severity) = app.message().expect("said on the message line");
    assert!(
        text.contains("STOP NOT CONFIRMED") && text.contains("500ms"),
        "{text}"
    );
    assert_eq!(severity, Severity::Error);
    // Rest alone is no evidence the stop got through.
    feed(&mut app, at_rest(), t0 + ms(100));
    assert!(may_be_moving(&app));
    // Nor is a confirmation alone, where telemetry exists.
    press(&mut app, "space", t0 + ms(200));
    app.handle(Input::Arm(ArmEvent::StopConfirmed), t0 + ms(210));
    assert_eq!(app.motion_shown(), MotionShown::Stopping);
    app.handle(Input::Tick, t0 + ms(210) + STOP_GRACE);
    assert!(may_be_moving(&app), "no telemetry at rest since the stop");
    feed(&mut app, at_rest(), t0 + ms(800));
    assert_eq!(app.motion_shown(), MotionShown::Idle);
}

#[test]
fn a_stop_not_acknowledged_within_the_grace_turns_stopping_into_may_be_moving() {
    let (mut app, t0) = app(TelemetrySource::None);
    press(&mut app, "w", t0);
    app.handle(key("w", KeyKind::Release), t0 + ms(100));
    assert_eq!(app.motion_shown(), MotionShown::Stopping);
    let deadline = app.next_deadline().expect("a deadline for the grace");
    assert!(deadline <= t0 + ms(100) + STOP_GRACE);
    app.handle(Input::Tick, t0 + ms(100) + STOP_GRACE);
    assert!(may_be_moving(&app), "{:?}", app.motion_shown());
    // Without telemetry a confirmed stop is all the evidence there is.
    app.handle(Input::Arm(ArmEvent::StopConfirmed), t0 + ms(700));
    assert_eq!(app.motion_shown(), MotionShown::Idle);
}

#[test]
fn a_lost_link_after_motion_says_may_be_moving_until_a_stop_is_confirmed() {
    let (mut app, t0) = app(TelemetrySource::None);
    press(&mut app, "w", t0);
    let down = ArmEvent::Status(LinkStatus::Down {
        reason: "reset".into(),
    });
    assert_eq!(app.handle(Input::Arm(down), t0 + ms(10)), [STOP]);
    assert_eq!(
        app.motion_shown(),
        MotionShown::MayBeMoving("link lost after motion".into())
    );
    let up = ArmEvent::Status(LinkStatus::Up {
        description: "back".into(),
    });
    assert_eq!(
        app.handle(Input::Arm(up), t0 + ms(2000)),
        [STOP],
        "the console stops it once it can reach it"
    );
    assert_ne!(
        app.motion_shown(),
        MotionShown::Idle,
        "back up proves nothing"
    );
    app.handle(Input::Arm(ArmEvent::StopConfirmed), t0 + ms(2110));
    assert_eq!(app.motion_shown(), MotionShown::Idle);
}

#[test]
fn a_confirmation_of_a_stop_older_than_the_last_motion_is_no_evidence() {
    let (mut app, t0) = app(TelemetrySource::None);
    press(&mut app, "w", t0);
    app.handle(key("w", KeyKind::Release), t0 + ms(50));
    press(&mut app, "w", t0 + ms(60));
    app.handle(Input::Arm(ArmEvent::StopConfirmed), t0 + ms(70));
    app.handle(key("w", KeyKind::Release), t0 + ms(80));
    app.handle(Input::Tick, t0 + ms(80) + STOP_GRACE);
    assert!(may_be_moving(&app), "the second STOP is still unanswered");
}

#[test]
fn telemetry_showing_velocity_says_may_be_moving_when_nothing_was_commanded() {
    let (mut app, t0) = app(TelemetrySource::TalosHardware);
    feed(&mut app, at_rest(), t0);
    assert_eq!(app.motion_shown(), MotionShown::Idle);
    let mut drifting = at_rest();
    drifting.tcp.twist.z = 0.01;
    feed(&mut app, drifting, t0 + ms(100));
    assert_eq!(
        app.motion_shown(),
        MotionShown::MayBeMoving("telemetry shows motion".into())
    );
    let mut nan = at_rest();
    nan.joints[3].velocity = f32::NAN;
    feed(&mut app, nan, t0 + ms(200));
    assert!(may_be_moving(&app), "an unreadable velocity is no rest");
    feed(&mut app, at_rest(), t0 + ms(300));
    assert_eq!(app.motion_shown(), MotionShown::Idle);
}

// ---- MOVING: HOME / GOTO ----

fn start_home(app: &mut App, now: Instant) {
    // Asked a moment before: a question ignores keys for its first moments.
    press(app, "h", now - QUESTION_QUIET);
    assert_eq!(press(app, "y", now), [Effect::Arm(ArmCommand::Home)]);
    app.handle(
        Input::Arm(ArmEvent::Done {
            command: ArmCommand::Home,
        }),
        now + ms(5),
    );
}

fn moving_home() -> MotionShown {
    MotionShown::Action {
        label: "HOME".into(),
        confirmed: true,
    }
}

#[test]
fn home_shows_moving_until_the_action_completes_at_rest() {
    let (mut app, t0) = app(TelemetrySource::Modbus);
    feed(&mut app, at_rest(), t0);
    start_home(&mut app, t0);
    // A poll from before the start still says the last action completed: not the end.
    feed(&mut app, at_rest(), t0 + ms(20));
    assert_eq!(app.motion_shown(), moving_home());
    for n in 1..40 {
        feed(&mut app, moving(), t0 + ms(20 + 100 * n));
        assert_eq!(app.motion_shown(), moving_home());
    }
    feed(&mut app, at_rest(), t0 + ms(4100));
    assert_eq!(app.motion_shown(), MotionShown::Idle);
    assert_eq!(message(&app), "home done");
}

#[test]
fn an_unknown_action_that_the_arm_aborts_at_once_is_a_failure() {
    let (mut app, t0) = app(TelemetrySource::Modbus);
    start_home(&mut app, t0);
    let aborted = telemetry(HOME, 0.0, Coded::Known(ActionStatus::Aborted));
    feed(&mut app, aborted.clone(), t0 + ms(100));
    assert_eq!(
        app.motion_shown(),
        moving_home(),
        "could be an older status"
    );
    let effects = feed(&mut app, aborted, t0 + ms(600));
    assert_eq!(message(&app), "home failed: aborted");
    assert_eq!(effects, [STOP], "a STOP makes sure and settles the doubt");
}

#[test]
fn a_home_aborted_at_a_joint_limit_names_the_joint_and_is_never_ok() {
    let (mut app, t0) = app(TelemetrySource::Modbus);
    start_home(&mut app, t0);
    let mut near = HOME;
    near[3] = 146.9;
    feed(
        &mut app,
        telemetry(near, 20.0, Coded::Known(ActionStatus::Started)),
        t0 + ms(50),
    );
    let mut stopped = telemetry(near, 0.0, Coded::Known(ActionStatus::Aborted));
    stopped.warnings = FlagSet::from_bits(Flag::JointFault.bit());
    assert_eq!(feed(&mut app, stopped, t0 + ms(90)), [STOP]);
    let (text, severity) = app.message().expect("a message");
    assert_eq!(text, "home failed: aborted, J4 at its limit");
    assert_eq!(severity, Severity::Error);
    assert!(!app.log().iter().any(|e| e.name == "home" && e.ok));
    // The STOP is confirmed and the arm at rest: settled.
    app.handle(Input::Arm(ArmEvent::StopConfirmed), t0 + ms(100));
    feed(&mut app, at_rest(), t0 + ms(130));
    assert_eq!(app.motion_shown(), MotionShown::Idle);
}

#[test]
fn a_home_on_an_arm_in_fault_fails() {
    let (mut app, t0) = app(TelemetrySource::Modbus);
    start_home(&mut app, t0);
    let mut fault = at_rest();
    fault.robot_state = Coded::Known(RobotState::InFault);
    fault.faults = FlagSet::from_bits(Flag::EmergencyStop.bit());
    feed(&mut app, fault, t0 + ms(40));
    assert_eq!(
        message(&app),
        "home failed: the arm is in fault: emergency_stop"
    );
    assert!(app.motion_truth().action().is_none());
}

#[test]
fn over_talos_hardware_telemetry_home_ends_at_rest_after_moving_or_at_a_joint_fault() {
    let unknown = Coded::Unknown(u16::MAX);
    let (mut app, t0) = app(TelemetrySource::TalosHardware);
    start_home(&mut app, t0);
    feed(&mut app, telemetry(HOME, 8.0, unknown), t0 + ms(100));
    feed(&mut app, telemetry(HOME, 0.0, unknown), t0 + ms(200));
    assert_eq!(message(&app), "home done");
    // Already home: nothing moves; done a second after the start.
    feed(&mut app, telemetry(HOME, 0.0, unknown), t0 + ms(1000));
    start_home(&mut app, t0 + ms(1000));
    feed(&mut app, telemetry(HOME, 0.0, unknown), t0 + ms(1100));
    assert_eq!(app.motion_shown(), moving_home());
    feed(&mut app, telemetry(HOME, 0.0, unknown), t0 + ms(2100));
    assert_eq!(app.motion_shown(), MotionShown::Idle);
    // Stopped by a joint limit on the way.
    feed(&mut app, telemetry(HOME, 0.0, unknown), t0 + ms(3000));
    start_home(&mut app, t0 + ms(3000));
    let mut near = HOME;
    near[1] = 127.5;
    feed(&mut app, telemetry(near, 8.0, unknown), t0 + ms(3100));
    let mut stopped = telemetry(near, 0.0, unknown);
    stopped.warnings = FlagSet::from_bits(Flag::JointFault.bit());
    feed(&mut app, stopped, t0 + ms(3200));
    assert_eq!(message(&app), "home failed: aborted, J2 at its limit");
}

#[test]
fn without_telemetry_home_may_be_moving_until_a_confirmed_stop_or_its_expected_time() {
    let (mut app, t0) = app(TelemetrySource::None);
    start_home(&mut app, t0);
    let unconfirmed = MotionShown::Action {
        label: "HOME".into(),
        confirmed: false,
    };
    assert_eq!(app.motion_shown(), unconfirmed);
    app.handle(Input::Tick, t0 + NO_TELEMETRY_ACTION_TIME - ms(1));
    assert_eq!(app.motion_shown(), unconfirmed);
    app.handle(Input::Tick, t0 + NO_TELEMETRY_ACTION_TIME);
    assert_eq!(app.motion_shown(), MotionShown::Idle);
    // A stop ends it sooner.
    let later = t0 + ms(60_000);
    start_home(&mut app, later);
    assert_eq!(press(&mut app, "space", later + ms(500)), [STOP]);
    app.handle(Input::Arm(ArmEvent::StopConfirmed), later + ms(510));
    assert_eq!(app.motion_shown(), MotionShown::Idle);
}

#[test]
fn a_failed_home_command_stops_and_reports() {
    let (mut app, t0) = app(TelemetrySource::TalosHardware);
    press(&mut app, "h", t0);
    press(&mut app, "y", t0 + QUESTION_QUIET);
    let failed = ArmEvent::Failed {
        command: CommandKind::Home,
        error: ArmError::Modbus(
            armjog::link::modbus::ModbusError::Disconnected {
                reason: "connection reset".into(),
            }
            .into(),
        ),
    };
    assert_eq!(app.handle(Input::Arm(failed), t0 + ms(5)), [STOP]);
    assert_eq!(
        message(&app),
        "home failed: not connected to the arm: connection reset"
    );
    assert!(app.motion_truth().action().is_none());
}

#[test]
fn go_to_over_modbus_shows_the_position_name() {
    let (mut app, t0) = app(TelemetrySource::Modbus);
    feed(&mut app, at_rest(), t0);
    let mut book = PositionBook::new();
    let bench = book.get_or_insert("bench");
    bench.cartesian = Some([4000, 1000, 3000]);
    bench.orientation = Some([90.0, 0.0, 90.0]);
    app.handle(Input::PositionsLoaded(Ok(book)), t0);
    press(&mut app, "o", t0);
    let effects = press(&mut app, "y", t0 + QUESTION_QUIET);
    assert!(
        matches!(effects.as_slice(), [Effect::Arm(ArmCommand::MoveToPose(_))]),
        "{effects:?}"
    );
    assert_eq!(
        app.motion_shown(),
        MotionShown::Action {
            label: "GOTO bench".into(),
            confirmed: true,
        }
    );
}

#[test]
fn a_go_to_the_link_cannot_carry_ends_its_tracking_and_stops() {
    let (mut app, t0) = app(TelemetrySource::Modbus);
    feed(&mut app, at_rest(), t0);
    let mut book = PositionBook::new();
    let bench = book.get_or_insert("bench");
    bench.cartesian = Some([4000, 1000, 3000]);
    bench.orientation = Some([90.0, 0.0, 90.0]);
    app.handle(Input::PositionsLoaded(Ok(book)), t0);
    press(&mut app, "o", t0);
    press(&mut app, "y", t0 + QUESTION_QUIET);
    let failed = ArmEvent::Failed {
        command: CommandKind::MoveToPose,
        error: ArmError::NoLinkCarriesIt,
    };
    assert_eq!(app.handle(Input::Arm(failed), t0 + ms(2)), [STOP]);
    assert!(app.motion_truth().action().is_none());
    assert_eq!(
        message(&app),
        "move to pose failed: not possible over this link"
    );
}

#[test]
fn ages_count_in_tenths_then_whole_seconds() {
    use armjog::console::app::age_text;
    assert_eq!(age_text(ms(1849)), "1.8 s");
    assert_eq!(age_text(ms(42_300)), "42 s");
    let (mut app, t0) = app(TelemetrySource::Modbus);
    feed(&mut app, at_rest(), t0);
    app.handle(Input::Tick, t0 + ms(2000));
    assert_eq!(
        app.next_deadline(),
        Some(t0 + ms(2100)),
        "tenths while young"
    );
    app.handle(Input::Tick, t0 + ms(20_000));
    assert_eq!(
        app.next_deadline(),
        Some(t0 + ms(21_000)),
        "seconds when old"
    );
}

#[test]
fn a_joint_limit_hit_between_two_polls_is_still_an_abort() {
    let unknown = Coded::Unknown(u16::MAX);
    let (mut app, t0) = app(TelemetrySource::TalosHardware);
    let mut near = HOME;
    near[3] = 145.8;
    feed(&mut app, telemetry(near, 0.0, unknown), t0);
    start_home(&mut app, t0);
    // The next poll already finds the arm stopped at the limit, never seen moving.
    near[3] = 147.8;
    let mut stopped = telemetry(near, 0.0, unknown);
    stopped.warnings = FlagSet::from_bits(Flag::JointFault.bit());
    feed(&mut app, stopped, t0 + ms(100));
    assert_eq!(message(&app), "home failed: aborted, J4 at its limit");
}

#[test]
fn a_joint_fault_warning_from_before_the_start_is_not_this_actions_abort() {
    let unknown = Coded::Unknown(u16::MAX);
    let (mut app, t0) = app(TelemetrySource::TalosHardware);
    let mut warned = telemetry(HOME, 0.0, unknown);
    warned.warnings = FlagSet::from_bits(Flag::JointFault.bit());
    feed(&mut app, warned.clone(), t0);
    start_home(&mut app, t0);
    feed(&mut app, warned.clone(), t0 + ms(100));
    assert_eq!(app.motion_shown(), moving_home());
    feed(&mut app, warned, t0 + ms(1100));
    assert_eq!(message(&app), "home done", "already home, nothing moved");
}

#[test]
fn a_stale_link_starts_no_home_step_or_go_to() {
    let (mut app, t0) = app(TelemetrySource::TalosHardware);
    feed(&mut app, at_rest(), t0);
    let stale = t0 + ms(800);
    // Refused at the key: no question is asked whose yes could not move.
    assert!(press(&mut app, "h", stale).is_empty(), "no home");
    assert_eq!(app.overlay(), &Overlay::None);
    assert_eq!(message(&app), "link stale: not moving");
    assert!(press(&mut app, "o", stale).is_empty(), "no go-to");
    assert_eq!(app.overlay(), &Overlay::None);
    press(&mut app, "t", stale);
    assert!(press(&mut app, "w", stale).is_empty(), "no step");
    assert!(app.motion_truth().action().is_none());
    // Fresh again: a new press moves.
    app.handle(key("w", KeyKind::Release), stale + ms(5));
    feed(&mut app, at_rest(), stale + ms(10));
    assert_eq!(
        press(&mut app, "w", stale + ms(20)),
        [Effect::Arm(ArmCommand::Step(
            armjog::link::interface::StepMove::Cartesian {
                dx: 50,
                dy: 0,
                dz: 0
            }
        ))]
    );
}

#[test]
fn an_abort_names_a_joint_as_the_cause_only_when_the_arm_reports_a_joint_fault() {
    let mut near = HOME;
    near[3] = 146.0;
    let mut t = telemetry(near, 0.0, Coded::Known(ActionStatus::Aborted));
    // Aborted by hand (or by anything else) near a limit: where the joint was, not why.
    assert_eq!(abort_reason(&t), "aborted, J4 near its limit");
    t.warnings = FlagSet::from_bits(Flag::JointFault.bit());
    assert_eq!(abort_reason(&t), "aborted, J4 at its limit");
    // Right at the limit it is the cause, even before the warning shows in a poll.
    near[3] = 147.6;
    let at = telemetry(near, 0.0, Coded::Known(ActionStatus::Aborted));
    assert_eq!(abort_reason(&at), "aborted, J4 at its limit");
    let far = telemetry(HOME, 0.0, Coded::Known(ActionStatus::Aborted));
    assert_eq!(abort_reason(&far), "aborted");
}

#[test]
fn a_link_back_after_a_loss_mid_jog_gets_a_stop_whose_confirmation_settles_it() {
    let (mut app, t0) = app(TelemetrySource::Modbus);
    feed(&mut app, at_rest(), t0);
    press(&mut app, "w", t0);
    feed(&mut app, moving(), t0 + ms(30));
    let down = Input::Arm(ArmEvent::Status(LinkStatus::Down {
        reason: "connection reset".into(),
    }));
    app.handle(down, t0 + ms(50));
    assert!(matches!(app.motion_shown(), MotionShown::MayBeMoving(_)));
    let up = Input::Arm(ArmEvent::Status(LinkStatus::Up {
        description: "test".into(),
    }));
    assert!(
        app.handle(up, t0 + ms(2000)).contains(&STOP),
        "the console asks the arm to stop once it can be reached again"
    );
    app.handle(Input::Arm(ArmEvent::StopConfirmed), t0 + ms(2010));
    feed(&mut app, at_rest(), t0 + ms(2040));
    assert_eq!(app.motion_shown(), MotionShown::Idle);
}

#[test]
fn a_home_on_a_link_that_goes_stale_is_stopped() {
    let (mut app, t0) = app(TelemetrySource::Modbus);
    feed(&mut app, at_rest(), t0);
    start_home(&mut app, t0);
    feed(&mut app, moving(), t0 + ms(100));
    assert_eq!(app.motion_shown(), moving_home());
    // The telemetry stops: past 500 ms the home can no longer be watched, so it is stopped.
    assert_eq!(app.handle(Input::Tick, t0 + ms(700)), [STOP]);
    assert_ne!(app.motion_shown(), moving_home());
    assert_ne!(app.motion_shown(), MotionShown::Idle);
    assert!(
        app.handle(Input::Tick, t0 + ms(900)).is_empty(),
        "one STOP, not one per tick"
    );
}
