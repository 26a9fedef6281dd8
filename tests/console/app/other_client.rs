//! Another client on the same arm (fake clock): its STOP is a STOP (the held keys latch, the
//! message says so, and the next refresh starts nothing), the arm's own start-up is not taken
//! for one, and its motion while the console is idle is `MOVED BY ANOTHER CLIENT`.

use std::time::Instant;

use armjog::console::app::{
    App, AppConfig, Effect, Input, MotionShown, OTHER_CLIENT_GRACE, OTHER_CLIENT_SAMPLES,
};
use armjog::console::jog::KeyKind;
use armjog::console::positions::PositionBook;
use armjog::kortex::{
    ActionStatus, Coded, Flag, FlagSet, MoveType, RegisterImage, RobotState, Telemetry,
};
use armjog::link::interface::{ArmEvent, LinkStatus, TelemetrySource};

use crate::app_support::{STOP, buffer_text, config, jog, key, message, ms, press, screen};

/// A ready arm; the tool moving along X at `mm_s`, its action started, a twist.
fn moving_at(mm_s: f32) -> Telemetry {
    let mut t = Telemetry::decode(&RegisterImage::default());
    t.robot_state = Coded::Known(RobotState::Ready);
    t.action.status = Coded::Known(ActionStatus::Started);
    t.action.move_type = Coded::Known(MoveType::Twist);
    t.joints[1].position = 15.0;
    t.tcp.twist.x = mm_s / 1000.0;
    t
}

fn at_rest() -> Telemetry {
    moving_at(0.0)
}

fn console(source: TelemetrySource) -> (App, Instant) {
    let config = AppConfig {
        positions_on_operator: source != TelemetrySource::Modbus,
        ..config()
    };
    let mut app = App::new(config, PositionBook::new());
    let t0 = Instant::now();
    for event in [
        ArmEvent::TelemetrySource(source),
        ArmEvent::Status(LinkStatus::Up {
            description: "test".into(),
        }),
        ArmEvent::Speed(50),
    ] {
        app.handle(Input::Arm(event), t0);
    }
    feed(&mut app, at_rest(), t0);
    (app, t0)
}

fn feed(app: &mut App, t: Telemetry, now: Instant) -> Vec<Effect> {
    app.handle(Input::Arm(ArmEvent::Telemetry(Box::new(t))), now)
}

/// The key every test holds: `w`, +X.
const HELD: &str = "w";

/// Feeds `t` every 33 ms over `from..to`, with the held key's repeats and the jog's refreshes
/// due meanwhile; every effect.
fn run(app: &mut App, t: &Telemetry, from: Instant, to: Instant) -> Vec<Effect> {
    let mut effects = Vec::new();
    let mut now = from;
    while now < to {
        let mut step = feed(app, t.clone(), now);
        step.extend(app.handle(key(HELD, KeyKind::Repeat), now + ms(1)));
        step.extend(app.handle(Input::Tick, now + ms(2)));
        // The arm answers every command, as a live link does (else the link goes stale).
        for effect in &step {
            if let Effect::Arm(command) = effect {
                let done = ArmEvent::Done {
                    command: command.clone(),
                };
                app.handle(Input::Arm(done), now + ms(3));
            }
        }
        effects.extend(step);
        now += ms(33);
    }
    effects
}

/// The arm takes the jog's START.
fn answer(app: &mut App, now: Instant) {
    let command =
        armjog::link::interface::ArmCommand::Jog(armjog::console::jog::JogMotion::Cartesian {
            x: 1,
            y: 0,
            z: 0,
        });
    app.handle(Input::Arm(ArmEvent::Done { command }), now + ms(1));
}

fn starts(effects: &[Effect]) -> usize {
    effects
        .iter()
        .filter(|e| matches!(e, Effect::Arm(c) if c.starts_motion()))
        .count()
}

#[test]
fn at_rest_right_after_our_start_is_the_arm_starting_up_not_another_client() {
    let (mut app, t0) = console(TelemetrySource::TalosHardware);
    assert_eq!(press(&mut app, "w", t0), [jog(1, 0, 0)]);
    // At rest for the whole grace (15 samples): the arm is still starting.
    let effects = run(&mut app, &at_rest(), t0, t0 + OTHER_CLIENT_GRACE);
    assert!(!effects.contains(&STOP), "{effects:?}");
    assert!(app.jog().is_jogging());
    // Then moving: the jog runs on, refreshed.
    let effects = run(
        &mut app,
        &moving_at(125.0),
        t0 + OTHER_CLIENT_GRACE,
        t0 + ms(2000),
    );
    assert!(!effects.contains(&STOP), "{effects:?}");
    assert!(starts(&effects) >= 10, "refreshed: {effects:?}");
    assert_eq!(
        app.motion_shown(),
        MotionShown::Jog(armjog::console::jog::JogMotion::Cartesian { x: 1, y: 0, z: 0 })
    );
}

#[test]
fn at_rest_after_the_grace_while_we_jog_is_another_client_s_stop_and_latches() {
    let (mut app, t0) = console(TelemetrySource::TalosHardware);
    press(&mut app, "w", t0);
    let moving_until = t0 + ms(1000);
    run(&mut app, &moving_at(125.0), t0, moving_until);
    assert!(app.jog().is_jogging());
    // Someone else's STOP: at rest. Two samples may be a glitch; the third stops.
    let mut now = moving_until;
    for n in 1..OTHER_CLIENT_SAMPLES {
        assert!(
            !feed(&mut app, at_rest(), now).contains(&STOP),
            "sample {n}"
        );
        now += ms(33);
    }
    assert_eq!(feed(&mut app, at_rest(), now), [STOP]);
    app.handle(Input::Arm(ArmEvent::StopConfirmed), now + ms(1));
    assert!(!app.jog().is_jogging());
    assert_eq!(
        message(&app),
        "stopped by another client: the arm is at rest while we jog +X"
    );
    assert_eq!(app.other_clients().stops(), 1);
    // The key is still held: the next refresh, its repeats and more telemetry start nothing.
    let effects = run(&mut app, &at_rest(), now + ms(10), now + ms(1000));
    assert_eq!(starts(&effects), 0, "{effects:?}");
    assert_eq!(
        starts(&app.handle(key("w", KeyKind::Repeat), now + ms(1010))),
        0
    );
    // The screen shows what the telemetry shows, not the jog sent.
    assert_ne!(
        app.motion_shown(),
        MotionShown::Jog(armjog::console::jog::JogMotion::Cartesian { x: 1, y: 0, z: 0 })
    );
    // Released and pressed anew, it moves again.
    app.handle(key("w", KeyKind::Release), now + ms(1020));
    assert_eq!(press(&mut app, "w", now + ms(1030)), [jog(1, 0, 0)]);
}

#[test]
fn over_modbus_an_aborted_action_under_our_twist_stops_at_once() {
    let (mut app, t0) = console(TelemetrySource::Modbus);
    // The status still reads aborted from before our START: within the grace, not evidence.
    let mut aborted = moving_at(125.0);
    aborted.action.status = Coded::Known(ActionStatus::Aborted);
    press(&mut app, "w", t0);
    answer(&mut app, t0);
    assert!(!feed(&mut app, aborted.clone(), t0 + ms(33)).contains(&STOP));
    run(&mut app, &moving_at(125.0), t0 + ms(66), t0 + ms(800));
    assert!(app.jog().is_jogging());
    // After it, one sample is enough (a register, not a noisy reading).
    assert_eq!(feed(&mut app, aborted, t0 + ms(833)), [STOP]);
    assert_eq!(
        message(&app),
        "stopped by another client: the arm's action is aborted (twist) under our +X jog"
    );
    assert!(!app.jog().is_jogging());
    assert_eq!(starts(&app.handle(Input::Tick, t0 + ms(950))), 0);
}

#[test]
fn over_modbus_another_move_type_under_our_twist_is_another_client() {
    let (mut app, t0) = console(TelemetrySource::Modbus);
    press(&mut app, "w", t0);
    run(&mut app, &moving_at(125.0), t0, t0 + ms(700));
    let mut trajectory = moving_at(125.0);
    trajectory.action.move_type = Coded::Known(MoveType::CartesianTrajectory);
    assert_eq!(feed(&mut app, trajectory, t0 + ms(733)), [STOP]);
    assert!(
        message(&app).starts_with("stopped by another client: "),
        "{}",
        message(&app)
    );
}

#[test]
fn a_stop_at_a_joint_limit_is_the_arm_s_own_and_says_so() {
    let (mut app, t0) = console(TelemetrySource::TalosHardware);
    press(&mut app, "w", t0);
    run(&mut app, &moving_at(125.0), t0, t0 + ms(700));
    let mut at_limit = at_rest();
    at_limit.warnings = FlagSet::from_bits(Flag::JointFault.bit());
    let effects = run(&mut app, &at_limit, t0 + ms(700), t0 + ms(850));
    assert!(effects.contains(&STOP), "{effects:?}");
    assert!(
        message(&app).starts_with("jog stopped by the arm: aborted"),
        "{}",
        message(&app)
    );
    assert_eq!(app.other_clients().stops(), 0);
}

#[test]
fn a_creeping_jog_at_1_percent_is_not_taken_for_rest() {
    let (mut app, t0) = console(TelemetrySource::TalosHardware);
    app.handle(Input::Arm(ArmEvent::Speed(1)), t0);
    press(&mut app, "w", t0);
    // 2.5 mm/s reads close to the at-rest threshold: never another client's stop.
    let effects = run(&mut app, &moving_at(1.5), t0, t0 + ms(2000));
    assert!(!effects.contains(&STOP), "{effects:?}");
    assert!(app.jog().is_jogging());
}

#[test]
fn idle_while_the_telemetry_moves_is_moved_by_another_client() {
    let (mut app, t0) = console(TelemetrySource::Modbus);
    // Idle, nothing of ours: at rest, then moving at 100 mm/s.
    run(&mut app, &at_rest(), t0, t0 + ms(300));
    assert_eq!(app.motion_shown(), MotionShown::Idle);
    let moving = moving_at(100.0);
    let mut now = t0 + ms(300);
    for _ in 1..OTHER_CLIENT_SAMPLES {
        feed(&mut app, moving.clone(), now);
        now += ms(33);
        assert_ne!(app.motion_shown(), MotionShown::MovedByAnotherClient);
    }
    feed(&mut app, moving.clone(), now);
    assert_eq!(app.motion_shown(), MotionShown::MovedByAnotherClient);
    let text = buffer_text(screen(&app, 100, 30).backend().buffer());
    assert!(text.contains("MOVED BY ANOTHER CLIENT"), "{text}");
    assert!(!text.contains(" idle "), "no claim of idle: {text}");
    // At rest again: idle again.
    feed(&mut app, at_rest(), now + ms(33));
    assert_eq!(app.motion_shown(), MotionShown::Idle);
    // Slow drift under the threshold is not another client's motion.
    feed(&mut app, moving_at(5.0), now + ms(66));
    feed(&mut app, moving_at(5.0), now + ms(99));
    feed(&mut app, moving_at(5.0), now + ms(132));
    assert_ne!(app.motion_shown(), MotionShown::MovedByAnotherClient);
}

#[test]
fn our_own_motion_coasting_after_a_stop_is_not_another_client() {
    let (mut app, t0) = console(TelemetrySource::Modbus);
    press(&mut app, "w", t0);
    run(&mut app, &moving_at(125.0), t0, t0 + ms(300));
    app.handle(key("w", KeyKind::Release), t0 + ms(300));
    app.handle(Input::Arm(ArmEvent::StopConfirmed), t0 + ms(310));
    // Still moving (decelerating) after our STOP: ours, unsettled, not another client's.
    run(&mut app, &moving_at(80.0), t0 + ms(320), t0 + ms(600));
    assert_ne!(app.motion_shown(), MotionShown::MovedByAnotherClient);
}

#[test]
fn an_arm_that_never_reports_a_twist_move_type_is_not_taken_for_another_client() {
    let (mut app, t0) = console(TelemetrySource::Modbus);
    press(&mut app, "w", t0);
    let mut silent = moving_at(125.0);
    silent.action.move_type = Coded::Known(MoveType::Action);
    let effects = run(&mut app, &silent, t0, t0 + ms(2000));
    assert!(!effects.contains(&STOP), "{effects:?}");
    assert!(app.jog().is_jogging());
}

fn stops(effects: &[Effect]) -> usize {
    effects.iter().filter(|e| **e == STOP).count()
}

#[test]
fn the_technicians_stop_is_sent_again_while_the_arm_moves_after_it() {
    let (mut app, t0) = console(TelemetrySource::Modbus);
    assert_eq!(stops(&press(&mut app, "space", t0)), 1);
    // Slowing down under our STOP, and soon after it: nothing more yet.
    assert_eq!(stops(&feed(&mut app, moving_at(100.0), t0 + ms(60))), 0);
    // Still moving a poll or three later: the STOP goes again, without a word while the arm
    // may still be slowing down.
    assert_eq!(stops(&feed(&mut app, moving_at(100.0), t0 + ms(120))), 1);
    assert!(
        !message(&app).contains("another client"),
        "{}",
        message(&app)
    );
    assert_eq!(stops(&feed(&mut app, moving_at(100.0), t0 + ms(150))), 0);
    // Moving long after a STOP is someone else's restart: stopped again, and said.
    assert_eq!(stops(&feed(&mut app, moving_at(100.0), t0 + ms(420))), 1);
    assert_eq!(
        message(&app),
        "the arm moved after our STOP (another client?): stopped again"
    );
    assert_eq!(stops(&feed(&mut app, at_rest(), t0 + ms(600))), 0);
    // The hold is over: the arm's motion is another client's to show, not ours to stop.
    assert_eq!(stops(&feed(&mut app, moving_at(100.0), t0 + ms(1100))), 0);
    assert_eq!(app.other_clients().stop_hold().resent(), 2);
}

#[test]
fn a_motion_of_our_own_after_the_stop_is_not_stopped_again() {
    let (mut app, t0) = console(TelemetrySource::Modbus);
    press(&mut app, "space", t0);
    app.handle(key("space", KeyKind::Release), t0 + ms(10));
    assert_eq!(press(&mut app, "w", t0 + ms(50)), [jog(1, 0, 0)]);
    assert_eq!(stops(&feed(&mut app, moving_at(100.0), t0 + ms(200))), 0);
    assert_eq!(app.other_clients().stop_hold().resent(), 0);
}
