//! The audit line format (hand-written expected lines), the deriver's starts and stops, and
//! the writer's files: one per UTC day, and a failure that stops nothing.

use std::time::{Duration, SystemTime, UNIX_EPOCH};

use super::*;
use crate::console::positions::PositionBook;
use crate::kortex::{Pose, ReferenceFrame};
use crate::link::interface::{ArmCommand, ArmEvent, JogMotion, LinkStatus, StepMove};

/// 2026-11-30T22:27:31.853Z.
fn t0() -> SystemTime {
    UNIX_EPOCH + Duration::from_millis(1_796_077_651_853)
}

fn line(event: AuditEvent) -> String {
    AuditRecord::new(t0(), event).json_line()
}

#[test]
fn lines_carry_the_timestamp_first_then_the_event_and_its_fields() {
    assert_eq!(
        line(AuditEvent::QuickStop),
        r#"{"ts":"2026-11-30T22:27:31.853Z","event":"quick_stop"}"#
    );
    assert_eq!(
        line(AuditEvent::JogStart {
            axis: "+X".into(),
            frame: Some("base".into()),
            speed_percent: 50,
            speed_mm_s: Some(125.0),
            speed_deg_s: None,
        }),
        r#"{"ts":"2026-11-30T22:27:31.853Z","event":"jog_start","axis":"+X","frame":"base","speed_percent":50,"speed_mm_s":125.0}"#
    );
    assert_eq!(
        line(AuditEvent::JogStop {
            axis: "J3-".into(),
            duration_ms: 1250,
        }),
        r#"{"ts":"2026-11-30T22:27:31.853Z","event":"jog_stop","axis":"J3-","duration_ms":1250}"#
    );
    assert_eq!(
        line(AuditEvent::Save {
            name: "pick \"A\"".into(),
            position_mm: Some([456.6, -1.0, 433.8]),
            polar: None,
            anchor: false,
            parent: None,
        }),
        r#"{"ts":"2026-11-30T22:27:31.853Z","event":"save","name":"pick \"A\"","position_mm":[456.6,-1.0,433.8]}"#
    );
    assert_eq!(
        line(AuditEvent::LinkDown {
            reason: "talos: connection refused".into(),
        }),
        r#"{"ts":"2026-11-30T22:27:31.853Z","event":"link_down","reason":"talos: connection refused"}"#
    );
    assert_eq!(
        line(AuditEvent::Speed {
            percent: 10,
            mm_s: 25.0
        }),
        r#"{"ts":"2026-11-30T22:27:31.853Z","event":"speed","percent":10,"mm_s":25.0}"#
    );
}

#[test]
fn the_file_is_named_for_the_records_utc_date() {
    let record = AuditRecord::new(t0(), AuditEvent::Stop);
    assert_eq!(record.file_name(), "audit-2026-11-30.jsonl");
}

fn deriver() -> AuditDeriver {
    // 250 mm/s at 100 %, Modbus frames, the console's own book.
    AuditDeriver::new(0.25, true, false)
}

fn events(records: Vec<AuditRecord>) -> Vec<AuditEvent> {
    records.into_iter().map(|r| r.event).collect()
}

/// The frame the console selected, as the runtime passes it (`App::frame`).
const BASE: ReferenceFrame = ReferenceFrame::Base;

const PLUS_X: ArmCommand = ArmCommand::Jog(JogMotion::Cartesian { x: 1, y: 0, z: 0 });

#[test]
fn a_jog_is_one_start_and_one_stop_whatever_its_refreshes() {
    let mut d = deriver();
    let book = PositionBook::new();
    let mut at = t0();
    let mut send = |d: &mut AuditDeriver, c: &ArmCommand, after_ms: u64| {
        at += Duration::from_millis(after_ms);
        events(d.command(c, &book, None, BASE, at))
    };
    assert_eq!(
        send(&mut d, &ArmCommand::SetSpeed(20), 0),
        [AuditEvent::Speed {
            percent: 20,
            mm_s: 50.0
        }]
    );
    assert_eq!(
        send(&mut d, &PLUS_X, 100),
        [AuditEvent::JogStart {
            axis: "+X".into(),
            frame: Some("base".into()),
            speed_percent: 20,
            speed_mm_s: Some(50.0),
            speed_deg_s: None,
        }]
    );
    for _ in 0..5 {
        assert_eq!(send(&mut d, &PLUS_X, 100), []);
    }
    let diagonal = ArmCommand::Jog(JogMotion::Cartesian { x: 1, y: 0, z: 1 });
    assert_eq!(
        send(&mut d, &diagonal, 100),
        [AuditEvent::JogChange {
            axis: "+X +Z".into(),
            from: "+X".into(),
            speed_percent: 20,
            speed_mm_s: Some(50.0),
            speed_deg_s: None,
        }]
    );
    assert_eq!(
        send(&mut d, &ArmCommand::Stop, 150),
        [AuditEvent::JogStop {
            axis: "+X +Z".into(),
            duration_ms: 750,
        }]
    );
    // A second STOP ends no jog.
    assert_eq!(send(&mut d, &ArmCommand::Stop, 10), [AuditEvent::Stop]);
    // A turn of the tool names its axis, the frame it turns in and its angular rate: 20 % of
    // 30 deg/s, and no tool speed (its point stays put).
    let turn = ArmCommand::Jog(JogMotion::Orientation {
        rx: 0,
        ry: 0,
        rz: -1,
    });
    assert_eq!(
        send(&mut d, &turn, 10),
        [AuditEvent::JogStart {
            axis: "-Rz".into(),
            frame: Some("base".into()),
            speed_percent: 20,
            speed_mm_s: None,
            speed_deg_s: Some(6.0),
        }]
    );
    let two_turns = ArmCommand::Jog(JogMotion::Orientation {
        rx: 1,
        ry: 0,
        rz: -1,
    });
    assert_eq!(
        send(&mut d, &two_turns, 100),
        [AuditEvent::JogChange {
            axis: "+Rx -Rz".into(),
            from: "-Rz".into(),
            speed_percent: 20,
            speed_mm_s: None,
            speed_deg_s: Some(6.0),
        }]
    );
}

#[test]
fn a_turn_records_its_rate_in_degrees_per_second_and_no_tool_speed() {
    let mut d = deriver();
    d.arm_event(&ArmEvent::Speed(100), t0());
    let turn = ArmCommand::Jog(JogMotion::Orientation {
        rx: 1,
        ry: 0,
        rz: 0,
    });
    let records = d.command(&turn, &PositionBook::new(), None, BASE, t0());
    let lines: Vec<String> = records.iter().map(AuditRecord::json_line).collect();
    assert_eq!(
        lines,
        [
            r#"{"ts":"2026-11-30T22:27:31.853Z","event":"jog_start","axis":"+Rx","frame":"base","speed_percent":100,"speed_deg_s":30.0}"#
        ]
    );
}

#[test]
fn a_turn_names_its_frame_also_where_frames_are_not_offered() {
    // Both links: cartesian jogs go over Talos (no frame), turns over Modbus in base.
    let mut d = AuditDeriver::new(0.25, false, true);
    let cartesian = ArmCommand::Jog(JogMotion::Cartesian { x: 1, y: 0, z: 0 });
    let turn = ArmCommand::Jog(JogMotion::Orientation {
        rx: 0,
        ry: 0,
        rz: -1,
    });
    let stop = ArmCommand::Stop;
    let book = PositionBook::new();
    let starts: Vec<AuditEvent> = [&cartesian, &stop, &turn]
        .into_iter()
        .flat_map(|c| d.command(c, &book, None, BASE, t0()))
        .map(|r| r.event)
        .filter(|e| matches!(e, AuditEvent::JogStart { .. }))
        .collect();
    let frames: Vec<Option<String>> = starts
        .iter()
        .map(|e| match e {
            AuditEvent::JogStart { frame, .. } => frame.clone(),
            _ => None,
        })
        .collect();
    assert_eq!(frames, [None, Some("base".to_string())]);
}

#[test]
fn the_speed_in_force_is_the_one_the_driver_reports() {
    let mut d = deriver();
    d.arm_event(&ArmEvent::Speed(75), t0());
    let step = ArmCommand::Step(StepMove::Polar {
        azimuth: -10,
        altitude: 0,
    });
    assert_eq!(
        events(d.command(&step, &PositionBook::new(), None, BASE, t0())),
        [AuditEvent::Step {
            axis: "az-".into(),
            delta_mm: None,
            delta_deg: Some([-10, 0]),
            speed_percent: 75,
            speed_mm_s: 187.5,
        }]
    );
}

#[test]
fn a_jog_start_names_the_frame_the_console_selected() {
    let mut d = deriver();
    let book = PositionBook::new();
    assert_eq!(
        events(d.command(&PLUS_X, &book, None, ReferenceFrame::Tool, t0())),
        [AuditEvent::JogStart {
            axis: "+X".into(),
            frame: Some("tool".into()),
            speed_percent: 50,
            speed_mm_s: Some(125.0),
            speed_deg_s: None,
        }]
    );
}

#[test]
fn a_speed_the_driver_refuses_is_recorded_as_asked_and_not_put_in_force() {
    let mut d = deriver();
    let book = PositionBook::new();
    assert_eq!(
        events(d.command(&ArmCommand::SetSpeed(0), &book, None, BASE, t0())),
        [AuditEvent::Speed {
            percent: 0,
            mm_s: 0.0
        }]
    );
    assert!(matches!(
        events(d.command(&PLUS_X, &book, None, BASE, t0()))[..],
        [AuditEvent::JogStart {
            speed_percent: 50,
            ..
        }]
    ));
}

#[test]
fn a_quick_stop_ends_the_jog_and_the_next_press_starts_one() {
    let mut d = deriver();
    let book = PositionBook::new();
    d.command(&PLUS_X, &book, None, BASE, t0());
    assert_eq!(
        events(d.command(&ArmCommand::QuickStop, &book, None, BASE, t0())),
        [AuditEvent::QuickStop]
    );
    assert!(matches!(
        events(d.command(&PLUS_X, &book, None, BASE, t0()))[..],
        [AuditEvent::JogStart { .. }]
    ));
}

#[test]
fn link_changes_are_recorded_once_each() {
    let mut d = deriver();
    let up = ArmEvent::Status(LinkStatus::Up {
        description: "talos 10.0.0.2:61616".into(),
    });
    assert!(events(d.arm_event(&ArmEvent::Status(LinkStatus::Connecting), t0())).is_empty());
    assert_eq!(
        events(d.arm_event(&up, t0())),
        [AuditEvent::LinkUp {
            description: "talos 10.0.0.2:61616".into()
        }]
    );
    assert!(events(d.arm_event(&up, t0())).is_empty());
    assert_eq!(
        events(d.link_stale(Some(Duration::from_millis(1500)), t0())),
        [AuditEvent::LinkStale { silent_ms: 1500 }]
    );
    assert!(events(d.link_stale(Some(Duration::from_millis(1600)), t0())).is_empty());
    assert_eq!(events(d.link_stale(None, t0())), [AuditEvent::LinkFresh]);
    let down = ArmEvent::Status(LinkStatus::Down {
        reason: "talos: timed out".into(),
    });
    assert_eq!(
        events(d.arm_event(&down, t0())),
        [AuditEvent::LinkDown {
            reason: "talos: timed out".into()
        }]
    );
}

#[test]
fn local_book_saves_become_save_and_delete_records() {
    let mut d = deriver();
    let mut book = PositionBook::new();
    book.get_or_insert("kept").cartesian = Some([1, 2, 3]);
    d.book_loaded(&book);
    book.get_or_insert("pick").cartesian = Some([4566, -10, 4338]);
    assert_eq!(
        events(d.book_saved(&book, t0())),
        [AuditEvent::Save {
            name: "pick".into(),
            position_mm: Some([456.6, -1.0, 433.8]),
            polar: None,
            anchor: false,
            parent: None,
        }]
    );
    book.remove("kept");
    assert_eq!(
        events(d.book_saved(&book, t0())),
        [AuditEvent::Delete {
            name: "kept".into()
        }]
    );
    // A go-to over Modbus names the position its pose came from.
    let pose = pick_pose();
    let go = events(d.command(&ArmCommand::MoveToPose(pose), &book, None, BASE, t0()));
    assert!(
        matches!(&go[..], [AuditEvent::GoTo { name: Some(n), .. }] if n == "pick"),
        "{go:?}"
    );
}

#[test]
fn with_an_operator_its_commands_say_what_was_saved_not_the_book() {
    let mut d = AuditDeriver::new(0.25, false, true);
    let mut book = PositionBook::new();
    book.get_or_insert("pick").cartesian = Some([1, 2, 3]);
    assert!(d.book_saved(&book, t0()).is_empty());
    let save = ArmCommand::SavePosition {
        name: "pick".into(),
        anchor: true,
        parent: None,
    };
    assert_eq!(
        line(events(d.command(&save, &book, None, BASE, t0())).remove(0)),
        r#"{"ts":"2026-11-30T22:27:31.853Z","event":"save","name":"pick","anchor":true}"#
    );
}

/// Telemetry with the tool at `pose`, as a Modbus link or the Talos hardware companion gives it.
fn telemetry_at(pose: Pose) -> ArmEvent {
    let mut telemetry = crate::kortex::Telemetry::decode(&crate::kortex::RegisterImage::default());
    telemetry.tcp.pose = pose;
    ArmEvent::Telemetry(Box::new(telemetry))
}

#[test]
fn with_an_operator_a_save_records_where_the_telemetry_has_the_tool() {
    let mut d = AuditDeriver::new(0.25, false, true);
    let book = PositionBook::new();
    let save = ArmCommand::SavePosition {
        name: "pick".into(),
        anchor: false,
        parent: Some("table".into()),
    };
    assert!(d.arm_event(&telemetry_at(pick_pose()), t0()).is_empty());
    assert_eq!(
        line(events(d.command(&save, &book, None, BASE, t0())).remove(0)),
        r#"{"ts":"2026-11-30T22:27:31.853Z","event":"save","name":"pick","position_mm":[456.6,-1.0,433.8],"parent":"table"}"#
    );
    // A position that is not a number is not known: none is recorded.
    let nowhere = Pose {
        x: f32::NAN,
        ..pick_pose()
    };
    d.arm_event(&telemetry_at(nowhere), t0());
    let saved = events(d.command(&save, &book, None, BASE, t0()));
    assert!(
        matches!(
            &saved[..],
            [AuditEvent::Save {
                position_mm: None,
                ..
            }]
        ),
        "{saved:?}"
    );
}

fn temp_dir() -> tempfile::TempDir {
    tempfile::tempdir().expect("temp dir")
}

/// Writes `records` through the writer thread, waits for it to end, and returns the failures
/// it reported.
async fn write_records(dir: std::path::PathBuf, records: Vec<AuditRecord>) -> Vec<String> {
    let mut log = AuditLog::start(Some(dir));
    for record in records {
        log.record(record);
    }
    let (_, closed) = tokio::sync::mpsc::unbounded_channel();
    let mut reported = std::mem::replace(&mut log.errors, closed);
    log.finish(Duration::from_secs(10)).await;
    let mut errors = Vec::new();
    while let Ok(e) = reported.try_recv() {
        errors.push(e);
    }
    errors
}

#[tokio::test]
async fn a_session_over_midnight_continues_in_the_next_days_file() {
    let dir = temp_dir();
    // 2026-11-30T23:59:59.900Z, then 200 ms later.
    let before = UNIX_EPOCH + Duration::from_millis(1_796_083_199_900);
    let after = before + Duration::from_millis(200);
    let errors = write_records(
        dir.path().to_path_buf(),
        vec![
            AuditRecord::new(before, AuditEvent::QuickStop),
            AuditRecord::new(after, AuditEvent::FaultReset),
        ],
    )
    .await;
    assert!(errors.is_empty(), "{errors:?}");
    let read = |name: &str| std::fs::read_to_string(dir.path().join(name)).expect(name);
    assert_eq!(
        read("audit-2026-11-30.jsonl"),
        "{\"ts\":\"2026-11-30T23:59:59.900Z\",\"event\":\"quick_stop\"}\n"
    );
    assert_eq!(
        read("audit-2026-12-01.jsonl"),
        "{\"ts\":\"2026-12-01T00:00:00.100Z\",\"event\":\"fault_reset\"}\n"
    );
}

#[tokio::test]
async fn lines_are_appended_to_an_existing_file() {
    let dir = temp_dir();
    let path = dir.path().join("audit-2026-11-30.jsonl");
    std::fs::write(&path, "earlier\n").expect("seed");
    write_records(
        dir.path().to_path_buf(),
        vec![AuditRecord::new(t0(), AuditEvent::Stop)],
    )
    .await;
    let text = std::fs::read_to_string(&path).expect("read");
    assert_eq!(
        text,
        "earlier\n{\"ts\":\"2026-11-30T22:27:31.853Z\",\"event\":\"stop\"}\n"
    );
}

/// The lines of `name` in `dir` once the writer has written `count` of them (at most 10 s).
fn lines_once_written(dir: &std::path::Path, name: &str, count: usize) -> Vec<String> {
    let until = std::time::Instant::now() + Duration::from_secs(10);
    loop {
        let text = std::fs::read_to_string(dir.join(name)).unwrap_or_default();
        let lines: Vec<String> = text.lines().map(str::to_string).collect();
        if lines.len() >= count || std::time::Instant::now() >= until {
            return lines;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
}

#[tokio::test]
async fn records_are_held_until_handed_over_and_none_is_lost() {
    let dir = temp_dir();
    let mut log = AuditLog::start(Some(dir.path().to_path_buf()));
    assert_eq!(log.hand_over_at(), None, "nothing held yet");
    let before = std::time::Instant::now();
    log.record(AuditRecord::new(t0(), AuditEvent::Stop));
    let due = log.hand_over_at().expect("a record is held");
    assert!(due >= before + HAND_OVER_AFTER, "{due:?}");
    assert!(
        due <= std::time::Instant::now() + HAND_OVER_AFTER,
        "{due:?}"
    );
    // A second record is due with the first, not later.
    log.record(AuditRecord::new(t0(), AuditEvent::QuickStop));
    assert_eq!(log.hand_over_at(), Some(due));
    // The writer has not been given them: nothing is written however long it waits.
    std::thread::sleep(Duration::from_millis(100));
    assert!(!dir.path().join("audit-2026-11-30.jsonl").exists());
    log.hand_over();
    assert_eq!(log.hand_over_at(), None);
    let lines = lines_once_written(dir.path(), "audit-2026-11-30.jsonl", 2);
    assert_eq!(
        lines,
        [
            "{\"ts\":\"2026-11-30T22:27:31.853Z\",\"event\":\"stop\"}",
            "{\"ts\":\"2026-11-30T22:27:31.853Z\",\"event\":\"quick_stop\"}",
        ]
    );
    log.finish(Duration::from_secs(10)).await;
}

#[test]
fn records_held_when_the_log_is_dropped_are_written() {
    // As when a panic unwinds through the event loop.
    let dir = temp_dir();
    let mut log = AuditLog::start(Some(dir.path().to_path_buf()));
    log.record(AuditRecord::new(t0(), AuditEvent::FaultReset));
    drop(log);
    let lines = lines_once_written(dir.path(), "audit-2026-11-30.jsonl", 1);
    assert_eq!(
        lines,
        ["{\"ts\":\"2026-11-30T22:27:31.853Z\",\"event\":\"fault_reset\"}"]
    );
}

#[tokio::test]
async fn a_write_that_fails_is_reported_once_and_stops_nothing() {
    let dir = temp_dir();
    // A file where the directory should be: unwritable even for root (unlike a read-only
    // directory).
    let blocked = dir.path().join("not-a-dir");
    std::fs::write(&blocked, "").expect("seed");
    let records = (0..5)
        .map(|i| AuditRecord::new(t0() + Duration::from_secs(i), AuditEvent::Stop))
        .collect();
    let started = std::time::Instant::now();
    let errors = write_records(blocked.join("audit"), records).await;
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(
        errors[0].contains("audit log not written") && errors[0].contains("not-a-dir"),
        "{}",
        errors[0]
    );
    assert!(started.elapsed() < Duration::from_secs(10));
}

#[test]
fn a_stored_run_by_id_is_recorded_with_its_kind_id_and_cap_as_home_is() {
    let mut d = deriver();
    d.arm_event(&ArmEvent::Speed(40), t0());
    let run = ArmCommand::StartStored(crate::kortex::Stored {
        motion: crate::kortex::StoredMotion::Sequence,
        id: 1,
    });
    let recorded = d.command(&run, &PositionBook::new(), None, BASE, t0());
    assert_eq!(recorded.len(), 1);
    assert_eq!(
        recorded[0].json_line(),
        r#"{"ts":"2026-11-30T22:27:31.853Z","event":"stored","kind":"sequence","id":1,"speed_percent":40,"speed_mm_s":100.0}"#
    );
}

/// Every line written in `dir`, whatever its day's file, oldest file first.
fn all_lines(dir: &std::path::Path) -> Vec<String> {
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .expect("dir")
        .map(|entry| entry.expect("entry").path())
        .collect();
    files.sort();
    files
        .iter()
        .flat_map(|file| {
            let text = std::fs::read_to_string(file).expect("audit file");
            text.lines().map(str::to_string).collect::<Vec<_>>()
        })
        .collect()
}

/// Where the book's "pick" (4566, -10, 4338 tenths of mm) is, as a Modbus go-to carries it.
fn pick_pose() -> Pose {
    Pose {
        x: 0.4566,
        y: -0.001,
        z: 0.4338,
        theta_x: 90.0,
        theta_y: 0.0,
        theta_z: 90.0,
    }
}

/// An app on `book` and an audit session writing to `dir`.
fn app_and_session(
    dir: &std::path::Path,
    book: PositionBook,
) -> (crate::console::app::App, AuditSession) {
    let config = crate::console::app::AppConfig::for_tests();
    let app = crate::console::app::App::new(config.clone(), book);
    let session = AuditSession::start(&config, "sim".into(), None, Some(dir.into()));
    (app, session)
}

#[tokio::test]
async fn an_inputs_commands_are_recorded_at_the_next_turn_stamped_when_it_was_handled() {
    let dir = temp_dir();
    let (app, mut session) = app_and_session(dir.path(), PositionBook::new());
    session.command(ArmCommand::Jog(JogMotion::Cartesian { x: 1, y: 0, z: 0 }));
    let before = SystemTime::now();
    session.handled(&app);
    let after = SystemTime::now();
    // The loop's next turn comes later: the record keeps the input's time.
    std::thread::sleep(Duration::from_millis(50));
    session.record_handled();
    // Recorded once, however many turns follow.
    session.record_handled();
    session.finish(Duration::from_secs(10)).await;
    let lines = all_lines(dir.path());
    let event = |line: &String| {
        let value: serde_json::Value = serde_json::from_str(line).expect("json");
        (
            value["event"].as_str().map(str::to_string),
            value["ts"].clone(),
        )
    };
    let events: Vec<_> = lines.iter().map(event).collect();
    let names: Vec<_> = events.iter().map(|(name, _)| name.as_deref()).collect();
    assert_eq!(
        names,
        [
            Some("session_start"),
            Some("jog_start"),
            Some("session_end")
        ],
        "{lines:?}"
    );
    // The same format, so the strings order as the times do.
    let stamped = events[1].1.as_str().expect("ts").to_string();
    let (earliest, latest) = (utc::rfc3339_ms(before), utc::rfc3339_ms(after));
    assert!(
        earliest <= stamped && stamped <= latest,
        "jog_start at {stamped}, handled between {earliest} and {latest}"
    );
}

fn event_names(dir: &std::path::Path) -> Vec<String> {
    all_lines(dir)
        .iter()
        .map(|line| {
            let value: serde_json::Value = serde_json::from_str(line).expect("json");
            value["event"].as_str().unwrap_or_default().to_string()
        })
        .collect()
}

#[tokio::test]
async fn an_inputs_records_need_no_app_once_it_is_handled() {
    let dir = temp_dir();
    let mut book = PositionBook::new();
    book.get_or_insert("pick").cartesian = Some([4566, -10, 4338]);
    let (app, mut session) = app_and_session(dir.path(), book);
    let pose = pick_pose();
    session.command(ArmCommand::MoveToPose(pose));
    session.handled(&app);
    drop(app);
    // The app is gone (a panic unwound it): the go-to is still recorded, with its name.
    session.record_handled();
    session.finish(Duration::from_secs(10)).await;
    let lines = all_lines(dir.path());
    let go_to: Vec<serde_json::Value> = lines
        .iter()
        .map(|line| serde_json::from_str(line).expect("json"))
        .filter(|value: &serde_json::Value| value["event"] == "go_to")
        .collect();
    assert_eq!(go_to.len(), 1, "{lines:?}");
    assert_eq!(go_to[0]["name"], "pick", "{lines:?}");
}

#[test]
fn a_session_dropped_between_an_input_and_the_next_turn_records_the_input() {
    let dir = temp_dir();
    let (app, mut session) = app_and_session(dir.path(), PositionBook::new());
    session.command(ArmCommand::Jog(JogMotion::Cartesian { x: 0, y: 1, z: 0 }));
    session.handled(&app);
    // As an unwinding panic drops it: no next turn, no finish.
    drop(session);
    // The writer ends once it has written what it was handed.
    let until = std::time::Instant::now() + Duration::from_secs(10);
    let mut names = event_names(dir.path());
    while !names.iter().any(|name| name == "jog_start") && std::time::Instant::now() < until {
        std::thread::sleep(Duration::from_millis(20));
        names = event_names(dir.path());
    }
    assert_eq!(names, ["session_start", "jog_start"]);
}

#[tokio::test]
async fn records_keep_the_order_of_their_inputs_whenever_they_are_made() {
    let dir = temp_dir();
    let (app, mut session) = app_and_session(dir.path(), PositionBook::new());
    // A press, then its release before the loop turned again (a key's records wait until
    // its frames are out): the press is recorded first.
    session.command(ArmCommand::Jog(JogMotion::Cartesian { x: 1, y: 0, z: 0 }));
    session.handled(&app);
    session.command(ArmCommand::Stop);
    session.handled(&app);
    // An arm event after: recorded after both.
    session.input(&crate::console::app::Input::Arm(ArmEvent::Status(
        LinkStatus::Up {
            description: "talos 10.0.0.2:61616".into(),
        },
    )));
    session.finish(Duration::from_secs(10)).await;
    assert_eq!(
        event_names(dir.path()),
        [
            "session_start",
            "jog_start",
            "jog_stop",
            "link_up",
            "session_end"
        ]
    );
}

/// A key press, as the terminal reader hands it to the app.
fn key_press(name: &str) -> crate::console::app::Input {
    use crate::console::app::{Input, KeyInput};
    let key = name.parse().expect("key name");
    let text = name.chars().next().filter(|_| name.chars().count() == 1);
    Input::Key(KeyInput {
        key,
        text,
        kind: crate::console::jog::KeyKind::Press,
    })
}

#[tokio::test]
async fn a_save_over_talos_with_modbus_telemetry_records_the_tools_position() {
    use crate::console::app::{Effect, Input};
    use crate::link::interface::TelemetrySource;
    let dir = temp_dir();
    // A Talos operator in the ICD dialect keeps the positions; Modbus gives the telemetry.
    let (mut app, mut session) = app_and_session(dir.path(), PositionBook::new());
    let now = std::time::Instant::now();
    let inputs = [
        Input::Arm(ArmEvent::TelemetrySource(TelemetrySource::Modbus)),
        Input::Arm(ArmEvent::Status(LinkStatus::Up {
            description: "talos 127.0.0.1:61616, modbus 127.0.0.1:502".into(),
        })),
        Input::Arm(telemetry_at(pick_pose())),
    ];
    for input in inputs {
        session.input(&input);
        app.handle(input, now);
        session.handled(&app);
    }
    let keys = ["p", "b", "e", "n", "c", "h", "enter"];
    for name in keys {
        let input = key_press(name);
        session.input(&input);
        for effect in app.handle(input, now) {
            if let Effect::Arm(command) = effect {
                session.command(command);
            }
        }
        session.handled(&app);
    }
    session.finish(Duration::from_secs(10)).await;
    let saves: Vec<String> = all_lines(dir.path())
        .into_iter()
        .filter(|line| line.contains(r#""event":"save""#))
        .collect();
    assert_eq!(saves.len(), 1, "{saves:?}");
    assert!(
        saves[0].ends_with(r#""event":"save","name":"bench","position_mm":[456.6,-1.0,433.8]}"#),
        "{saves:?}"
    );
}
