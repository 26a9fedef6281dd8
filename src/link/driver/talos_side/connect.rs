//! Opening a Talos link: connect, handshake, the operator's speed brought under the cap.

use tokio::sync::mpsc;

use super::super::connect::ConnectError;

use crate::link::speed::{INITIAL_SPEED, OperatorScale};
use crate::link::talos::{self, Answer, TalosConfig, TalosError, TalosEvent};
use crate::link::{Dialect, TalosLink};
use crate::talos::{Reply, Request};

/// A Talos link that connected and answered the handshake, not yet attached.
pub struct TalosConnected {
    pub(super) link: TalosLink,
    pub(super) link_events: mpsc::UnboundedReceiver<TalosEvent>,
    /// The operator's speed (ICD dialect), if it answered: percent of the console's cap.
    pub(super) speed: Option<u8>,
    /// The operator was over the cap and was brought under it: what to tell the technician.
    pub(super) speed_lowered: Option<String>,
    pub(super) description: String,
}

/// Connects, handshakes and reads the speed (ICD dialect). An operator over the console's cap is
/// set to [`INITIAL_SPEED`] before the link is attached (before any motion); one that refuses is
/// not attached.
pub(super) async fn connect(
    config: TalosConfig,
    oid: u16,
    scale: OperatorScale,
) -> Result<TalosConnected, ConnectError> {
    let (link, mut link_events) = TalosLink::connect(config.clone())
        .await
        .map_err(|e| ConnectError::Talos(e.into()))?;
    let version = match link.handshake(oid).await {
        Ok(Some((major, minor))) => format!(", operator {major}.{minor}"),
        Ok(None) => String::new(),
        Err(e) => {
            // A reply that fails our checksum may only be given up after the handshake timed out.
            let fit = match e {
                TalosError::Timeout { .. } => {
                    talos::wait_for_checksum_fit(&mut link_events, config.frame_deadline).await
                }
                _ => None,
            };
            let words = talos::first_exchange_error(&e, &config, fit);
            return Err(ConnectError::Handshake(words));
        }
    };
    let mut speed = None;
    let mut speed_lowered = None;
    if config.dialect == Dialect::Icd
        && let Ok(exchange) = link.request(Request::GetSpeed).await
        && let Answer::Reply(Reply::GetSpeed { speed: s, .. }) = exchange.answer
    {
        speed = scale.from_operator(s);
        if speed.is_none() {
            let lowered = Request::SetSpeed {
                speed: scale.to_operator(INITIAL_SPEED),
            };
            match link.request(lowered).await {
                Ok(exchange) if exchange.return_code().is_ok() => {
                    speed = Some(INITIAL_SPEED);
                    let cap = scale.cap().max_mm_s();
                    let was = scale.operator_mm_s(s);
                    let now = scale.cap().tool_speed_mm_s(INITIAL_SPEED);
                    let text = format!(
                        "the operator was at {s}% ({was:.0} mm/s), over the {cap:.0} mm/s cap: \
                         set to {now:.0} mm/s ({INITIAL_SPEED}% of the cap)"
                    );
                    tracing::warn!("{text}");
                    speed_lowered = Some(text);
                }
                Ok(exchange) => {
                    let code = exchange.return_code();
                    return Err(ConnectError::SpeedRefused { speed: s, code });
                }
                Err(e) => {
                    let error = e.into();
                    return Err(ConnectError::SpeedNotSet { speed: s, error });
                }
            }
        }
    }
    Ok(TalosConnected {
        link,
        link_events,
        speed,
        speed_lowered,
        description: format!(
            "talos {} ({}, {}){version}",
            config.addr, config.dialect, config.checksum
        ),
    })
}
