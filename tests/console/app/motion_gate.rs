//! The arm's own state gates motion (fake clock): a fault, an emergency stop, a state other
//! than ready/controlled, telemetry that is not a number or out of physical range each refuse a
//! jog, a step, home and go-to, with a message naming the cause; a fault appearing during a jog
//! stops it and latches the key.

use std::time::Instant;

use armjog::console::app::{App, Effect, Input, Overlay};
use armjog::console::jog::KeyKind;
use armjog::console::positions::PositionBook;
use armjog::kortex::{Coded, Flag, FlagSet, MoveType, RegisterImage, RobotState, Telemetry};
use armjog::link::interface::{ArmCommand, ArmEvent, LinkStatus, TelemetrySource};

use crate::app_support::{STOP, config, jog, key, message, ms, press};

/// A ready arm at home, at rest.
fn ready() -> Telemetry {
    let mut t = Telemetry::decode(&RegisterImage::default());
    t.robot_state = Coded::Known(RobotState::Ready);
    t.action.move_type = Coded::Known(MoveType::Twist);
    for (joint, deg) in t
        .joints
        .iter_mut()
        .zip([0.0, 15.0, 180.0, 230.0, 0.0, 55.0, 90.0])
    {
        joint.position = deg;
    }
    t.tcp.pose.x = 0.4566;
    t.tcp.pose.z = 0.4338;
    t
}

/// A console on a Talos operator (it keeps the positions; "bench" is one) with Modbus
/// telemetry, link up, fed `t`.
fn console(t: Telemetry) -> (App, Instant) {
    let config = config();
    let mut book = PositionBook::new();
    book.get_or_insert("bench").cartesian = Some([4000, 0, 3000]);
    let mut app = App::new(config, book);
    let t0 = Instant::now();
    for event in [
        ArmEvent::TelemetrySource(TelemetrySource::Modbus),
        ArmEvent::Status(LinkStatus::Up {
            description: "test".into(),
        }),
    ] {
        app.handle(Input::Arm(event), t0);
    }
    feed(&mut app, t, t0);
    (app, t0)
}

fn feed(app: &mut App, t: Telemetry, now: Instant) -> Vec<Effect> {
    app.handle(Input::Arm(ArmEvent::Telemetry(Box::new(t))), now)
}

fn moves(effects: &[Effect]) -> Vec<&Effect> {
    effects
        .iter()
        .filter(|e| matches!(e, Effect::Arm(c) if c.starts_motion()))
        .collect()
}

/// Every way to start a motion, from `app` as it is: jog, turn... each refused with `why`.
fn assert_everything_refused(t: Telemetry, why: &str) {
    let (mut app, t0) = console(t.clone());
    assert_eq!(app.motion_refusal().as_deref(), Some(why));

    // A cartesian jog, a polar pan, a joint jog and a turn of the tool.
    for (n, k) in ["w", "right", "k", "i"].iter().enumerate() {
        let now = t0 + ms(10 * n as u64);
        let effects = press(&mut app, k, now);
        assert!(moves(&effects).is_empty(), "{k}: {effects:?}");
        assert_eq!(message(&app), why, "{k}");
        assert!(!app.jog().is_jogging(), "{k}");
        app.handle(key(k, KeyKind::Release), now + ms(1));
    }
    // The refresh time passes: nothing starts by itself.
    assert!(moves(&app.handle(Input::Tick, t0 + ms(200))).is_empty());

    // A step.
    press(&mut app, "t", t0 + ms(300));
    let effects = press(&mut app, "w", t0 + ms(310));
    assert!(moves(&effects).is_empty(), "step: {effects:?}");
    assert_eq!(message(&app), why, "step");
    app.handle(key("w", KeyKind::Release), t0 + ms(311));
    press(&mut app, "t", t0 + ms(320));

    // Home and go-to: not even asked.
    for k in ["h", "o"] {
        let effects = press(&mut app, k, t0 + ms(400));
        assert!(moves(&effects).is_empty(), "{k}: {effects:?}");
        assert_eq!(app.overlay(), &Overlay::None, "{k} asks nothing");
        assert_eq!(message(&app), why, "{k}");
    }

    // Asked while the arm was fine, answered once it is not: refused at the answer.
    for k in ["h", "o"] {
        let (mut app, t0) = console(ready());
        press(&mut app, k, t0);
        assert!(matches!(app.overlay(), Overlay::Confirm(_)), "{k}");
        feed(&mut app, t.clone(), t0 + ms(10));
        // Answered after the question's first 150 ms, as a person answers.
        let effects = press(&mut app, "y", t0 + ms(200));
        assert!(moves(&effects).is_empty(), "{k} y: {effects:?}");
        assert_eq!(message(&app), why, "{k} y");
    }
}

#[test]
fn a_ready_arm_moves() {
    let (mut app, t0) = console(ready());
    assert_eq!(app.motion_refusal(), None);
    assert_eq!(press(&mut app, "w", t0), [jog(1, 0, 0)]);
    let (mut app, t0) = console(ready());
    press(&mut app, "h", t0);
    assert_eq!(
        press(&mut app, "y", t0 + ms(200)),
        [Effect::Arm(ArmCommand::Home)]
    );
    // Controlled (by a sequence, manually) is the arm running a motion: not a refusal.
    for state in [
        RobotState::ControlledBySequence,
        RobotState::ControlledManually,
    ] {
        let mut t = ready();
        t.robot_state = Coded::Known(state);
        assert_eq!(console(t).0.motion_refusal(), None, "{state}");
    }
}

#[test]
fn an_emergency_stop_refuses_every_motion() {
    let mut t = ready();
    t.robot_state = Coded::Known(RobotState::InFault);
    t.faults = FlagSet::from_bits(Flag::EmergencyStop.bit());
    assert_everything_refused(t, "refused: the arm reports emergency_stop");
}

#[test]
fn every_fault_bit_is_named() {
    let mut t = ready();
    t.faults = FlagSet::from_bits(u32::MAX);
    let (app, _) = console(t);
    let why = app.motion_refusal().expect("refused");
    assert!(why.starts_with("refused: the arm reports firmware_update_failure, unknown_bit_1"));
    assert!(why.contains("emergency_stop"), "{why}");
}

#[test]
fn in_fault_without_a_fault_bit_refuses_every_motion() {
    let mut t = ready();
    t.robot_state = Coded::Known(RobotState::InFault);
    assert_everything_refused(t, "refused: the arm reports in_fault");
}

#[test]
fn a_state_other_than_ready_refuses_every_motion() {
    let mut t = ready();
    t.robot_state = Coded::Known(RobotState::InMaintenance);
    assert_everything_refused(
        t,
        "refused: the arm reports state in_maintenance (5), not ready",
    );
    let mut t = ready();
    t.robot_state = Coded::Unknown(65535);
    assert_everything_refused(
        t,
        "refused: the arm reports state unknown (65535), not ready",
    );
}

#[test]
fn nan_telemetry_refuses_every_motion() {
    let mut t = ready();
    t.tcp.twist.x = f32::NAN;
    assert_everything_refused(
        t,
        "refused: the arm reports nonsense: tool twist x NaN (input registers 116-117)",
    );
    let mut t = ready();
    t.joints[3].position = f32::NAN;
    assert_everything_refused(
        t,
        "refused: the arm reports nonsense: J4 position NaN (input registers 40-41)",
    );
}

#[test]
fn out_of_range_telemetry_refuses_every_motion() {
    let mut t = ready();
    t.joints[0].position = 1e9;
    assert_everything_refused(
        t,
        "refused: the arm reports nonsense: J1 position 1e9 (input registers 34-35)",
    );
    let mut t = ready();
    t.joints[1].velocity = 500.0;
    assert_everything_refused(
        t,
        "refused: the arm reports nonsense: J2 speed 500 (input registers 50-51)",
    );
}

#[test]
fn a_fault_during_a_jog_stops_it_and_latches_the_key() {
    let (mut app, t0) = console(ready());
    assert_eq!(press(&mut app, "w", t0), [jog(1, 0, 0)]);
    let mut faulted = ready();
    faulted.robot_state = Coded::Known(RobotState::InFault);
    faulted.faults = FlagSet::from_bits(Flag::EmergencyStop.bit());
    assert_eq!(feed(&mut app, faulted, t0 + ms(50)), [STOP]);
    assert!(!app.jog().is_jogging());
    assert_eq!(message(&app), "stopped: the arm reports emergency_stop");
    // The fault is reset and the key still held: nothing restarts, not at the refresh nor on
    // the key's repeat.
    feed(&mut app, ready(), t0 + ms(100));
    assert!(moves(&app.handle(Input::Tick, t0 + ms(200))).is_empty());
    assert!(moves(&app.handle(key("w", KeyKind::Repeat), t0 + ms(210))).is_empty());
    assert!(!app.jog().is_jogging());
    // Released and pressed anew, it moves.
    app.handle(key("w", KeyKind::Release), t0 + ms(220));
    assert_eq!(press(&mut app, "w", t0 + ms(230)), [jog(1, 0, 0)]);
}

#[test]
fn nonsense_telemetry_during_a_jog_stops_it() {
    let (mut app, t0) = console(ready());
    press(&mut app, "right", t0);
    let mut t = ready();
    t.joints[5].position = f32::NAN;
    assert_eq!(feed(&mut app, t, t0 + ms(50)), [STOP]);
    assert_eq!(
        message(&app),
        "stopped: the arm reports nonsense: J6 position NaN (input registers 44-45)"
    );
}

#[test]
fn the_stop_guard_not_ready_refuses_with_its_reason() {
    let (mut app, t0) = console(ready());
    app.handle(
        Input::Arm(ArmEvent::Guard(
            armjog::link::interface::GuardStatus::Starting,
        )),
        t0,
    );
    assert!(moves(&press(&mut app, "w", t0)).is_empty());
    assert_eq!(message(&app), "refused: the stop guard is not ready yet");
}

#[test]
fn the_refusal_is_said_while_the_arm_refuses_and_goes_once_it_is_ready() {
    let mut faulted = ready();
    faulted.robot_state = Coded::Known(RobotState::InFault);
    faulted.faults = FlagSet::from_bits(Flag::EmergencyStop.bit());
    let (mut app, t0) = console(faulted.clone());
    // The operator answers the read of "bench" the console asked for when the link came up.
    let bench = ArmCommand::GetPosition {
        name: "bench".into(),
    };
    app.handle(Input::Arm(ArmEvent::Done { command: bench }), t0);
    let mut effects = press(&mut app, "w", t0);
    effects.extend(app.handle(key("w", KeyKind::Release), t0 + ms(10)));
    assert!(moves(&effects).is_empty(), "{effects:?}");
    // The driver answers the STOPs the console sends on the way.
    for effect in effects {
        if let Effect::Arm(command @ ArmCommand::Stop) = effect {
            app.handle(Input::Arm(ArmEvent::Done { command }), t0 + ms(20));
            app.handle(Input::Arm(ArmEvent::StopConfirmed), t0 + ms(20));
        }
    }
    // Long after a notice would have gone, the arm still refuses: the reason stays.
    for n in 1..=200 {
        feed(&mut app, faulted.clone(), t0 + ms(100 * n));
    }
    assert_eq!(message(&app), "refused: the arm reports emergency_stop");
    // Reset: the arm reports ready, and the refusal is no longer true.
    feed(&mut app, ready(), t0 + ms(20_100));
    assert_eq!(message(&app), "");
    assert_eq!(press(&mut app, "w", t0 + ms(20_150)), [jog(1, 0, 0)]);
}
