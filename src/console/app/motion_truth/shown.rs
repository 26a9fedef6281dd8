//! What the status bar says about motion, from the evidence kept.

use std::time::Instant;

use super::{MotionShown, STOP_GRACE, TruthView};
use crate::console::app::App;
use crate::console::app::age::age_text;
use crate::link::interface::LinkStatus;

impl App {
    /// The truth's part of the view: the motion shown and the ages that make things stale.
    pub(in crate::console::app) fn truth_view(&self) -> TruthView {
        TruthView {
            motion: self.motion_shown(),
            link_stale: self.link_stale(),
            telemetry_source: self.telemetry_source(),
            telemetry_stale: self.telemetry_stale(),
            cap_watched: self.cap_watched(),
        }
    }

    /// What the status bar says about motion, by precedence: a jog, a tracked action, a STOP
    /// being confirmed, any doubt, idle.
    pub fn motion_shown(&self) -> MotionShown {
        if let Some(motion) = self.keys.jog().active() {
            return MotionShown::Jog(motion);
        }
        let truth = &self.truth;
        if let Some(action) = &truth.action {
            return MotionShown::Action {
                label: action.kind.label(),
                confirmed: truth.expects_telemetry(),
            };
        }
        let Some(now) = self.now else {
            return MotionShown::Idle;
        };
        if let Some(reason) = &truth.stop_failure {
            return MotionShown::MayBeMoving(format!("stop not confirmed: {reason}"));
        }
        if truth.unsettled {
            match self.arm.link() {
                LinkStatus::Up { .. } => {}
                _ => return MotionShown::MayBeMoving("link lost after motion".into()),
            }
            if let Some(age) = self.link_stale() {
                return MotionShown::MayBeMoving(format!(
                    "no word from the arm for {}",
                    age_text(age)
                ));
            }
        }
        let within = |at: Option<Instant>| at.is_some_and(|at| now < at + STOP_GRACE);
        if within(truth.stop_sent) || (truth.unsettled && within(truth.stop_confirmed_at)) {
            return MotionShown::Stopping;
        }
        let telemetry_fresh = self.telemetry_stale().is_none() && truth.telemetry_at.is_some();
        if telemetry_fresh && self.moved_by_another_client() {
            return MotionShown::MovedByAnotherClient;
        }
        if telemetry_fresh && truth.telemetry_moving {
            return MotionShown::MayBeMoving("telemetry shows motion".into());
        }
        if truth.stop_sent.is_some() {
            return MotionShown::MayBeMoving("stop not acknowledged".into());
        }
        if truth.unsettled {
            let why = if truth.stop_confirmed_at.is_some() {
                "no telemetry at rest since the stop"
            } else {
                "motion not shown to have ended: press stop"
            };
            return MotionShown::MayBeMoving(why.into());
        }
        MotionShown::Idle
    }
}
