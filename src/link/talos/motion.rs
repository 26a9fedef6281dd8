//! What a dropped or failed link owes the arm: the whole stop set once anything that may move
//! it went out with no full stop set since.

use crate::talos::{Dialect, Request, may_move, stop_requests};

/// Whether anything that may move the arm went out since the last full stop set: what a
/// dropped or failed link must stop.
#[derive(Debug)]
pub(super) struct MotionSinceStop {
    /// The dialect's stop set ([`stop_requests`]).
    stops: Vec<Request>,
    /// Which of `stops` went out since the last motion.
    stopped: Vec<bool>,
    moving: bool,
}

impl MotionSinceStop {
    pub(super) fn new(dialect: Dialect) -> MotionSinceStop {
        let stops = stop_requests(dialect);
        MotionSinceStop {
            stopped: vec![false; stops.len()],
            stops,
            moving: false,
        }
    }

    pub(super) fn note(&mut self, request: &Request) {
        if may_move(request) {
            self.moving = true;
            self.stopped.fill(false);
        } else if let Some(i) = self.stops.iter().position(|stop| stop == request) {
            self.stopped[i] = true;
            if self.stopped.iter().all(|s| *s) {
                self.moving = false;
            }
        }
    }

    /// The whole stop set if anything may be moving, else nothing.
    pub(super) fn owed(&self) -> &[Request] {
        if self.moving { &self.stops } else { &[] }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::talos::hardware::{ActuatorCommand, HwRequest};

    #[test]
    fn a_joint_jog_is_owed_the_whole_set_until_every_stop_of_it_went_out() {
        let mut motion = MotionSinceStop::new(Dialect::Icd);
        assert!(motion.owed().is_empty(), "nothing moved yet");
        let jog = HwRequest::SendActuatorCommand {
            joint: 2,
            command: ActuatorCommand::jog(10.0, 5.0),
        };
        motion.note(&jog.to_request().expect("jog"));
        assert_eq!(motion.owed(), stop_requests(Dialect::Icd).as_slice());
        motion.note(&Request::CartesianMoveStop);
        motion.note(&Request::PolarPanStop);
        assert_eq!(motion.owed().len(), 3, "the joints are not stopped yet");
        motion.note(&HwRequest::stop_all_joints_request());
        assert!(motion.owed().is_empty());
        // A motion after a partial stop starts the count again.
        motion.note(&Request::Home { delay_ms: 0 });
        motion.note(&Request::CartesianMoveStop);
        motion.note(&Request::PolarPanStop);
        motion.note(&Request::Home { delay_ms: 0 });
        motion.note(&HwRequest::stop_all_joints_request());
        assert_eq!(motion.owed().len(), 3);
    }
}
