//! The deriver: one start and one stop per jog or turn whatever its refreshes, the speed and
//! frame in force, link changes once each, saves and deletes from the book or the operator,
//! stored runs.

use super::*;

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
fn the_guards_stop_is_a_guard_stop_not_a_failed_jog_and_other_failures_name_their_command() {
    use crate::link::guard::GuardNotRunning;
    use crate::link::interface::{ArmError, CommandKind};
    let mut d = deriver();
    let stopped = ArmEvent::Failed {
        command: CommandKind::Jog,
        error: ArmError::GuardStoppedArm("no heartbeat from the console for 1000 ms".into()),
    };
    assert_eq!(
        events(d.arm_event(&stopped, t0())),
        [AuditEvent::GuardStop {
            error: "the stop guard stopped the arm: no heartbeat from the console for 1000 ms"
                .into()
        }]
    );
    let failed = ArmEvent::Failed {
        command: CommandKind::Jog,
        error: ArmError::GuardStopFailed("not answered".into()),
    };
    assert_eq!(
        events(d.arm_event(&failed, t0())),
        [AuditEvent::GuardStop {
            error: "the stop guard could NOT stop the arm, it may still be moving: not answered"
                .into()
        }]
    );
    let other = ArmEvent::Failed {
        command: CommandKind::Home,
        error: ArmError::GuardNotRunning(GuardNotRunning::Starting),
    };
    assert_eq!(
        events(d.arm_event(&other, t0())),
        [AuditEvent::CommandFailed {
            command: CommandKind::Home.to_string(),
            error: "stop guard not running: still starting".into()
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
