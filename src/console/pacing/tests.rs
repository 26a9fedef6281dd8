use super::*;
use crate::console::app::{App, AppConfig, Input, STALE_AFTER};
use crate::console::positions::PositionBook;
use crate::link::interface::{ArmEvent, LinkStatus, TelemetrySource};

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

#[test]
fn nothing_changed_wakes_nothing_and_a_change_is_drawn_once_its_command_is_out() {
    let start = Instant::now();
    let mut pacer = FramePacer::default();
    assert_eq!(pacer.due_at(false), None);
    pacer.changed(true, start);
    assert_eq!(pacer.due_at(false), Some(start + SETTLE));
    // Later changes before that frame do not put it off.
    pacer.changed(true, start + Duration::from_millis(2));
    assert_eq!(pacer.due_at(false), Some(start + SETTLE));
    assert!(pacer.frame(View::new(&app()), start + SETTLE).is_some());
    // Long after the last frame, a key's frame comes SETTLE after it.
    let later = start + Duration::from_secs(1);
    pacer.changed(true, later);
    assert_eq!(pacer.due_at(false), Some(later + SETTLE));
}

#[test]
fn a_changed_view_is_drawn_at_its_rate_and_an_identical_one_is_not() {
    let start = Instant::now();
    let mut app = app();
    let mut pacer = FramePacer::default();
    pacer.changed(true, start);
    assert!(pacer.frame(View::new(&app), start).is_some());
    assert_eq!(pacer.due_at(false), None, "drawn: nothing due");

    // The arm's report changes what is shown: due IDLE_FRAME after the last frame.
    app.handle(Input::Arm(ArmEvent::Speed(40)), start);
    pacer.changed(false, start);
    assert_eq!(pacer.due_at(false), Some(start + IDLE_FRAME));
    // A key (or a jog) brings it forward to the 30 fps rate.
    assert_eq!(pacer.due_at(true), Some(start + FRAME));
    pacer.changed(true, start);
    assert_eq!(pacer.due_at(false), Some(start + FRAME));
    let at = start + FRAME;
    let painted = pacer.frame(View::new(&app), at).expect("the speed changed");
    assert_eq!(painted.arm.speed, Some(40));

    // The same again (an identical report): woken, but nothing is handed to the painter.
    app.handle(Input::Arm(ArmEvent::Speed(40)), at);
    pacer.changed(false, at);
    assert_eq!(pacer.frame(View::new(&app), at + IDLE_FRAME), None);
    assert_eq!(pacer.due_at(false), None);
    // The skipped frame did not count as a drawn one: the next change is due as before.
    let next = at + IDLE_FRAME;
    app.handle(Input::Arm(ArmEvent::Speed(60)), next);
    pacer.changed(false, next);
    assert_eq!(pacer.due_at(false), Some(next + SETTLE));
}

#[test]
fn a_due_time_dependent_change_is_drawn_with_no_new_report() {
    let start = Instant::now();
    let mut app = app();
    up(&mut app, start);
    let mut pacer = FramePacer::default();
    pacer.changed(false, start);
    assert!(pacer.frame(View::new(&app), start).is_some());
    assert_eq!(View::new(&app).truth.link_stale, None);

    // A tick before anything is due shows the same: not drawn.
    let early = start + Duration::from_millis(50);
    app.handle(Input::Tick, early);
    pacer.changed(false, early);
    assert_eq!(pacer.frame(View::new(&app), early), None);

    // The silent link's deadline: the tick that wakes the app there makes it stale, and
    // that frame is drawn although no report came.
    let deadline = app
        .next_deadline()
        .expect("the link's silence has a deadline");
    assert!(deadline >= start + STALE_AFTER);
    app.handle(Input::Tick, deadline);
    pacer.changed(false, deadline);
    let due = pacer.due_at(false).expect("due");
    let painted = pacer
        .frame(View::new(&app), due.max(deadline))
        .expect("the stale link is drawn");
    assert!(painted.truth.link_stale.is_some());

    // And its age, as it grows, is drawn again.
    let later = deadline + Duration::from_secs(2);
    app.handle(Input::Tick, later);
    pacer.changed(false, later);
    assert!(pacer.frame(View::new(&app), later).is_some());
}

fn report(telemetry: &crate::kortex::Telemetry) -> Input {
    Input::Arm(ArmEvent::Telemetry(Box::new(telemetry.clone())))
}

fn poll_line(count: u32, latency_ms: u64) -> ArmEvent {
    ArmEvent::Log(crate::link::interface::LogEntry {
        name: "modbus poll".into(),
        outcome: "OK".into(),
        ok: true,
        poll: true,
        count,
        latency: Some(Duration::from_millis(latency_ms)),
        ..Default::default()
    })
}

#[test]
fn what_ticks_over_at_rest_is_drawn_every_two_seconds() {
    let start = Instant::now();
    // No link promising telemetry: nothing goes stale in this test.
    let mut app = app();
    app.handle(Input::Arm(poll_line(1, 2)), start);
    let mut pacer = FramePacer::default();
    pacer.changed(false, start);
    assert!(pacer.frame(View::new(&app), start).is_some());

    // Another poll and a new latency: held back until a second after the last frame.
    let t = start + IDLE_FRAME;
    app.handle(Input::Arm(poll_line(1, 3)), t);
    app.handle(Input::Arm(ArmEvent::Latency(Duration::from_millis(3))), t);
    pacer.changed(false, t);
    let mut view = View::new(&app);
    let as_built = view.clone();
    assert!(view.differs_only_in_background(&pacer.shown.clone().expect("drawn")));
    // Compared in place: the view keeps its own count and latency.
    assert_eq!(view, as_built);
    assert_eq!(view.arm.latency, Some(Duration::from_millis(3)));
    assert_eq!(pacer.frame(View::new(&app), t), None);
    assert_eq!(pacer.due_at(false), Some(start + BACKGROUND_FRAME));
    // The next poll is looked at a frame's period after the held one, not at once.
    app.handle(Input::Arm(poll_line(1, 2)), t + FRAME);
    pacer.changed(false, t + FRAME);
    assert_eq!(pacer.due_at(false), Some(t + IDLE_FRAME));
    assert_eq!(pacer.frame(View::new(&app), t + IDLE_FRAME), None);
    let painted = pacer
        .frame(View::new(&app), start + BACKGROUND_FRAME)
        .expect("the counters are drawn a second on");
    assert_eq!(painted.screen.log.back().map(|e| e.count), Some(3));
    assert_eq!(pacer.due_at(false), None);

    // A key draws them at once.
    let k = start + BACKGROUND_FRAME + IDLE_FRAME;
    app.handle(Input::Arm(poll_line(1, 4)), k);
    pacer.changed(true, k);
    assert!(pacer.frame(View::new(&app), k + FRAME).is_some());

    // Anything else the arm reports is drawn at its own rate, counters and all.
    let r = k + 2 * FRAME;
    app.handle(Input::Arm(poll_line(1, 5)), r);
    pacer.changed(false, r);
    assert_eq!(pacer.frame(View::new(&app), r + IDLE_FRAME), None);
    app.handle(Input::Arm(ArmEvent::Speed(40)), r + IDLE_FRAME);
    pacer.changed(false, r + IDLE_FRAME);
    let at = pacer.due_at(false).expect("due");
    assert!(at < k + FRAME + BACKGROUND_FRAME);
    let painted = pacer.frame(View::new(&app), at).expect("the speed changed");
    assert_eq!(painted.arm.speed, Some(40));
    assert_eq!(painted.screen.log.back().map(|e| e.count), Some(5));

    // A failed poll is a new line, not a counter: drawn at once.
    let f = at + IDLE_FRAME;
    app.handle(
        Input::Arm(ArmEvent::Log(crate::link::interface::LogEntry {
            name: "modbus poll".into(),
            outcome: "timed out".into(),
            poll: true,
            ..Default::default()
        })),
        f,
    );
    pacer.changed(false, f);
    assert!(pacer.frame(View::new(&app), f).is_some());
}

#[test]
fn a_temperature_creeping_is_background_and_a_joint_moving_is_not() {
    let start = Instant::now();
    let mut app = app();
    let mut telemetry = crate::kortex::Telemetry::decode(&Default::default());
    app.handle(report(&telemetry), start);
    let mut pacer = FramePacer::default();
    pacer.changed(false, start);
    assert!(pacer.frame(View::new(&app), start).is_some());

    let t = start + IDLE_FRAME;
    telemetry.joints[3].temperature += 0.001;
    telemetry.arm.cpu_temperature += 0.01;
    app.handle(report(&telemetry), t);
    pacer.changed(false, t);
    assert_eq!(pacer.frame(View::new(&app), t), None);
    assert_eq!(pacer.due_at(false), Some(start + BACKGROUND_FRAME));

    telemetry.joints[3].position += 0.01;
    let m = t + IDLE_FRAME;
    app.handle(report(&telemetry), m);
    pacer.changed(false, m);
    let painted = pacer.frame(View::new(&app), m).expect("a joint moved");
    let shown = painted.arm.telemetry.expect("telemetry");
    assert_eq!(shown.joints[3].position, telemetry.joints[3].position);
    assert_eq!(shown.joints[3].temperature, telemetry.joints[3].temperature);
}

#[test]
fn a_turning_joint_or_a_motion_shown_draws_at_the_full_rate() {
    let start = Instant::now();
    let mut app = app();
    let mut telemetry = crate::kortex::Telemetry::decode(&Default::default());
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
    pacer.changed(false, start);
    assert!(pacer.frame(View::new(&app), start).is_some());
    pacer.changed(false, start + Duration::from_millis(1));
    assert_eq!(pacer.due_at(app.arm_in_motion()), Some(start + FRAME));
}

#[test]
fn a_frame_only_reports_changed_may_wait_for_a_later_reports_turn() {
    let start = Instant::now();
    let mut app = app();
    let mut pacer = FramePacer::default();
    assert_eq!(pacer.wake_at(false), None, "nothing changed: no wake-up");

    // A report: due as any change the arm reported, but the runtime need not wake for it
    // before REPORT_SLACK has passed (a later report's turn draws it).
    pacer.reported(start);
    let due = pacer.due_at(false).expect("due");
    assert_eq!(due, start + SETTLE);
    assert_eq!(pacer.wake_at(false), Some(due + REPORT_SLACK));
    // While anything moves, the frame keeps its time.
    assert_eq!(pacer.wake_at(true), pacer.due_at(true));

    // Anything else the arm says (a status, a failure) is drawn on time, reports or not.
    pacer.changed(false, start);
    assert_eq!(pacer.wake_at(false), Some(due));
    assert!(pacer.frame(View::new(&app), due).is_some());

    // A key after reports: on time, at the key's rate.
    let k = start + Duration::from_secs(1);
    app.handle(Input::Arm(ArmEvent::Speed(40)), k);
    pacer.reported(k);
    pacer.changed(true, k);
    assert_eq!(pacer.wake_at(false), Some(k + SETTLE));
    assert_eq!(pacer.wake_at(false), pacer.due_at(false));
    assert!(pacer.frame(View::new(&app), k + SETTLE).is_some());

    // Once a frame was considered, reports alone may wait again.
    let r = k + Duration::from_secs(1);
    pacer.reported(r);
    pacer.reported(r + FRAME);
    assert_eq!(pacer.wake_at(false), Some(r + SETTLE + REPORT_SLACK));
}

#[test]
fn a_frame_held_for_the_background_may_wait_for_a_reports_turn_too() {
    let start = Instant::now();
    let mut app = app();
    app.handle(Input::Arm(poll_line(1, 2)), start);
    let mut pacer = FramePacer::default();
    pacer.reported(start);
    assert!(pacer.frame(View::new(&app), start).is_some());
    // Only the poll count and the latency changed: held for BACKGROUND_FRAME.
    let t = start + IDLE_FRAME;
    app.handle(Input::Arm(poll_line(1, 3)), t);
    pacer.reported(t);
    assert_eq!(pacer.frame(View::new(&app), t), None);
    assert_eq!(pacer.due_at(false), Some(start + BACKGROUND_FRAME));
    assert_eq!(
        pacer.wake_at(false),
        Some(start + BACKGROUND_FRAME + REPORT_SLACK)
    );
}

#[test]
fn a_poll_line_is_background_only_in_its_count_and_latency() {
    let start = Instant::now();
    let mut app = app();
    app.handle(Input::Arm(poll_line(1, 2)), start);
    let shown = View::new(&app);
    let line = |view: &mut View| {
        std::sync::Arc::make_mut(view.screen.log.back_mut().expect("the poll's line")).clone()
    };

    let mut counted = View::new(&app);
    let mut changed = line(&mut counted);
    changed.count += 4;
    changed.latency = Some(Duration::from_millis(9));
    *counted.screen.log.back_mut().expect("line") = changed.into();
    assert!(counted.differs_only_in_background(&shown));
    // Compared, not changed: the view keeps its own count.
    assert_eq!(counted.screen.log.back().map(|l| l.count), Some(5));

    let mut other = View::new(&app);
    let mut changed = line(&mut other);
    changed.id = Some(7);
    *other.screen.log.back_mut().expect("line") = changed.into();
    assert!(!other.differs_only_in_background(&shown));

    let mut failed = View::new(&app);
    let mut changed = line(&mut failed);
    changed.ok = false;
    *failed.screen.log.back_mut().expect("line") = changed.into();
    assert!(!failed.differs_only_in_background(&shown));
}
