//! The audit log: every technician action, and what the arm and its link did meanwhile, as one
//! JSON line with a UTC timestamp in `audit-YYYY-MM-DD.jsonl` (docs/audit.md).
//!
//! Records are derived at the runtime's edge ([`deriver`]) from what already flows between the
//! state machine and the driver, so the state machine stays pure; a thread of its own writes
//! them ([`writer`]), so a slow or failing disk never holds up a key or a STOP.

pub mod deriver;
pub mod session;
mod utc;
pub mod writer;

use std::path::PathBuf;
use std::time::SystemTime;

use serde::Serialize;

pub use deriver::AuditDeriver;
pub use session::AuditSession;
pub use utc::{date, rfc3339_ms};
pub use writer::{AuditLog, HAND_OVER_AFTER};

/// One thing worth an entry. The `event` names are stable: scripts read them (docs/audit.md
/// lists them). Lengths are in mm, angles in degrees, speeds as the cap in force: a percentage of
/// `--max-jog-speed` and the tool speed it stands for.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "event", rename_all = "snake_case")]
pub enum AuditEvent {
    /// The console opened on an arm: its profile's name when one was used (`target` then says
    /// where it was reached), else its target ("talos-127.0.0.1:61616", ...).
    SessionStart {
        arm: String,
        #[serde(skip_serializing_if = "Option::is_none")]
        target: Option<String>,
    },
    /// The console closed (after its last STOP).
    SessionEnd,
    /// Continuous motion began: "+X", "-Y +Z", "az+", "alt-", "J3+", "+Rz". A turn of the tool
    /// records its angular rate cap (`speed_deg_s`); every other jog its tool speed cap
    /// (`speed_mm_s`).
    JogStart {
        axis: String,
        #[serde(skip_serializing_if = "Option::is_none")]
        frame: Option<String>,
        speed_percent: u8,
        #[serde(skip_serializing_if = "Option::is_none")]
        speed_mm_s: Option<f64>,
        #[serde(skip_serializing_if = "Option::is_none")]
        speed_deg_s: Option<f64>,
    },
    /// A jog changed direction without stopping (another key joined or left); its rate as
    /// [`AuditEvent::JogStart`]'s, for the new direction.
    JogChange {
        axis: String,
        from: String,
        speed_percent: u8,
        #[serde(skip_serializing_if = "Option::is_none")]
        speed_mm_s: Option<f64>,
        #[serde(skip_serializing_if = "Option::is_none")]
        speed_deg_s: Option<f64>,
    },
    /// A jog ended with a STOP, after `duration_ms`.
    JogStop {
        axis: String,
        duration_ms: u64,
    },
    /// A STOP when no jog was running (space, quitting, a stop of a step or go-to).
    Stop,
    /// A discrete move: `delta_mm` (x, y, z) or `delta_deg` (azimuth, altitude).
    Step {
        axis: String,
        #[serde(skip_serializing_if = "Option::is_none")]
        delta_mm: Option<[f64; 3]>,
        #[serde(skip_serializing_if = "Option::is_none")]
        delta_deg: Option<[i32; 2]>,
        speed_percent: u8,
        speed_mm_s: f64,
    },
    /// A named position saved (or saved over): where known, its coordinates; `polar` is
    /// (elevation deg, azimuth deg, radius mm) as typed.
    Save {
        name: String,
        #[serde(skip_serializing_if = "Option::is_none")]
        position_mm: Option<[f64; 3]>,
        #[serde(skip_serializing_if = "Option::is_none")]
        polar: Option<[f64; 3]>,
        #[serde(skip_serializing_if = "std::ops::Not::not")]
        anchor: bool,
        #[serde(skip_serializing_if = "Option::is_none")]
        parent: Option<String>,
    },
    Delete {
        name: String,
    },
    /// A move to a named position (over Modbus, to its stored pose).
    GoTo {
        #[serde(skip_serializing_if = "Option::is_none")]
        name: Option<String>,
        #[serde(skip_serializing_if = "Option::is_none")]
        position_mm: Option<[f64; 3]>,
        speed_percent: u8,
        speed_mm_s: f64,
    },
    Home {
        speed_percent: u8,
        speed_mm_s: f64,
    },
    /// The speed asked for.
    Speed {
        percent: u8,
        mm_s: f64,
    },
    /// The reference frame of cartesian jogs (Modbus).
    Frame {
        frame: String,
    },
    QuickStop,
    FaultReset,
    LinkUp {
        description: String,
    },
    LinkDown {
        reason: String,
    },
    /// Up, but nothing heard for `silent_ms`: no motion starts.
    LinkStale {
        silent_ms: u64,
    },
    /// Heard from again after being stale.
    LinkFresh,
    /// The arm reported a fault (or another one).
    Fault {
        reason: String,
    },
    FaultCleared,
    /// A command failed (the status line says the same).
    CommandFailed {
        command: String,
        error: String,
    },
    /// A STOP was not confirmed: the arm may still be moving.
    StopUnconfirmed {
        reason: String,
    },
    /// The stop guard went down: motion is refused until it is back.
    GuardDown {
        reason: String,
    },
    /// The stop guard stopped the arm (the console went quiet, or its link did), or could not:
    /// its words. Not a failed command: whatever ran (a jog, a go-to, a tour's leg) the
    /// message line names.
    GuardStop {
        error: String,
    },
    /// The telemetry showed a motion over the speed cap and the console stopped it: why, as
    /// the message line said it.
    OverCap {
        reason: String,
    },
    /// The driver did something on its own the technician was told of (an operator found over
    /// the cap brought under it).
    DriverNotice {
        text: String,
    },
    /// A stored action or sequence started by id (`kind` is `action` or `sequence`), capped
    /// as home is.
    Stored {
        kind: String,
        id: u16,
        speed_percent: u8,
        speed_mm_s: f64,
    },
}

/// An event and when it happened.
#[derive(Debug, Clone, PartialEq)]
pub struct AuditRecord {
    pub at: SystemTime,
    pub event: AuditEvent,
}

/// The line as written: the timestamp first, then the event's name and fields.
#[derive(Serialize)]
struct Line<'a> {
    ts: String,
    #[serde(flatten)]
    event: &'a AuditEvent,
}

impl AuditRecord {
    pub fn new(at: SystemTime, event: AuditEvent) -> AuditRecord {
        AuditRecord { at, event }
    }

    /// One JSON object, no newline: `{"ts":"2026-11-30T22:27:31.853Z","event":"quick_stop"}`.
    pub fn json_line(&self) -> String {
        let line = Line {
            ts: rfc3339_ms(self.at),
            event: &self.event,
        };
        // Strings, integers and finite floats only: serialising cannot fail; should it ever,
        // the entry still names its time and says so rather than vanish.
        serde_json::to_string(&line).unwrap_or_else(|e| {
            format!(
                "{{\"ts\":\"{}\",\"event\":\"unwritable\",\"error\":{}}}",
                rfc3339_ms(self.at),
                serde_json::Value::String(e.to_string())
            )
        })
    }

    /// The file this record belongs in: `audit-YYYY-MM-DD.jsonl`, by its UTC date.
    pub fn file_name(&self) -> String {
        format!("audit-{}.jsonl", date(self.at))
    }
}

/// Where the audit files go: `$ARMJOG_STATE_DIR`, else where the logs go
/// ([`crate::logging::log_dir`]: a run that keeps its logs elsewhere keeps its audit with them).
pub fn audit_dir() -> Option<PathBuf> {
    match std::env::var_os("ARMJOG_STATE_DIR") {
        Some(dir) => Some(PathBuf::from(dir)),
        None => crate::logging::log_dir(),
    }
}

#[cfg(test)]
mod tests;
