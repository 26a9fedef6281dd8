//! The audit log: every technician action and what the arm and link did meanwhile, one JSON line
//! each in `audit-YYYY-MM-DD.jsonl` (docs/audit.md). Records are derived at the runtime's edge
//! ([`deriver`]), so the state machine stays pure, and written on a thread of their own
//! ([`writer`]), so a slow disk never holds up a key or a STOP.

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

/// One thing worth an entry. `event` names are stable (scripts read them; docs/audit.md). Lengths
/// in mm, angles in degrees, speeds as the cap in force (percent and tool speed).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "event", rename_all = "snake_case")]
pub enum AuditEvent {
    /// The console opened on an arm: its profile's name if used, else its target.
    SessionStart {
        arm: String,
        #[serde(skip_serializing_if = "Option::is_none")]
        target: Option<String>,
        /// The session's flight recording (MCAP), unless `--no-record`.
        #[serde(skip_serializing_if = "Option::is_none")]
        recording: Option<String>,
    },
    /// The console closed (after its last STOP).
    SessionEnd,
    /// Continuous motion began ("+X", "az+", "J3+", "+Rz"): a tool turn records its angular cap
    /// (`speed_deg_s`), every other jog its tool speed cap (`speed_mm_s`).
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
    /// A jog changed direction without stopping; its rate as [`AuditEvent::JogStart`]'s.
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
    /// A named position saved: its coordinates where known; `polar` as typed (deg, deg, mm).
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
    /// The fence's share of the speed asked for (per mille, 1000: none taken), and the tool
    /// speed that leaves.
    FenceSpeed {
        permille: u16,
        mm_s: f64,
    },
    /// The fence taught in the console (`change`, in words), written into `arm`'s profile in
    /// `file`.
    FenceChanged {
        change: String,
        arm: String,
        file: String,
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
    /// The stop guard stopped the arm, or could not: its words. Not a failed command.
    GuardStop {
        error: String,
    },
    /// The console stopped a motion telemetry showed over the cap: why, as the message line said.
    OverCap {
        reason: String,
    },
    /// Something the driver did on its own that the technician was told of.
    DriverNotice {
        text: String,
    },
    /// A stored action or sequence started by id (`kind`), capped as home is.
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
        // Serialising cannot fail; should it, the entry still names its time rather than vanish.
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

/// `$ARMJOG_STATE_DIR`, `$ARMJOG_LOG_DIR`, `~/.local/state/armjog/`, or the data directory.
pub fn audit_dir() -> Option<PathBuf> {
    let state_dir = std::env::var_os("ARMJOG_STATE_DIR").map(PathBuf::from);
    state_dir.or_else(crate::logging::log_dir)
}

#[cfg(test)]
mod tests;
