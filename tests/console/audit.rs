//! The audit records of technician actions, from the state machine's real effects through the
//! audit deriver (the runtime's edge), with fake clocks.

use std::time::{Duration, SystemTime, UNIX_EPOCH};

use crate::app_support::{app, press, release};

use armjog::console::app::{App, Effect};
use armjog::console::audit::{AuditDeriver, AuditEvent, AuditRecord};
use armjog::console::jog::ReleaseMode;
use armjog::link::interface::ArmCommand;

/// What the runtime records of `effects`.
fn records(d: &mut AuditDeriver, app: &App, effects: &[Effect], at: SystemTime) -> Vec<String> {
    effects
        .iter()
        .flat_map(|effect| match effect {
            Effect::Arm(command) => d.command(
                command,
                app.positions(),
                app.selected_name(),
                app.frame(),
                at,
            ),
            Effect::SavePositions(book) => d.book_saved(book, at),
            _ => Vec::new(),
        })
        .map(|record: AuditRecord| record.json_line())
        .collect()
}

#[test]
fn a_held_jog_key_records_one_start_with_axis_and_speed_then_one_stop() {
    let (mut app, t0) = app(ReleaseMode::Reported, false);
    let config = app.config().clone();
    let mut d = AuditDeriver::new(
        config.max_jog_speed,
        config.frames,
        config.positions_on_operator,
    );
    // 2026-11-30T22:27:31.000Z on the wall clock.
    let wall = UNIX_EPOCH + Duration::from_secs(1_796_077_651);
    let mut lines = Vec::new();

    // Speed down once: 50 % to the next step below.
    let effects = press(&mut app, "-", t0);
    lines.extend(records(&mut d, &app, &effects, wall));
    release(&mut app, "-", t0);
    let percent = effects
        .iter()
        .find_map(|e| match e {
            Effect::Arm(ArmCommand::SetSpeed(p)) => Some(*p),
            _ => None,
        })
        .expect("the speed key asks the driver for a speed");

    let at = t0 + Duration::from_millis(100);
    let effects = press(&mut app, "w", at);
    lines.extend(records(
        &mut d,
        &app,
        &effects,
        wall + Duration::from_millis(100),
    ));
    // Re-sends while held add nothing.
    for i in 1..=5 {
        let later = at + Duration::from_millis(100 * i);
        let effects = app.handle(armjog::console::app::Input::Tick, later);
        lines.extend(records(
            &mut d,
            &app,
            &effects,
            wall + Duration::from_millis(100 + 100 * i),
        ));
    }
    let effects = release(&mut app, "w", at + Duration::from_millis(800));
    lines.extend(records(
        &mut d,
        &app,
        &effects,
        wall + Duration::from_millis(900),
    ));

    let speed = lines
        .iter()
        .find(|l| l.contains(r#""event":"speed""#))
        .expect("the speed change is recorded");
    assert!(
        speed.starts_with(r#"{"ts":"2026-11-30T22:27:31.000Z","#),
        "{speed}"
    );
    let jogs: Vec<&String> = lines
        .iter()
        .filter(|l| l.contains(r#""event":"jog_"#))
        .collect();
    let mm_s = 250.0 * f64::from(percent) / 100.0;
    assert_eq!(
        jogs,
        [
            &format!(
                r#"{{"ts":"2026-11-30T22:27:31.100Z","event":"jog_start","axis":"+X","frame":"base","speed_percent":{percent},"speed_mm_s":{mm_s:?}}}"#
            ),
            &r#"{"ts":"2026-11-30T22:27:31.900Z","event":"jog_stop","axis":"+X","duration_ms":800}"#
                .to_string(),
        ],
        "all lines: {lines:#?}"
    );
    assert!(
        percent < armjog::link::driver::INITIAL_SPEED,
        "the speed key took effect: {percent}"
    );
}

#[test]
fn a_fresh_press_after_a_stop_is_a_new_start() {
    let (mut app, t0) = app(ReleaseMode::Reported, false);
    let mut d = AuditDeriver::new(0.25, true, false);
    let wall = UNIX_EPOCH + Duration::from_secs(1_796_077_651);
    let mut events = Vec::new();
    for (i, (key, down)) in [("w", true), ("w", false), ("s", true), ("s", false)]
        .into_iter()
        .enumerate()
    {
        let at = t0 + Duration::from_millis(200 * i as u64);
        let effects = if down {
            press(&mut app, key, at)
        } else {
            release(&mut app, key, at)
        };
        for effect in &effects {
            if let Effect::Arm(command) = effect {
                events.extend(
                    d.command(command, app.positions(), None, app.frame(), wall)
                        .into_iter()
                        .map(|r| r.event),
                );
            }
        }
    }
    let names: Vec<String> = events
        .iter()
        .map(|e| match e {
            AuditEvent::JogStart { axis, .. } => format!("start {axis}"),
            AuditEvent::JogStop { axis, .. } => format!("stop {axis}"),
            other => format!("{other:?}"),
        })
        .collect();
    assert_eq!(names, ["start +X", "stop +X", "start -X", "stop -X"]);
}

#[test]
fn a_jog_after_a_frame_change_names_the_frame_the_console_selected() {
    let (mut app, t0) = app(ReleaseMode::Reported, false);
    let mut d = AuditDeriver::new(0.25, true, false);
    let wall = UNIX_EPOCH + Duration::from_secs(1_796_077_651);
    let mut lines = Vec::new();
    let effects = press(&mut app, "g", t0);
    lines.extend(records(&mut d, &app, &effects, wall));
    release(&mut app, "g", t0);
    let at = t0 + Duration::from_millis(100);
    let effects = press(&mut app, "w", at);
    lines.extend(records(&mut d, &app, &effects, wall));
    assert_eq!(
        lines,
        [
            r#"{"ts":"2026-11-30T22:27:31.000Z","event":"frame","frame":"tool"}"#,
            r#"{"ts":"2026-11-30T22:27:31.000Z","event":"jog_start","axis":"+X","frame":"tool","speed_percent":50,"speed_mm_s":125.0}"#,
        ]
    );
}
