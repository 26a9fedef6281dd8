//! Another client's STOP or motion under a jog we hold, on the fake clock: a refresh never
//! follows telemetry that contradicts the jog (at rest, far slower than it ran, or moving the
//! tool elsewhere); three such samples, or one left standing for `CONTRADICTED_FOR`, stop and
//! latch. Start-up, acceleration, a speed change of ours and a 1 % jog are not taken for one.

use std::time::{Duration, Instant};

use armjog::console::app::{App, CONTRADICTED_FOR, Effect, Input, MotionShown, REFRESH_WAIT};
use armjog::console::jog::{JogMotion, KeyKind};
use armjog::console::positions::PositionBook;
use armjog::kortex::{ActionStatus, Coded, MoveType, RegisterImage, RobotState, Telemetry};
use armjog::link::interface::{ArmCommand, ArmEvent, LinkStatus, TelemetrySource};

use crate::app_support::{STOP, config, key, message, ms};

const PLUS_Y: JogMotion = JogMotion::Cartesian { x: 0, y: 1, z: 0 };

/// A ready arm, the tool moving at (vx, vy, vz) mm/s.
fn moving(vx: f32, vy: f32, vz: f32) -> Telemetry {
    let mut t = Telemetry::decode(&RegisterImage::default());
    t.robot_state = Coded::Known(RobotState::Ready);
    t.action.status = Coded::Known(ActionStatus::Started);
    t.action.move_type = Coded::Known(MoveType::Twist);
    t.joints[1].position = 15.0;
    t.tcp.twist.x = vx / 1000.0;
    t.tcp.twist.y = vy / 1000.0;
    t.tcp.twist.z = vz / 1000.0;
    t
}

fn at_rest() -> Telemetry {
    moving(0.0, 0.0, 0.0)
}

/// A console on the default link shape (Talos jogs, Modbus telemetry) at 50 %, holding `a`
/// (+Y) since `t0`.
fn jogging() -> (App, Instant) {
    let config = config();
    let mut app = App::new(config, PositionBook::new());
    let t0 = Instant::now();
    for event in [
        ArmEvent::TelemetrySource(TelemetrySource::Modbus),
        ArmEvent::Status(LinkStatus::Up {
            description: "test".into(),
        }),
        ArmEvent::Speed(50),
    ] {
        app.handle(Input::Arm(event), t0);
    }
    feed(&mut app, at_rest(), t0);
    let effects = app.handle(key("a", KeyKind::Press), t0);
    assert!(effects.contains(&jog_effect()), "{effects:?}");
    (app, t0)
}

fn jog_effect() -> Effect {
    Effect::Arm(ArmCommand::Jog(PLUS_Y))
}

fn feed(app: &mut App, t: Telemetry, now: Instant) -> Vec<Effect> {
    app.handle(Input::Arm(ArmEvent::Telemetry(Box::new(t))), now)
}

/// Telemetry from `sample(elapsed since from)` every 33 ms over `from..to`, the held key's
/// repeats and the ticks due meanwhile; the arm answers every command. Every effect.
fn run(
    app: &mut App,
    from: Instant,
    to: Instant,
    sample: impl Fn(Duration) -> Telemetry,
) -> Vec<Effect> {
    let mut effects = Vec::new();
    let mut now = from;
    while now < to {
        let mut step = feed(app, sample(now - from), now);
        step.extend(app.handle(key("a", KeyKind::Repeat), now + ms(1)));
        // Every deadline the app asks for until the next sample, as the runtime wakes.
        while let Some(at) = app.next_deadline().filter(|at| *at < now + ms(33)) {
            step.extend(app.handle(Input::Tick, at.max(now + ms(2))));
            if at <= now + ms(2) {
                break;
            }
        }
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

fn count(effects: &[Effect], wanted: &Effect) -> usize {
    effects.iter().filter(|e| *e == wanted).count()
}

/// A held +Y jog that ran 125 mm/s for a second.
fn steady() -> (App, Instant) {
    let (mut app, t0) = jogging();
    let effects = run(&mut app, t0, t0 + ms(1000), |_| moving(0.0, 125.0, 0.0));
    assert!(!effects.contains(&STOP), "{effects:?}");
    assert!(
        count(&effects, &jog_effect()) >= 8,
        "refreshed: {effects:?}"
    );
    (app, t0 + ms(1000))
}

#[test]
fn start_up_acceleration_and_a_steady_jog_are_never_taken_for_another_client() {
    let (mut app, t0) = jogging();
    // At rest for the grace, then a ramp to 125 mm/s over 400 ms, then steady for 2 s.
    let effects = run(&mut app, t0, t0 + ms(3000), |e| {
        let ramp = (e.as_secs_f32() - 0.4).clamp(0.0, 0.4) / 0.4;
        moving(0.0, 125.0 * ramp, 0.0)
    });
    assert!(!effects.contains(&STOP), "{effects:?}");
    // About 10 Hz of refreshes whatever the telemetry's phase: never starved.
    let refreshes = count(&effects, &jog_effect());
    assert!((25..=31).contains(&refreshes), "{refreshes} refreshes");
    assert_eq!(app.motion_shown(), MotionShown::Jog(PLUS_Y));
    assert_eq!(app.other_clients().withheld(), 0);
}

#[test]
fn a_refresh_goes_out_only_on_telemetry_not_on_a_tick_alone() {
    let (mut app, now) = steady();
    // The refresh falls due; no sample yet: nothing goes out.
    let due = app.next_deadline().expect("a refresh is due");
    assert!(!app.handle(Input::Tick, due).contains(&jog_effect()));
    // Two samples that show the jog running: it goes out on the second.
    assert!(!feed(&mut app, moving(0.0, 125.0, 0.0), due + ms(10)).contains(&jog_effect()));
    assert_eq!(
        feed(&mut app, moving(0.0, 125.0, 0.0), due + ms(43)),
        [jog_effect()]
    );
    // With no telemetry at all it still goes out after REFRESH_WAIT (staleness watches that).
    let due = app.next_deadline().expect("next refresh");
    assert!(due > now);
    assert!(!app.handle(Input::Tick, due).contains(&jog_effect()));
    assert_eq!(app.handle(Input::Tick, due + REFRESH_WAIT), [jog_effect()]);
}

#[test]
fn at_rest_after_a_due_refresh_withholds_it_and_the_third_sample_stops_and_latches() {
    let (mut app, now) = steady();
    let due = app.next_deadline().expect("a refresh is due");
    app.handle(Input::Tick, due);
    // Another client's STOP: at rest. The waiting refresh never goes out.
    let effects = run(&mut app, due + ms(5), due + ms(400), |_| at_rest());
    assert_eq!(count(&effects, &jog_effect()), 0, "{effects:?}");
    assert_eq!(count(&effects, &STOP), 1, "{effects:?}");
    assert_eq!(
        message(&app),
        "stopped by another client: the arm is at rest while we jog +Y"
    );
    assert!(
        !app.jog().is_jogging()
            && app
                .jog()
                .is_latched(armjog::console::action::Action::JogYPlus)
    );
    assert!(now < due);
}

#[test]
fn far_slower_than_the_jog_ran_is_another_client_s_stop() {
    let (mut app, now) = steady();
    // A Gen3 decelerating under someone else's STOP: 40 mm/s, then less (the third sample,
    // 66 ms on, reads 33).
    let effects = run(&mut app, now, now + ms(300), |e| {
        moving(0.0, 40.0 - 100.0 * e.as_secs_f32().min(0.3), 0.0)
    });
    assert_eq!(count(&effects, &jog_effect()), 0, "withheld: {effects:?}");
    assert!(effects.contains(&STOP), "{effects:?}");
    assert_eq!(
        message(&app),
        "stopped by another client: the arm runs at 33 mm/s, not the 125 mm/s of our +Y jog"
    );
    assert_eq!(app.other_clients().stops(), 1);
}

#[test]
fn a_speed_change_of_ours_is_learnt_anew_not_taken_for_a_stop() {
    let (mut app, now) = steady();
    // The technician goes from 50 % to 10 %: the operator says so and the arm slows to 25.
    app.handle(Input::Arm(ArmEvent::Speed(10)), now);
    let effects = run(&mut app, now, now + ms(2000), |_| moving(0.0, 25.0, 0.0));
    assert!(!effects.contains(&STOP), "{effects:?}");
    assert!(count(&effects, &jog_effect()) >= 15);
    assert!(app.jog().is_jogging());
    // And the new steady speed is the one compared with: 10 mm/s is far under 25.
    let effects = run(&mut app, now + ms(2000), now + ms(2200), |_| {
        moving(0.0, 10.0, 0.0)
    });
    assert!(effects.contains(&STOP), "{effects:?}");
}

#[test]
fn a_one_percent_jog_creeping_is_not_taken_for_rest_or_slowness() {
    let (mut app, t0) = jogging();
    app.handle(Input::Arm(ArmEvent::Speed(1)), t0);
    // 2.5 mm/s expected; readings wander between 0.5 and 3 mm/s.
    let effects = run(&mut app, t0, t0 + ms(3000), |e| {
        let wobble = (e.as_millis() / 33 % 5) as f32 * 0.6;
        moving(0.0, 0.5 + wobble, 0.0)
    });
    assert!(!effects.contains(&STOP), "{effects:?}");
    assert!(app.jog().is_jogging());
}

#[test]
fn the_arm_moving_plus_z_under_our_plus_y_is_another_client_s_motion() {
    let (mut app, now) = steady();
    // B's +Z jog replaced ours: the tool goes +Z at 125 mm/s, a little Y left.
    let effects = run(&mut app, now, now + ms(200), |_| moving(0.0, 10.0, 125.0));
    assert_eq!(count(&effects, &jog_effect()), 0, "withheld: {effects:?}");
    assert!(effects.contains(&STOP), "{effects:?}");
    assert_eq!(
        message(&app),
        "stopped by another client: the arm moves +Z, not our +Y"
    );
    // A shows what it sees, not `JOG +Y`.
    assert_ne!(app.motion_shown(), MotionShown::Jog(PLUS_Y));
    // A diagonal of ours is not "elsewhere" for its own components.
    let (mut app, t0) = jogging();
    app.handle(key("r", KeyKind::Press), t0 + ms(1));
    let effects = run(&mut app, t0, t0 + ms(1500), |_| moving(0.0, 88.0, 88.0));
    assert!(!effects.contains(&STOP), "{effects:?}");
}

#[test]
fn one_contradicting_sample_then_silence_stops_after_contradicted_for() {
    let (mut app, now) = steady();
    assert!(!feed(&mut app, at_rest(), now).contains(&STOP));
    // No more telemetry: ambiguous, and the safe side wins.
    let mut effects = Vec::new();
    let mut at = now;
    while !effects.contains(&STOP) {
        at = app.next_deadline().expect("deadline").max(at + ms(1));
        assert!(at <= now + CONTRADICTED_FOR, "stopped by {:?}", at - now);
        effects.extend(app.handle(Input::Tick, at));
    }
    assert_eq!(at, now + CONTRADICTED_FOR);
    assert_eq!(count(&effects, &jog_effect()), 0, "{effects:?}");
    assert!(message(&app).starts_with("stopped by another client"));
}

#[test]
fn a_glitch_then_the_jog_running_again_resumes_the_refreshes() {
    let (mut app, now) = steady();
    let effects = run(&mut app, now, now + ms(1000), |e| {
        // One sample in ten reads at rest.
        if e.as_millis() / 33 % 10 == 3 {
            at_rest()
        } else {
            moving(0.0, 125.0, 0.0)
        }
    });
    assert!(!effects.contains(&STOP), "{effects:?}");
    assert!(count(&effects, &jog_effect()) >= 8, "{effects:?}");
}

#[test]
fn b_gone_its_stop_seen_a_stays_stopped_for_the_rest_of_the_hold() {
    // B quits, is killed or freezes: its STOP (or its guard's) leaves the arm at rest.
    let (mut app, now) = steady();
    let effects = run(&mut app, now, now + ms(3000), |_| at_rest());
    assert_eq!(count(&effects, &STOP), 1, "{effects:?}");
    assert_eq!(count(&effects, &jog_effect()), 0, "{effects:?}");
    assert!(!app.jog().is_jogging());
    assert_ne!(app.motion_shown(), MotionShown::Jog(PLUS_Y));
}
