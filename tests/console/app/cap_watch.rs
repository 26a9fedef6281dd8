//! The speed cap watched from telemetry (fake clock): a motion the console started that runs
//! more than 10 % over the cap for three samples in a row is stopped, with the reason on the
//! message line, and the held key stays latched; within 10 %, or a run broken by one sample
//! under, nothing happens; without telemetry the status bar says the cap is not watched.

use std::time::Instant;

use armjog::console::app::{App, AppConfig, Effect, Input};
use armjog::console::jog::{JogMotion, KeyKind};
use armjog::console::positions::PositionBook;
use armjog::console::ui::status::speed_text;
use armjog::console::view::View;
use armjog::kortex::{Coded, MoveType, RegisterImage, RobotState, Telemetry};
use armjog::link::driver::JOINT_JOG_SPEED;
use armjog::link::interface::{ArmCommand, ArmEvent, LinkStatus, TelemetrySource};

use crate::app_support::{STOP, config, jog, key, message, ms, press, release};

/// The cap of these tests: 50 mm/s.
const CAP: f64 = 0.05;

fn console(source: TelemetrySource) -> (App, Instant) {
    let config = AppConfig {
        positions_on_operator: source != TelemetrySource::Modbus,
        max_jog_speed: CAP,
        ..config()
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
    app.handle(Input::Arm(ArmEvent::Speed(100)), t0);
    if source != TelemetrySource::None {
        feed(&mut app, moving_at(0.0), t0);
    }
    (app, t0)
}

/// The tool moving along X at `mm_s`.
fn moving_at(mm_s: f32) -> Telemetry {
    let mut t = Telemetry::decode(&RegisterImage::default());
    // Ready, running a twist: the arm's state lets motion start.
    t.robot_state = Coded::Known(RobotState::Ready);
    t.action.move_type = Coded::Known(MoveType::Twist);
    t.tcp.twist.x = mm_s / 1000.0;
    t
}

/// Joint 2 turning at `deg_s`, the tool at rest.
fn joint_at(deg_s: f32) -> Telemetry {
    let mut t = moving_at(0.0);
    t.joints[1].velocity = deg_s;
    t
}

fn feed(app: &mut App, t: Telemetry, now: Instant) -> Vec<Effect> {
    app.handle(Input::Arm(ArmEvent::Telemetry(Box::new(t))), now)
}

/// Feeds `samples` 33 ms apart from `from`; returns every effect and when the last came.
fn feed_all(app: &mut App, samples: &[Telemetry], from: Instant) -> (Vec<Effect>, Instant) {
    let mut effects = Vec::new();
    let mut now = from;
    for t in samples {
        now += ms(33);
        effects.extend(feed(app, t.clone(), now));
    }
    (effects, now)
}

#[test]
fn the_third_sample_in_a_row_over_the_cap_stops_the_jog_and_says_why() {
    let (mut app, t0) = console(TelemetrySource::Modbus);
    assert_eq!(press(&mut app, "w", t0), [jog(1, 0, 0)]);
    let over = moving_at(239.0);
    let (effects, _) = feed_all(&mut app, &[over.clone(), over.clone()], t0);
    assert!(
        effects.is_empty(),
        "two samples may be a spike: {effects:?}"
    );
    assert!(app.jog().is_jogging());
    let effects = feed(&mut app, over, t0 + ms(100));
    assert_eq!(effects, [STOP]);
    assert!(!app.jog().is_jogging());
    assert_eq!(
        message(&app),
        "stopped: tool at 239 mm/s, over the 50 mm/s cap; is --operator-full-speed right?"
    );
    let (stops, reason) = app.cap_watch().stops();
    assert_eq!(stops, 1);
    assert_eq!(reason, Some(message(&app).as_str()));
}

#[test]
fn at_the_cap_and_up_to_10_percent_over_nothing_stops() {
    let (mut app, t0) = console(TelemetrySource::Modbus);
    press(&mut app, "right", t0);
    let samples: Vec<Telemetry> = [50.0, 54.9, 54.9, 54.9, 52.0, 54.9, 54.9, 54.9]
        .map(moving_at)
        .to_vec();
    let (effects, _) = feed_all(&mut app, &samples, t0);
    assert!(effects.is_empty(), "{effects:?}");
    assert!(app.jog().is_jogging());
    assert_eq!(app.cap_watch().stops().0, 0);
}

#[test]
fn two_over_then_one_under_starts_the_count_again() {
    let (mut app, t0) = console(TelemetrySource::Modbus);
    press(&mut app, "w", t0);
    let samples: Vec<Telemetry> = [80.0, 80.0, 40.0, 80.0, 80.0, 50.0, 80.0, 80.0]
        .map(moving_at)
        .to_vec();
    let (effects, now) = feed_all(&mut app, &samples, t0);
    assert!(effects.is_empty(), "{effects:?}");
    assert!(app.jog().is_jogging());
    // The third in a row, now, does.
    assert_eq!(feed(&mut app, moving_at(80.0), now + ms(33)), [STOP]);
}

#[test]
fn a_cap_stop_latches_the_held_key_until_it_is_released_and_pressed_again() {
    let (mut app, t0) = console(TelemetrySource::Modbus);
    press(&mut app, "w", t0);
    let over = moving_at(100.0);
    let (effects, now) = feed_all(&mut app, &[over.clone(), over.clone(), over], t0);
    assert_eq!(effects, [STOP]);
    // The refresh time passes and the key repeats: nothing restarts.
    assert!(app.handle(Input::Tick, now + ms(150)).is_empty());
    assert!(
        app.handle(key("w", KeyKind::Repeat), now + ms(160))
            .is_empty()
    );
    assert!(!app.jog().is_jogging());
    // Motion at rest is not watched.
    let (effects, now) = feed_all(&mut app, &[moving_at(0.0)], now + ms(200));
    assert!(effects.is_empty());
    release(&mut app, "w", now + ms(10));
    assert_eq!(press(&mut app, "w", now + ms(20)), [jog(1, 0, 0)]);
}

#[test]
fn over_the_cap_with_nothing_started_is_not_the_watchs_to_stop() {
    // Someone else moves the arm (the status bar says MAY BE MOVING): the watch guards the
    // console's own motions only.
    let (mut app, t0) = console(TelemetrySource::Modbus);
    let over = moving_at(300.0);
    let (effects, _) = feed_all(
        &mut app,
        &[over.clone(), over.clone(), over.clone(), over],
        t0,
    );
    assert!(effects.is_empty(), "{effects:?}");
    assert_eq!(app.cap_watch().stops().0, 0);
}

#[test]
fn home_go_to_and_steps_are_watched_too() {
    let over = moving_at(120.0);
    let three = [over.clone(), over.clone(), over];

    // Home, over Talos hardware telemetry.
    let (mut app, t0) = console(TelemetrySource::TalosHardware);
    press(&mut app, "h", t0);
    // Answered as a person answers: after the question's first 150 ms.
    let answered = t0 + ms(200);
    assert_eq!(
        press(&mut app, "y", answered),
        [Effect::Arm(ArmCommand::Home)]
    );
    let (effects, _) = feed_all(&mut app, &three, answered);
    assert_eq!(effects, [STOP], "home");
    assert!(app.motion_truth().action().is_none());
    assert!(
        message(&app).contains("over the 50 mm/s cap"),
        "{}",
        message(&app)
    );

    // Go to a named position on the operator.
    let (mut app, t0) = console(TelemetrySource::TalosHardware);
    let mut book = PositionBook::new();
    book.get_or_insert("bench").cartesian = Some([4000, 1000, 3000]);
    app.handle(Input::PositionsLoaded(Ok(book)), t0);
    press(&mut app, "o", t0);
    let answered = t0 + ms(200);
    let effects = press(&mut app, "y", answered);
    assert!(
        matches!(
            effects.as_slice(),
            [Effect::Arm(ArmCommand::GoToPosition { .. })]
        ),
        "{effects:?}"
    );
    let (effects, _) = feed_all(&mut app, &three, answered);
    assert_eq!(effects, [STOP], "go to");

    // A step.
    let (mut app, t0) = console(TelemetrySource::Modbus);
    press(&mut app, "t", t0);
    let effects = press(&mut app, "w", t0);
    assert!(
        matches!(effects.as_slice(), [Effect::Arm(ArmCommand::Step(_))]),
        "{effects:?}"
    );
    let (effects, _) = feed_all(&mut app, &three, t0);
    assert_eq!(effects, [STOP], "step");
}

#[test]
fn a_joint_jog_is_watched_against_the_joint_jog_speed() {
    let (mut app, t0) = console(TelemetrySource::TalosHardware);
    let effects = press(&mut app, "k", t0);
    assert!(
        matches!(
            effects.as_slice(),
            [Effect::Arm(ArmCommand::Jog(JogMotion::Joint { .. }))]
        ),
        "{effects:?}"
    );
    let within = JOINT_JOG_SPEED * 1.09;
    let (effects, now) = feed_all(
        &mut app,
        &[joint_at(within), joint_at(within), joint_at(within)],
        t0,
    );
    assert!(effects.is_empty(), "{effects:?}");
    let over = joint_at(JOINT_JOG_SPEED * 2.0);
    let (effects, _) = feed_all(&mut app, &[over.clone(), over.clone(), over], now);
    assert_eq!(effects, [STOP]);
    assert_eq!(
        message(&app),
        "stopped: J2 at 40 deg/s, over the 20 deg/s joint jog speed"
    );
}

#[test]
fn without_telemetry_the_status_bar_says_the_cap_is_not_watched() {
    let (app_none, _) = console(TelemetrySource::None);
    assert_eq!(app_none.cap_watched(), Some(false));
    assert_eq!(
        speed_text(&View::new(&app_none)),
        "100% (≤50 mm/s, cap not watched)"
    );
    for source in [TelemetrySource::Modbus, TelemetrySource::TalosHardware] {
        let (watched, _) = console(source);
        assert_eq!(watched.cap_watched(), Some(true));
        assert_eq!(speed_text(&View::new(&watched)), "100% (≤50 mm/s)");
    }
}
