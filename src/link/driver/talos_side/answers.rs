//! A Talos command's replies, awaited in order off the loop, as events and words.

use tokio::sync::mpsc;

use super::super::speed::SpeedInForce;
use crate::link::interface::{
    ArmCommand, ArmError, ArmEvent, LogEntry, PositionCoordinates, Traffic,
};
use crate::link::talos::{Answer, Exchange, PendingReply, TalosError};
use crate::talos::hardware::HwReply;
use crate::talos::{CommandValue, Reply, RequestClass, ReturnCode};

pub(super) fn hw_reply(exchange: &Exchange) -> Option<HwReply> {
    match &exchange.answer {
        Answer::Reply(Reply::HardwareOperation {
            subcommand,
            payload,
            ..
        }) => HwReply::decode(*subcommand, payload).ok(),
        _ => None,
    }
}

pub(super) fn log_entry(exchange: &Exchange) -> LogEntry {
    let code = exchange.return_code();
    LogEntry {
        id: Some(exchange.id),
        poll: false,
        count: 1,
        name: exchange.request.command().name().to_string(),
        outcome: match exchange.answer {
            Answer::Ack => "ACK".into(),
            // The operator took the motion; how it ends shows in the telemetry.
            Answer::Reply(_)
                if code.is_ok()
                    && matches!(
                        exchange.request.class(),
                        RequestClass::Motion { runs_to_end: true }
                    ) =>
            {
                "accepted".into()
            }
            Answer::Reply(_) => code.name().map_or_else(|| code.to_string(), str::to_string),
        },
        ok: code.is_ok(),
        latency: Some(exchange.latency),
        traffic: Traffic::Talos {
            request: exchange.request_bytes.clone(),
            reply: Some(exchange.reply_bytes.clone()),
        },
    }
}

pub(super) fn report_error(
    events: &mpsc::UnboundedSender<ArmEvent>,
    command: &ArmCommand,
    name: CommandValue,
    id: Option<u32>,
    error: TalosError,
) {
    log_error(events, command, name, id, &error);
    // An unknown name asked about is not a failure of the technician's: the panel marks it.
    let unknown_asked = matches!(command, ArmCommand::GetPosition { .. })
        && matches!(&error, TalosError::ReturnCode { exchange } if exchange.return_code() == ReturnCode::UNKNOWN_POSITION);
    if unknown_asked {
        return;
    }
    let _ = events.send(ArmEvent::failed(command, failure_reason(error)));
}

pub(super) fn failure_reason(error: TalosError) -> ArmError {
    match error {
        TalosError::ReturnCode { exchange } => ArmError::ReturnCode(exchange.return_code()),
        other => ArmError::Talos(other.into()),
    }
}

/// Logs a failed request (and marks an unknown name), without reporting the command failed.
pub(super) fn log_error(
    events: &mpsc::UnboundedSender<ArmEvent>,
    command: &ArmCommand,
    name: CommandValue,
    id: Option<u32>,
    error: &TalosError,
) {
    if let TalosError::ReturnCode { exchange } = error {
        let _ = events.send(ArmEvent::Log(log_entry(exchange)));
        if exchange.return_code() == ReturnCode::UNKNOWN_POSITION
            && let Some(name) = position_name(command)
        {
            let _ = events.send(ArmEvent::UnknownPosition { name });
        }
    } else {
        let entry = LogEntry::new(name.name(), error.to_string());
        let _ = events.send(ArmEvent::Log(LogEntry { id, ..entry }));
    }
}

pub(super) fn position_name(command: &ArmCommand) -> Option<String> {
    match command {
        ArmCommand::GoToPosition { name }
        | ArmCommand::DeletePosition { name }
        | ArmCommand::GetPosition { name } => Some(name.clone()),
        _ => None,
    }
}

/// Awaits a command's replies in order. A stop tries every request and reports one `Done` or
/// `Failed`. A Set Speed takes effect only once answered OK, as the percentage of the cap asked
/// for, not the operator's rounded-down value read back (which would make speed steps stick).
pub(super) async fn answers(
    command: ArmCommand,
    pending: Vec<PendingReply>,
    mut stop_failure: Option<ArmError>,
    events: mpsc::UnboundedSender<ArmEvent>,
    speed_in_force: SpeedInForce,
) {
    let all_ok = !pending.is_empty();
    let mut coordinates = PositionCoordinates::default();
    for p in pending {
        let (id, name) = (p.id(), p.command());
        match p.wait().await {
            Ok(exchange) => {
                let _ = events.send(ArmEvent::Latency(exchange.latency));
                let _ = events.send(ArmEvent::Log(log_entry(&exchange)));
                match exchange.answer {
                    Answer::Reply(Reply::GetCartesianPosition { x, y, z, .. }) => {
                        coordinates.cartesian = Some([x, y, z]);
                    }
                    Answer::Reply(Reply::GetPolarPosition {
                        delta,
                        azimuth,
                        radius,
                        ..
                    }) => coordinates.polar = Some([delta, azimuth, radius]),
                    _ => {}
                }
            }
            Err(e) if command.is_stop() => {
                // A Stop still tries every request.
                log_error(&events, &command, name, Some(id), &e);
                stop_failure.get_or_insert_with(|| failure_reason(e));
            }
            Err(e) => {
                // One failure is enough to report.
                report_error(&events, &command, name, Some(id), e);
                return;
            }
        }
    }
    if let Some(error) = stop_failure {
        let _ = events.send(ArmEvent::failed(&command, error));
        return;
    }
    if !all_ok {
        return;
    }
    if let ArmCommand::GetPosition { name } = &command {
        let _ = events.send(ArmEvent::Position {
            name: name.clone(),
            coordinates,
        });
    }
    if let ArmCommand::SetSpeed(speed) = command {
        speed_in_force.set(speed);
        let _ = events.send(ArmEvent::Speed(speed));
    }
    let _ = events.send(ArmEvent::Done { command });
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    use crate::talos::Request;

    fn outcome(request: Request, reply: Reply) -> String {
        log_entry(&Exchange {
            id: 2,
            request,
            answer: Answer::Reply(reply),
            request_bytes: vec![],
            reply_bytes: vec![],
            latency: Duration::ZERO,
        })
        .outcome
    }

    /// A move the operator runs to its end is "accepted" (how it ends shows in the telemetry);
    /// a continuous start's OK is an OK, and a refusal is named.
    #[test]
    fn the_log_says_a_move_to_its_end_was_accepted_and_a_start_ok() {
        let ok = ReturnCode::OK;
        assert_eq!(
            outcome(
                Request::Home { delay_ms: 0 },
                Reply::Home { return_code: ok }
            ),
            "accepted"
        );
        assert_eq!(
            outcome(
                Request::GoToPosition { name: "a".into() },
                Reply::GoToPosition { return_code: ok }
            ),
            "accepted"
        );
        let start = Request::PolarPanStart {
            moving_azimuth: 1,
            moving_altitude: 0,
        };
        assert_eq!(
            outcome(start.clone(), Reply::PolarPanStart { return_code: ok }),
            "OK"
        );
        assert_eq!(
            outcome(
                Request::GoToPosition { name: "a".into() },
                Reply::GoToPosition {
                    return_code: ReturnCode::UNKNOWN_POSITION
                }
            ),
            "UNKNOWN_POSITION"
        );
    }
}
