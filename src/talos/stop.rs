//! What "stop" and "motion" mean on a Talos link, as facts of the ICD: what each request does
//! ([`Request::class`]), and the set that stops every motion a dialect may carry. Every path that
//! stops the Talos side sends [`stop_requests`], the stop guard included.

use super::hardware::{HwRequest, subcommand};
use super::{Dialect, Request};

/// What a Talos request does to the arm, by the Talos ICD and the hardware companion ICD.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RequestClass {
    /// One of the ICD's stops: Cartesian Move STOP (0x0007), Polar Pan STOP (0x0004), and
    /// Execute Hardware Operation (0x0008) STOP_ALL_JOINTS (subcommand 0x0004). The link
    /// never holds one back, and re-sends it in the ack dialect.
    Stop,
    /// May set the arm moving. `runs_to_end`: the operator carries it to its end on its own
    /// (discrete pan and move, home, go-to), so its OK says only that it was accepted; otherwise it
    /// moves until stopped or no longer refreshed.
    Motion { runs_to_end: bool },
    /// Moves nothing: the handshake, speed, the operator's positions, reads, a fault clear.
    Still,
}

impl Request {
    /// What this request does to the arm. No `_` arm: a new request must be classified here.
    pub fn class(&self) -> RequestClass {
        match self {
            Request::PolarPanStop | Request::CartesianMoveStop => RequestClass::Stop,
            Request::PolarPan { .. }
            | Request::Home { .. }
            | Request::CartesianMove { .. }
            | Request::GoToPosition { .. } => RequestClass::Motion { runs_to_end: true },
            Request::PolarPanStart { .. } | Request::CartesianMoveStart { .. } => {
                RequestClass::Motion { runs_to_end: false }
            }
            Request::HardwareOperation { subcommand, .. } => match *subcommand {
                subcommand::STOP_ALL_JOINTS => RequestClass::Stop,
                subcommand::GET_ACTUATOR_FEEDBACK
                | subcommand::GET_ARM_STATE
                | subcommand::CLEAR_ALL_FAULTS => RequestClass::Still,
                // SEND_ACTUATOR_COMMAND, and any subcommand this build does not know.
                _ => RequestClass::Motion { runs_to_end: false },
            },
            Request::Handshake { .. }
            | Request::GetSpeed
            | Request::SetSpeed { .. }
            | Request::SavePosition { .. }
            | Request::DeletePosition { .. }
            | Request::SetPolarPosition { .. }
            | Request::GetPolarPosition { .. }
            | Request::SetCartesianPosition { .. }
            | Request::GetCartesianPosition { .. } => RequestClass::Still,
        }
    }
}

/// Every request that stops a motion, in the order they are sent: cartesian, polar, then the
/// joints (hardware companion ICD STOP_ALL_JOINTS), keeping those `dialect` can carry. The ICD
/// dialect sends all three; the ack dialect (commands 0x0000-0x0004) only the polar STOP.
pub fn stop_requests(dialect: Dialect) -> Vec<Request> {
    [
        Request::CartesianMoveStop,
        Request::PolarPanStop,
        HwRequest::stop_all_joints_request(),
    ]
    .into_iter()
    .filter(|request| dialect.supports(request.command()))
    .collect()
}

/// Whether `request` may set the arm moving: its class is motion ([`Request::class`]).
pub fn may_move(request: &Request) -> bool {
    matches!(request.class(), RequestClass::Motion { .. })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::talos::hardware::ActuatorCommand;

    /// Command value, hardware subcommand (for 0x0008) and payload of each frame the set makes,
    /// from the Talos ICD (0x0007 cartesian STOP, 0x0004 polar STOP, 0x0008 hardware operation)
    /// and the hardware companion ICD (0x0004 STOP_ALL_JOINTS, no body).
    fn wire(requests: &[Request]) -> Vec<(u16, Vec<u8>)> {
        requests
            .iter()
            .map(|r| {
                let frame = r.to_frame(0).expect("frame");
                (frame.command, frame.payload)
            })
            .collect()
    }

    #[test]
    fn the_icd_set_is_cartesian_polar_and_every_joint() {
        assert_eq!(
            wire(&stop_requests(Dialect::Icd)),
            vec![
                (0x0007, vec![]),
                (0x0004, vec![]),
                // Subcommand 0x0004, RESERVED 0 (4 bytes), no hardware payload.
                (0x0008, vec![0x00, 0x04, 0, 0, 0, 0]),
            ]
        );
    }

    #[test]
    fn the_ack_set_is_what_the_dialect_carries() {
        assert_eq!(wire(&stop_requests(Dialect::Ack)), vec![(0x0004, vec![])]);
        for dialect in Dialect::ALL {
            assert!(
                stop_requests(dialect)
                    .iter()
                    .all(|r| dialect.supports(r.command()))
            );
        }
    }

    #[test]
    fn stops_and_reads_do_not_move_and_every_motion_does() {
        for stop in stop_requests(Dialect::Icd) {
            assert!(!may_move(&stop), "{stop:?}");
        }
        let jog = HwRequest::SendActuatorCommand {
            joint: 1,
            command: ActuatorCommand::jog(0.0, 1.0),
        };
        assert!(may_move(&jog.to_request().expect("jog")));
        assert!(may_move(&Request::Home { delay_ms: 0 }));
        assert!(may_move(&Request::GoToPosition { name: "a".into() }));
        assert!(may_move(&Request::PolarPanStart {
            moving_azimuth: 0,
            moving_altitude: 0
        }));
        assert!(!may_move(
            &HwRequest::GetArmState.to_request().expect("state")
        ));
        assert!(!may_move(&Request::SetSpeed { speed: 50 }));
    }
}
