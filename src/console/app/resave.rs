//! Names a Talos operator has lost: a go-to must not send the doomed Go To. The console offers
//! to re-save the name from the coordinates it remembers (Set Cartesian Position) and, once the
//! operator has taken them, goes there, as the technician confirmed.
//!
//! The go-to after a re-save is part of the one confirmation: it is dropped if anything else
//! happens first (any key, focus loss, the link going down, a signal), or if the operator takes
//! longer than [`RESAVE_GO_WITHIN`] to accept the coordinates. The arm never starts moving
//! without a fresh press. The offer's state is here; the state machine's side is in `book.rs`.

use std::time::{Duration, Instant};

/// How long after the technician's "yes" a re-saved position is still gone to.
pub const RESAVE_GO_WITHIN: Duration = Duration::from_secs(3);

/// The re-save offer's state.
#[derive(Debug, Clone, Default)]
pub(super) struct Resave {
    /// The position of the last Go To sent to the operator: its failure names no position.
    pub(super) goto_sent: Option<String>,
    /// A confirmed re-save: go to the name when the operator accepts it, if in time.
    pub(super) then_go: Option<(String, Instant)>,
}
