//! Names a Talos operator has lost: rather than send a doomed Go To, the console offers to re-save
//! the name from the coordinates it remembers, then goes there as confirmed. The go-to is dropped
//! if anything else happens first or the operator takes longer than [`RESAVE_GO_WITHIN`]: the arm
//! never starts without a fresh press.

use std::time::{Duration, Instant};

/// How long after the technician's "yes" a re-saved position is still gone to.
pub const RESAVE_GO_WITHIN: Duration = Duration::from_secs(3);

#[derive(Debug, Clone, Default)]
pub(super) struct Resave {
    /// The position of the last Go To sent to the operator: its failure names no position.
    pub(super) goto_sent: Option<String>,
    /// A confirmed re-save: go to the name when the operator accepts it, if in time.
    pub(super) then_go: Option<(String, Instant)>,
}
