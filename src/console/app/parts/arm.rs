//! What the driver says about the link and the arm, and what the console keeps of it.

use std::time::{Duration, Instant};

use super::super::cap_watch::CapWatch;
use super::super::history::{History, HistorySeries};
use super::super::limits::{NearLimit, near_limits};
use super::super::other_client::OtherClients;
use super::super::singularity::near_singularity;
use super::super::trail::{ToolTrail, TrailShade};
use crate::kortex::{Coded, ReferenceFrame, RobotState, Telemetry};
use crate::link::interface::{GuardStatus, LinkStatus};

/// Why the arm's own report forbids motion, in the words after `the arm reports`, or `None`.
pub fn arm_refusal(t: &Telemetry) -> Option<String> {
    if !t.faults.is_empty() {
        return Some(t.faults.names().join(", "));
    }
    match t.robot_state {
        Coded::Known(
            RobotState::Ready | RobotState::ControlledBySequence | RobotState::ControlledManually,
        ) => {}
        Coded::Known(RobotState::InFault) => return Some("in_fault".into()),
        state => return Some(format!("state {state}, not ready")),
    }
    // The panels' own test of what is physically possible: what shows as `?` never moves.
    t.insane_fields()
        .first()
        .map(|field| format!("nonsense: {field}"))
}

#[derive(Debug, Clone)]
pub(in crate::console::app) struct Arm {
    link: LinkStatus,
    telemetry: Option<Telemetry>,
    /// [`near_singularity`], worked out when the joints move (an SVD), not per view.
    singularity: Option<f64>,
    /// [`arm_refusal`], worked out per report rather than by the gate after every input.
    refusal: Option<String>,
    latency: Option<Duration>,
    speed: Option<u8>,
    frame: ReferenceFrame,
    /// The stop guard's state, once the driver says one is required (a real arm).
    guard: Option<GuardStatus>,
    /// The last 30 s of telemetry, for the history panel.
    history: History,
    /// The tool point's recent path, for the arm view.
    trail: ToolTrail,
    /// The speed cap as the telemetry shows it kept.
    cap_watch: CapWatch,
    /// Other clients on the same arm: their stops and motions (see `other_client`).
    others: OtherClients,
}

/// What the arm's panels show of it, worked out once per frame.
#[derive(Debug, Clone, PartialEq)]
pub struct ArmView {
    pub link: LinkStatus,
    pub latency: Option<Duration>,
    pub guard: Option<GuardStatus>,
    pub speed: Option<u8>,
    pub frame: ReferenceFrame,
    pub telemetry: Option<Telemetry>,
    pub history: HistorySeries,
    /// Limited joints within 5 degrees of a limit, the nearest first.
    pub near_limits: Vec<NearLimit>,
    /// The Jacobian's estimated condition number when above the warning; else `None`.
    pub near_singularity: Option<f64>,
    /// The arm view's trail (base frame, m), oldest first.
    pub trail: Vec<(TrailShade, [f64; 3])>,
    /// What the fence says (`SLOWED: table 34 mm`, `AT FENCE: table`), the app's to fill.
    pub fence: Option<String>,
    /// The fence's barrier nearest the tool sphere and its clearance (mm), the app's to fill.
    pub fence_nearest: Option<(String, f64)>,
    /// The fence screen's rows and state while it is open, the app's to fill.
    pub fence_screen: Option<FenceScreenView>,
}

/// What the fence screen shows besides its selection.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FenceScreenView {
    pub rows: Vec<super::super::FenceRow>,
    /// A zone's first corner, marked (mm).
    pub corner: Option<[i64; 3]>,
    /// Why the fence taught last is not in the file.
    pub unwritten: Option<String>,
}

impl Default for Arm {
    fn default() -> Arm {
        Arm {
            link: LinkStatus::Connecting,
            telemetry: None,
            singularity: None,
            refusal: None,
            latency: None,
            speed: None,
            frame: ReferenceFrame::Base,
            guard: None,
            history: History::default(),
            trail: ToolTrail::default(),
            cap_watch: CapWatch::default(),
            others: OtherClients::default(),
        }
    }
}

impl Arm {
    pub(in crate::console::app) fn link(&self) -> &LinkStatus {
        &self.link
    }

    /// Up, as the driver last said (stale or not: see the motion truth).
    pub(in crate::console::app) fn link_up(&self) -> bool {
        matches!(self.link, LinkStatus::Up { .. })
    }

    /// The driver's link status; whether the link has just come up.
    pub(in crate::console::app) fn on_link(&mut self, status: LinkStatus) -> bool {
        let came_up = matches!(status, LinkStatus::Up { .. }) && !self.link_up();
        self.link = status;
        came_up
    }

    pub(in crate::console::app) fn telemetry(&self) -> Option<&Telemetry> {
        self.telemetry.as_ref()
    }

    /// A telemetry sample into the history, the trail and the panels.
    pub(in crate::console::app) fn on_telemetry(&mut self, t: Telemetry, now: Instant) {
        self.history.record(&t, now);
        self.trail.record(&t, now);
        let angles = |t: &Telemetry| t.joints.map(|j| j.position.to_bits());
        if self
            .telemetry
            .as_ref()
            .is_none_or(|was| angles(was) != angles(&t))
        {
            self.singularity = near_singularity(&t);
        }
        self.refusal = arm_refusal(&t);
        self.telemetry = Some(t);
    }

    /// Why the last report forbids motion ([`arm_refusal`]), or `None`: also with no report.
    pub(in crate::console::app) fn refusal(&self) -> Option<&str> {
        self.refusal.as_deref()
    }

    pub(in crate::console::app) fn on_latency(&mut self, latency: Duration) {
        self.latency = Some(latency);
    }

    pub(in crate::console::app) fn speed(&self) -> Option<u8> {
        self.speed
    }

    /// The speed the arm says; whether it changed from one it had said.
    pub(in crate::console::app) fn on_speed(&mut self, speed: u8) -> bool {
        let changed = self.speed.is_some_and(|s| s != speed);
        self.speed = Some(speed);
        changed
    }

    pub(in crate::console::app) fn frame(&self) -> ReferenceFrame {
        self.frame
    }

    /// The next reference frame: base, tool, mixed, base again.
    pub(in crate::console::app) fn on_frame_cycle(&mut self) -> ReferenceFrame {
        self.frame = match self.frame {
            ReferenceFrame::Base => ReferenceFrame::Tool,
            ReferenceFrame::Tool => ReferenceFrame::Mixed,
            ReferenceFrame::Mixed => ReferenceFrame::Base,
        };
        self.frame
    }

    pub(in crate::console::app) fn guard(&self) -> Option<&GuardStatus> {
        self.guard.as_ref()
    }

    pub(in crate::console::app) fn guard_ready(&self) -> bool {
        matches!(self.guard, Some(GuardStatus::Ready { .. }))
    }

    pub(in crate::console::app) fn on_guard(&mut self, status: GuardStatus) {
        self.guard = Some(status);
    }

    pub(in crate::console::app) fn history(&self) -> &History {
        &self.history
    }

    pub(in crate::console::app) fn on_history_cycle(&mut self) {
        self.history.cycle_quantity();
    }

    pub(in crate::console::app) fn trail(&self) -> &ToolTrail {
        &self.trail
    }

    pub(in crate::console::app) fn cap_watch(&self) -> &CapWatch {
        &self.cap_watch
    }

    /// A sample under our motion, `over` the cap or not: the stop's text per `cap_watch`.
    pub(in crate::console::app) fn on_cap_sample(
        &mut self,
        over: Option<String>,
    ) -> Option<String> {
        self.cap_watch.sample(over)
    }

    /// No motion of the console's runs: a run of over-cap samples starts again.
    pub(in crate::console::app) fn on_cap_idle(&mut self) {
        self.cap_watch.sample(None);
    }

    pub(in crate::console::app) fn others(&self) -> &OtherClients {
        &self.others
    }

    /// Other clients' watch, to feed it (it keeps its own state: see `other_client`).
    pub(in crate::console::app) fn others_mut(&mut self) -> &mut OtherClients {
        &mut self.others
    }

    /// What the panels show; `now` is the latest input's (ages are drawn against it).
    pub(in crate::console::app) fn view(&self, now: Option<Instant>) -> ArmView {
        ArmView {
            link: self.link.clone(),
            latency: self.latency,
            guard: self.guard.clone(),
            speed: self.speed,
            frame: self.frame,
            telemetry: self.telemetry.clone(),
            history: now.map(|now| self.history.series(now)).unwrap_or_default(),
            near_limits: self.telemetry.as_ref().map(near_limits).unwrap_or_default(),
            near_singularity: self.singularity,
            trail: now.map(|now| self.trail.shaded(now)).unwrap_or_default(),
            fence: None,
            fence_nearest: None,
            fence_screen: None,
        }
    }
}
