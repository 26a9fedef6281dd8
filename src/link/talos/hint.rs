//! What to try when an operator's first exchange fails (another dialect or checksum).

use std::time::Duration;

use tokio::sync::mpsc;

use super::{TalosConfig, TalosError, TalosEvent};
use crate::talos::frame::{ChecksumFit, Rejection};
use crate::talos::{Checksum, Dialect};

/// ": try --checksum X" after a rejection whose bytes fit checksum X.
pub(super) fn checksum_hint(rejection: &Rejection) -> String {
    match rejection.fits {
        Some(fit) => format!(": try --checksum {}", fit.fits),
        None => String::new(),
    }
}

/// The failure of a link's first exchange in words, with a hint at a dialect or checksum mismatch
/// (`fit`: a checksum the bytes fit, [`wait_for_checksum_fit`]).
pub fn first_exchange_error(
    error: &TalosError,
    config: &TalosConfig,
    fit: Option<ChecksumFit>,
) -> String {
    match error {
        TalosError::Timeout { command, id, after } => {
            let mut text = format!(
                "no reply from {} within {after:?} to {command} (id {id})",
                config.addr
            );
            match fit {
                Some(fit) => {
                    text.push_str(&format!(": the reply's {fit}: try --checksum {}", fit.fits))
                }
                None => text.push_str(&format!(
                    ": the operator may speak another dialect or checksum \
                     (now --dialect {} --checksum {}); try --dialect {} or --checksum {}",
                    config.dialect,
                    config.checksum,
                    others(&Dialect::ALL, config.dialect),
                    others(&Checksum::ALL, config.checksum),
                )),
            }
            text
        }
        other => other.to_string(),
    }
}

/// The values other than `current`, as a `--help` lists them: "xor8|none".
fn others<T: PartialEq + std::fmt::Display>(all: &[T], current: T) -> String {
    all.iter()
        .filter(|v| **v != current)
        .map(|v| v.to_string())
        .collect::<Vec<_>>()
        .join("|")
}

/// After a timed-out first exchange: waits up to `within` for the link to give up on bytes it could
/// not decode and returns the checksum they fit. A reply one byte short is given up only at the
/// frame deadline, which may come after the request's timeout.
pub async fn wait_for_checksum_fit(
    events: &mut mpsc::UnboundedReceiver<TalosEvent>,
    within: Duration,
) -> Option<ChecksumFit> {
    let wait = async {
        while let Some(event) = events.recv().await {
            if let TalosEvent::Rejected(Rejection {
                fits: Some(fit), ..
            }) = event
            {
                return Some(fit);
            }
        }
        None
    };
    tokio::time::timeout(within, wait).await.ok().flatten()
}
