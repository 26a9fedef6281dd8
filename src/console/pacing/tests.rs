use super::*;
use crate::console::app::{AppConfig, STALE_AFTER};
use crate::console::positions::PositionBook;
use crate::kortex::{Flag, FlagSet, Telemetry};
use crate::link::interface::{LinkStatus, LogEntry, TelemetrySource};

fn app() -> App {
    App::new(AppConfig::for_tests(), PositionBook::new())
}

/// A Modbus link up, which promises telemetry (so its silence makes it stale).
fn up(app: &mut App, now: Instant) {
    let source = ArmEvent::TelemetrySource(TelemetrySource::Modbus);
    app.handle(Input::Arm(source), now);
    let up = LinkStatus::Up {
        description: "modbus 127.0.0.1:502".into(),
    };
    app.handle(Input::Arm(ArmEvent::Status(up)), now);
}

/// The app takes `input` at `now` and the pacer hears of it, as the console's loop does.
fn take(app: &mut App, pacer: &mut FramePacer, input: Input, now: Instant) {
    let routine = is_routine_report(&input);
    app.handle(input, now);
    pacer.changed(routine, app, now);
}

fn report(telemetry: &Telemetry) -> Input {
    Input::Arm(ArmEvent::Telemetry(Box::new(telemetry.clone())))
}

fn poll_line(count: u32, latency_ms: u64) -> Input {
    Input::Arm(ArmEvent::Log(LogEntry {
        name: "modbus poll".into(),
        outcome: "OK".into(),
        ok: true,
        poll: true,
        count,
        latency: Some(Duration::from_millis(latency_ms)),
        ..Default::default()
    }))
}

#[test]
fn routine_reports_are_the_polls_snapshot_latency_and_successful_line() {
    let telemetry = Telemetry::decode(&Default::default());
    assert!(is_routine_report(&report(&telemetry)));
    let latency = Input::Arm(ArmEvent::Latency(Duration::from_millis(2)));
    assert!(is_routine_report(&latency));
    assert!(is_routine_report(&poll_line(3, 2)));

    let failed = LogEntry {
        name: "modbus poll".into(),
        outcome: "timed out".into(),
        poll: true,
        ..Default::default()
    };
    assert!(!is_routine_report(&Input::Arm(ArmEvent::Log(failed))));
    let reply = LogEntry {
        name: "Cartesian Move".into(),
        outcome: "OK".into(),
        ok: true,
        ..Default::default()
    };
    assert!(!is_routine_report(&Input::Arm(ArmEvent::Log(reply))));
    assert!(!is_routine_report(&Input::Arm(ArmEvent::Speed(40))));
    assert!(!is_routine_report(&Input::Tick));
    let resize = Input::Resize {
        width: 80,
        height: 24,
    };
    assert!(!is_routine_report(&resize));
}

#[test]
fn nothing_changed_wakes_nothing_and_a_change_is_drawn_once_its_command_is_out() {
    let start = Instant::now();
    let app = app();
    let mut pacer = FramePacer::default();
    assert_eq!(pacer.due_at(), None);
    pacer.changed(false, &app, start);
    assert_eq!(pacer.due_at(), Some(start + SETTLE));
    // Later changes before that frame do not put it off.
    pacer.changed(false, &app, start + Duration::from_millis(2));
    assert_eq!(pacer.due_at(), Some(start + SETTLE));
    assert!(pacer.frame(View::new(&app), start + SETTLE).is_some());
    // Long after the last frame, a key's frame comes SETTLE after it.
    let later = start + Duration::from_secs(1);
    pacer.changed(false, &app, later);
    assert_eq!(pacer.due_at(), Some(later + SETTLE));
}

#[test]
fn a_changed_view_is_drawn_at_its_rate_and_an_identical_one_is_not() {
    let start = Instant::now();
    let mut app = app();
    let mut pacer = FramePacer::default();
    pacer.changed(false, &app, start);
    assert!(pacer.frame(View::new(&app), start).is_some());
    assert_eq!(pacer.due_at(), None, "drawn: nothing due");

    // What the arm says besides its routine reports is drawn at the live rate.
    take(&mut app, &mut pacer, Input::Arm(ArmEvent::Speed(40)), start);
    assert_eq!(pacer.due_at(), Some(start + FRAME));
    let at = start + FRAME;
    let painted = pacer.frame(View::new(&app), at).expect("the speed changed");
    assert_eq!(painted.arm.speed, Some(40));

    // The same again (an identical report): woken, but nothing is handed to the painter.
    take(&mut app, &mut pacer, Input::Arm(ArmEvent::Speed(40)), at);
    assert_eq!(pacer.frame(View::new(&app), at + FRAME), None);
    assert_eq!(pacer.due_at(), None);
    // The skipped frame did not count as a drawn one: the next change is due as before.
    let next = at + FRAME;
    take(&mut app, &mut pacer, Input::Arm(ArmEvent::Speed(60)), next);
    assert_eq!(pacer.due_at(), Some(next + SETTLE));
}

#[test]
fn a_due_time_dependent_change_is_drawn_with_no_new_report_at_the_live_rate() {
    let start = Instant::now();
    let mut app = app();
    up(&mut app, start);
    let mut pacer = FramePacer::default();
    pacer.changed(false, &app, start);
    assert!(pacer.frame(View::new(&app), start).is_some());
    assert_eq!(View::new(&app).motion_status.link_stale, None);

    // A tick before anything is due shows the same: not drawn.
    let early = start + Duration::from_millis(50);
    take(&mut app, &mut pacer, Input::Tick, early);
    assert_eq!(pacer.frame(View::new(&app), early), None);

    // The silent link's deadline: the tick that wakes the app there makes it stale, and
    // that frame is drawn although no report came, SETTLE after the tick (the last frame is
    // long past).
    let deadline = app
        .next_deadline()
        .expect("the link's silence has a deadline");
    assert!(deadline >= start + STALE_AFTER);
    take(&mut app, &mut pacer, Input::Tick, deadline);
    let due = pacer.due_at().expect("due");
    assert_eq!(due, deadline + SETTLE);
    let painted = pacer
        .frame(View::new(&app), due)
        .expect("the stale link is drawn");
    assert!(painted.motion_status.link_stale.is_some());

    // And its age, as it grows, is drawn again.
    let later = deadline + Duration::from_secs(2);
    take(&mut app, &mut pacer, Input::Tick, later);
    assert!(pacer.frame(View::new(&app), later).is_some());

    // The report that ends the staleness changes the gate's answer: drawn at the live rate.
    let fresh = later + Duration::from_millis(10);
    let telemetry = Telemetry::decode(&Default::default());
    take(&mut app, &mut pacer, report(&telemetry), fresh);
    assert_eq!(pacer.due_at(), Some(later + FRAME));
    let painted = pacer.frame(View::new(&app), later + FRAME).expect("fresh");
    assert_eq!(painted.motion_status.link_stale, None);
}

#[test]
fn what_ticks_over_at_rest_is_drawn_every_two_seconds() {
    let start = Instant::now();
    // No link promising telemetry: nothing goes stale in this test.
    let mut app = app();
    let mut pacer = FramePacer::default();
    take(&mut app, &mut pacer, poll_line(1, 2), start);
    assert!(pacer.frame(View::new(&app), start).is_some());

    // Another poll and a new latency: held until REST_FRAME after the last frame.
    let t = start + FRAME;
    take(&mut app, &mut pacer, poll_line(1, 3), t);
    let latency = Input::Arm(ArmEvent::Latency(Duration::from_millis(3)));
    take(&mut app, &mut pacer, latency, t);
    assert_eq!(pacer.due_at(), Some(start + REST_FRAME));
    take(&mut app, &mut pacer, poll_line(1, 2), t + FRAME);
    assert_eq!(pacer.due_at(), Some(start + REST_FRAME));
    let painted = pacer
        .frame(View::new(&app), start + REST_FRAME)
        .expect("the counters are drawn");
    assert_eq!(painted.screen.log.back().map(|e| e.count), Some(3));
    assert_eq!(pacer.due_at(), None);

    // A key draws them at once.
    let k = start + REST_FRAME + FRAME;
    take(&mut app, &mut pacer, poll_line(1, 4), k);
    pacer.changed(false, &app, k);
    assert_eq!(pacer.due_at(), Some(k + SETTLE));
    assert!(pacer.frame(View::new(&app), k + SETTLE).is_some());

    // Anything else the arm says is drawn at the live rate, counters and all.
    let r = k + 2 * FRAME;
    take(&mut app, &mut pacer, poll_line(1, 5), r);
    take(
        &mut app,
        &mut pacer,
        Input::Arm(ArmEvent::Speed(40)),
        r + FRAME,
    );
    let at = pacer.due_at().expect("due");
    assert_eq!(at, r + SETTLE);
    let painted = pacer.frame(View::new(&app), at).expect("the speed changed");
    assert_eq!(painted.arm.speed, Some(40));
    assert_eq!(painted.screen.log.back().map(|e| e.count), Some(5));

    // A failed poll is a new line, not a counter: drawn at the live rate.
    let f = at + FRAME;
    let failed = LogEntry {
        name: "modbus poll".into(),
        outcome: "timed out".into(),
        poll: true,
        ..Default::default()
    };
    take(&mut app, &mut pacer, Input::Arm(ArmEvent::Log(failed)), f);
    assert_eq!(pacer.due_at(), Some(f + SETTLE));
    assert!(pacer.frame(View::new(&app), f + SETTLE).is_some());
}

#[test]
fn a_temperature_creeping_is_drawn_at_rest_and_a_joint_turning_is_not() {
    let start = Instant::now();
    let mut app = app();
    let mut telemetry = Telemetry::decode(&Default::default());
    let mut pacer = FramePacer::default();
    take(&mut app, &mut pacer, report(&telemetry), start);
    assert!(pacer.frame(View::new(&app), start).is_some());

    let t = start + FRAME;
    telemetry.joints[3].temperature += 0.001;
    telemetry.arm.cpu_temperature += 0.01;
    take(&mut app, &mut pacer, report(&telemetry), t);
    assert_eq!(pacer.due_at(), Some(start + REST_FRAME));

    telemetry.joints[3].position += 0.01;
    telemetry.joints[3].velocity = 3.0;
    let m = t + FRAME;
    take(&mut app, &mut pacer, report(&telemetry), m);
    assert_eq!(pacer.due_at(), Some(t + SETTLE));
    let painted = pacer.frame(View::new(&app), m).expect("a joint moved");
    let shown = painted.arm.telemetry.expect("telemetry");
    assert_eq!(shown.joints[3].position, telemetry.joints[3].position);
    assert_eq!(shown.joints[3].temperature, telemetry.joints[3].temperature);

    // The report that shows the joint stopped is drawn at the live rate too; the next one,
    // at rest again, at the rest rate.
    telemetry.joints[3].velocity = 0.0;
    let s = m + FRAME;
    take(&mut app, &mut pacer, report(&telemetry), s);
    assert_eq!(pacer.due_at(), Some(s + SETTLE));
    assert!(pacer.frame(View::new(&app), s).is_some());
    telemetry.arm.cpu_temperature += 0.01;
    take(&mut app, &mut pacer, report(&telemetry), s + FRAME);
    assert_eq!(pacer.due_at(), Some(s + REST_FRAME));
}

#[test]
fn a_fault_in_a_routine_report_is_drawn_at_the_live_rate() {
    let start = Instant::now();
    let mut app = app();
    up(&mut app, start);
    let mut telemetry = Telemetry::decode(&Default::default());
    let mut pacer = FramePacer::default();
    take(&mut app, &mut pacer, report(&telemetry), start);
    assert!(pacer.frame(View::new(&app), start).is_some());
    let t = start + FRAME;
    telemetry.arm.cpu_temperature += 0.01;
    take(&mut app, &mut pacer, report(&telemetry), t);
    assert_eq!(pacer.due_at(), Some(start + REST_FRAME), "at rest");

    telemetry.faults = FlagSet::from_bits(Flag::EmergencyStop.bit());
    let f = t + FRAME;
    take(&mut app, &mut pacer, report(&telemetry), f);
    assert_eq!(
        pacer.due_at(),
        Some(t + SETTLE),
        "kept its first change's time"
    );
    let painted = pacer.frame(View::new(&app), f).expect("the fault");
    let shown = painted.arm.telemetry.expect("telemetry");
    assert!(!shown.faults.is_empty());

    // Cleared: drawn at the live rate as well.
    telemetry.faults = FlagSet::from_bits(0);
    take(&mut app, &mut pacer, report(&telemetry), f + FRAME);
    assert_eq!(pacer.due_at(), Some(f + FRAME + SETTLE));
}

#[test]
fn a_turning_joint_or_a_motion_shown_draws_at_the_full_rate() {
    let start = Instant::now();
    let mut app = app();
    let mut telemetry = Telemetry::decode(&Default::default());
    app.handle(report(&telemetry), start);
    assert!(!app.arm_in_motion(), "at rest");
    // Noise below the threshold is rest.
    telemetry.joints[2].velocity = -0.2;
    app.handle(report(&telemetry), start);
    assert!(!app.arm_in_motion());
    // Another client moves the arm: J1 turns.
    telemetry.joints[0].velocity = 3.0;
    app.handle(report(&telemetry), start);
    assert!(app.arm_in_motion());
    let mut pacer = FramePacer::default();
    pacer.changed(true, &app, start);
    assert!(pacer.frame(View::new(&app), start).is_some());
    take(
        &mut app,
        &mut pacer,
        report(&telemetry),
        start + Duration::from_millis(1),
    );
    assert_eq!(pacer.due_at(), Some(start + FRAME));
}
