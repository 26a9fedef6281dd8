//! Which client holds the running continuous motion, so its connection closing stops it (the
//! hardware ICD's SHALL for joints; for START, a hold-to-run motion whose holder is gone must not
//! wait for the watchdog). Only the client that last started or refreshed it: a console's jog
//! survives an `armjog send` beside it.

use super::Operator;
use crate::sim::arm_model::Arm;
use crate::talos::{Reply, Request};

/// A Talos client connection, numbered by the server in accept order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ClientId(pub u64);

impl Operator {
    /// [`Operator::handle`] for `client`, noting whether it (re)armed a continuous motion.
    pub fn handle_from(&mut self, client: ClientId, arm: &mut Arm, request: Request) -> Reply {
        let before = arm.watchdog_deadline();
        let reply = self.handle(arm, request);
        match arm.watchdog_deadline() {
            None => self.holder = None,
            Some(after) if Some(after) != before => self.holder = Some(client),
            Some(_) => {}
        }
        reply
    }

    /// `client`'s connection closed: stops the continuous motion it holds and says whether it did.
    /// Discrete moves run on (`armjog send home` closes right after sending).
    pub fn client_gone(&mut self, client: ClientId, arm: &mut Arm) -> bool {
        if self.holder != Some(client) {
            return false;
        }
        self.holder = None;
        if arm.watchdog_deadline().is_none() {
            return false;
        }
        arm.stop();
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::talos::ReturnCode;
    use crate::talos::hardware::{self, ActuatorCommand, HwRequest};

    const A: ClientId = ClientId(1);
    const B: ClientId = ClientId(2);

    fn jog(joint: u8, velocity: f32) -> Request {
        let hw = HwRequest::SendActuatorCommand {
            joint,
            command: ActuatorCommand::jog(0.0, velocity),
        };
        Request::HardwareOperation {
            subcommand: hw.subcommand(),
            reserved: 0,
            payload: hw.encode_payload().unwrap(),
        }
    }

    fn ok(reply: &Reply) -> bool {
        reply.return_code() == ReturnCode::OK
    }

    #[test]
    fn a_joint_jog_stops_when_its_client_goes_and_not_when_another_does() {
        let (mut op, mut arm) = (Operator::default(), Arm::default());
        assert!(ok(&op.handle_from(A, &mut arm, jog(1, 10.0))));
        arm.advance(0.05);
        assert!(!op.client_gone(B, &mut arm), "B holds nothing");
        assert!(!arm.motion().is_idle(), "A's jog runs on after B left");
        assert!(op.client_gone(A, &mut arm));
        assert!(arm.motion().is_idle() && !arm.is_moving());
        assert!(!op.client_gone(A, &mut arm), "nothing left to stop");
    }

    #[test]
    fn continuous_starts_stop_with_their_client() {
        let (mut op, mut arm) = (Operator::default(), Arm::default());
        let start = Request::CartesianMoveStart {
            moving_x: 1,
            moving_y: 0,
            moving_z: 0,
        };
        assert!(ok(&op.handle_from(A, &mut arm, start)));
        arm.advance(0.05);
        assert!(op.client_gone(A, &mut arm));
        assert!(arm.motion().is_idle());
        let pan = Request::PolarPanStart {
            moving_azimuth: 1,
            moving_altitude: 0,
        };
        assert!(ok(&op.handle_from(B, &mut arm, pan)));
        assert!(op.client_gone(B, &mut arm));
        assert!(arm.motion().is_idle());
    }

    #[test]
    fn the_client_that_refreshed_last_holds_the_motion() {
        let (mut op, mut arm) = (Operator::default(), Arm::default());
        op.handle_from(A, &mut arm, jog(2, 5.0));
        arm.advance(0.01);
        op.handle_from(B, &mut arm, jog(2, 5.0));
        arm.advance(0.01);
        assert!(!op.client_gone(A, &mut arm), "B refreshed it last");
        assert!(!arm.motion().is_idle());
        // A query from A changes nothing about who holds it.
        op.handle_from(A, &mut arm, Request::GetSpeed);
        assert!(op.client_gone(B, &mut arm));
        assert!(arm.motion().is_idle());
    }

    #[test]
    fn discrete_moves_and_stops_are_not_held() {
        let (mut op, mut arm) = (Operator::default(), Arm::default());
        op.handle_from(A, &mut arm, jog(1, 10.0));
        // B replaces A's jog with a home: A leaving must not stop B's move.
        op.handle_from(B, &mut arm, Request::Home { delay_ms: 0 });
        assert!(!arm.motion().is_idle(), "home runs");
        assert!(!op.client_gone(A, &mut arm));
        assert!(
            !op.client_gone(B, &mut arm),
            "a discrete move outlives its client"
        );
        assert!(!arm.motion().is_idle());
        // A refused jog does not make its sender the holder of the running jog.
        op.handle_from(A, &mut arm, Request::CartesianMoveStop);
        op.handle_from(A, &mut arm, jog(1, 10.0));
        let Request::HardwareOperation { mut payload, .. } = jog(1, 10.0) else {
            unreachable!()
        };
        payload[0] = 8; // no joint 8: MALFORMED_PAYLOAD
        let joint_8 = Request::HardwareOperation {
            subcommand: hardware::subcommand::SEND_ACTUATOR_COMMAND,
            reserved: 0,
            payload,
        };
        let refused = op.handle_from(B, &mut arm, joint_8);
        assert!(!ok(&refused));
        assert!(!op.client_gone(B, &mut arm));
        assert!(op.client_gone(A, &mut arm));
    }
}
