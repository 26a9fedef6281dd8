//! How far a stored action or sequence started by id has got, from telemetry: one reading for
//! `armjog modbus home|action|sequence` and the console. Status registers 100-102 describe the last
//! move whoever started it, so "completed" or "aborted" counts only after the run was seen started
//! or [`STATUS_GRACE`] passed; no sign within [`START_LIMIT`] means not taken; a status naming
//! another move after ours started ([`OurMove::other_in`]) is another client's.

use std::fmt;
use std::time::Duration;

use super::arm_state::{OurMove, abort_reason, at_rest, fault_reason};
use super::codes::{ActionStatus, CodeName, Coded, MoveType};
use super::commands::StoredMotion;
use super::telemetry::Telemetry;

/// A status read this soon after the start may still be the previous run's.
pub const STATUS_GRACE: Duration = Duration::from_millis(500);
/// An arm that has not taken the id by then does not have it.
pub const START_LIMIT: Duration = Duration::from_secs(2);

impl StoredMotion {
    /// `action` or `sequence`, as messages name it: its move type's key.
    pub fn name(self) -> &'static str {
        self.move_type().key()
    }

    /// Its move type in register 202.
    pub fn move_type(self) -> MoveType {
        match self {
            StoredMotion::Action => MoveType::Action,
            StoredMotion::Sequence => MoveType::Sequence,
        }
    }
}

/// A stored action or sequence, by id: `action 5`, `sequence 1`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Stored {
    pub motion: StoredMotion,
    pub id: u16,
}

impl Stored {
    /// The run as the action status names it: its move type and id.
    pub fn as_our_move(&self) -> OurMove {
        OurMove {
            move_type: self.motion.move_type(),
            id: Some(self.id),
        }
    }
}

impl fmt::Display for Stored {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} {}", self.motion.name(), self.id)
    }
}

/// What one poll says about the run.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Progress {
    /// Not shown yet: the arm has not reported the run (nor refused it).
    Pending,
    /// Shown started for the first time by this poll.
    Started,
    /// Still running (seen started before).
    Running,
    /// Completed with the arm at rest.
    Completed,
    /// Aborted after it ran (a stop, another client, a joint limit, named if so).
    Aborted(String),
    Fault(String),
    /// Not taken: refused at once, or something else reported after [`START_LIMIT`].
    NotTaken(String),
    /// Seen started, then the status names another client's move (never the run's end).
    OtherMove(String),
}

impl Progress {
    /// Whether the run is over (completed or failed).
    pub fn ended(&self) -> bool {
        !matches!(
            self,
            Progress::Pending | Progress::Started | Progress::Running
        )
    }
}

/// One run being watched: feed it every poll with the time since the start was written.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StoredRun {
    pub stored: Stored,
    seen_started: bool,
}

impl StoredRun {
    pub fn new(stored: Stored) -> StoredRun {
        StoredRun {
            stored,
            seen_started: false,
        }
    }

    pub fn seen_started(&self) -> bool {
        self.seen_started
    }

    /// What the poll `t`, read `elapsed` after the start was written, says about the run.
    pub fn observe(&mut self, t: &Telemetry, elapsed: Duration) -> Progress {
        if let Some(fault) = fault_reason(t) {
            return Progress::Fault(fault);
        }
        if self.seen_started
            && let Some(other) = self.stored.as_our_move().other_in(&t.action)
        {
            return Progress::OtherMove(other);
        }
        let ours = t.action.id == self.stored.id
            && t.action.move_type == Coded::Known(self.stored.motion.move_type());
        let mut first_seen = false;
        if ours && t.action.status == Coded::Known(ActionStatus::Started) && !self.seen_started {
            self.seen_started = true;
            first_seen = true;
        }
        let current = ours && (self.seen_started || elapsed >= STATUS_GRACE);
        match t.action.status {
            Coded::Known(ActionStatus::Aborted) if current => {
                let reason = abort_reason(t);
                if self.seen_started {
                    Progress::Aborted(reason)
                } else {
                    Progress::NotTaken(format!(
                        "the arm did not take {}: {reason} at once (is it on the arm's Web App, \
                         Actions page?)",
                        self.stored
                    ))
                }
            }
            Coded::Known(ActionStatus::Completed) if current && at_rest(t) => Progress::Completed,
            _ if !ours && elapsed >= START_LIMIT => Progress::NotTaken(format!(
                "the arm did not take {} within {:.0} s: it reports {} {} (is it on the arm's \
                 Web App, Actions page?)",
                self.stored,
                START_LIMIT.as_secs_f64(),
                t.action.move_type.key().replace('_', " "),
                t.action.id,
            )),
            _ if first_seen => Progress::Started,
            _ if self.seen_started => Progress::Running,
            _ => Progress::Pending,
        }
    }
}

#[cfg(test)]
mod tests;
