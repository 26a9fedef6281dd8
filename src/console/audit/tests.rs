//! The audit line format (hand-written expected lines) and the file's name; the deriver, the
//! writer and the session in modules of their own.

use std::time::{Duration, SystemTime, UNIX_EPOCH};

use super::*;
use crate::console::positions::PositionBook;
use crate::kortex::{Pose, ReferenceFrame};
use crate::link::interface::{ArmCommand, ArmEvent, JogMotion, LinkStatus, StepMove};

/// The deriver's records: jogs and turns started and stopped, speeds, links, saves.
mod deriver;
/// The session: an input's records, their times and order, a session dropped.
mod session;
/// The writer's files: one per UTC day, appended, records held and handed over, a failure
/// that stops nothing.
mod writer;

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

/// Telemetry with the tool at `pose`, as a Modbus link or the Talos hardware companion gives it.
fn telemetry_at(pose: Pose) -> ArmEvent {
    let mut telemetry = crate::kortex::Telemetry::decode(&crate::kortex::RegisterImage::default());
    telemetry.tcp.pose = pose;
    ArmEvent::Telemetry(Box::new(telemetry))
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

fn temp_dir() -> tempfile::TempDir {
    tempfile::tempdir().expect("temp dir")
}
