//! The fence as the app keeps it: a telemetry sample and a held motion made into the fence's
//! terms ([`sample`], [`heading`]), and what the app last put on the wire for it ([`FenceWatch`]).
//! The rules themselves are `link::fence`'s.

use super::parts::Book;
use crate::console::arm_geometry::jog_direction;
use crate::console::jog::JogMotion;
use crate::kortex::gen3::signed_deg;
use crate::kortex::{Pose, ReferenceFrame, Telemetry};
use crate::link::fence::{Fence, KeepOut};
use std::sync::Arc;
use std::time::{Duration, Instant};

use crate::link::fence::{Heading, MIN_LOOKAHEAD_S, Sample, Verdict, WHOLE, kappa_ahead};
use crate::link::interface::{ArmCommand, StepMove};

/// The fence kept and what the app last did for it, so a sample that changes nothing sends
/// nothing; and the teaching in progress.
#[derive(Debug, Clone, PartialEq)]
pub struct FenceWatch {
    /// The fence kept now: the profile's, then as taught.
    pub kept: Option<Arc<Fence>>,
    /// A zone's first corner, marked (mm).
    pub corner: Option<[i64; 3]>,
    /// The last zone deleted and where it was, for undo.
    pub deleted: Option<(usize, KeepOut)>,
    /// Why the last taught fence is not in the file (held: written again with the next change).
    pub unwritten: Option<String>,
    /// The profile a fence taught without one goes to, once named.
    pub profile: Option<String>,
    /// The share in force on the wire, per mille.
    pub sent: u16,
    /// The held motion is stopped at the fence (a STOP went out for it).
    pub stopped: bool,
    /// The last verdict on the held motion, or on none (idle: where the tool is).
    pub verdict: Option<Verdict>,
    /// When the last sample came, and the time since the one before: the telemetry's period.
    pub sampled: Option<(Instant, Duration)>,
}

impl FenceWatch {
    pub fn new(kept: Option<Arc<Fence>>) -> FenceWatch {
        FenceWatch {
            kept,
            corner: None,
            deleted: None,
            unwritten: None,
            profile: None,
            sent: WHOLE,
            stopped: false,
            verdict: None,
            sampled: None,
        }
    }
}

/// Allowed for the link and the console between a sample and its stop on the wire, s.
const LATENCY_ALLOWANCE_S: f64 = 0.04;

impl FenceWatch {
    /// A sample came at `now`.
    pub fn on_sample(&mut self, now: Instant) {
        let period = self
            .sampled
            .map(|(at, _)| now.saturating_duration_since(at));
        let period = period.unwrap_or(Duration::from_millis(100));
        self.sampled = Some((now, period));
    }

    /// How far ahead a contact is called: a telemetry period and the latency allowance, within
    /// half a second (a slower telemetry is stale long before).
    pub fn lookahead_s(&self) -> f64 {
        let period = self.sampled.map_or(0.1, |(_, p)| p.as_secs_f64());
        (period + LATENCY_ALLOWANCE_S).clamp(MIN_LOOKAHEAD_S, 0.5)
    }

    /// The status bar's words for the fence, if it has any to say.
    pub fn text(&self) -> Option<String> {
        self.verdict.as_ref().and_then(|v| v.state.text())
    }
}

/// The joint angles of `t`, degrees in (-180, 180]; `None` if one is not a number.
fn joints_deg(t: &Telemetry) -> Option<[f64; 7]> {
    let q = t.joints.map(|j| f64::from(signed_deg(j.position)));
    q.iter().all(|a| a.is_finite()).then_some(q)
}

/// `t` in the fence's terms for `heading`; `None` when its pose or angles are not numbers.
pub fn sample(t: &Telemetry, heading: &Heading) -> Option<Sample> {
    let pose = t.tcp.pose;
    let tool_mm = [pose.x, pose.y, pose.z].map(|m| f64::from(m) * 1000.0);
    if !tool_mm.iter().all(|v| v.is_finite()) {
        return None;
    }
    let joints_deg = joints_deg(t)?;
    Some(Sample {
        tool_mm,
        joints_deg,
        joint_rates: t.joints.map(|j| f64::from(j.velocity)),
        kappa: kappa_ahead(&joints_deg, heading),
    })
}

/// Where `motion` takes the tool, from the angles in `t`. `base_frame`: a cartesian jog's axes
/// are the base frame's (else the tool's, turned into the base frame: no axis is taken out). The
/// direction is the arm view's arrow's ([`jog_direction`]).
pub fn heading(motion: JogMotion, t: &Telemetry, base_frame: bool) -> Option<Heading> {
    joints_deg(t)?;
    if let JogMotion::Cartesian { x, y, z } = motion
        && base_frame
    {
        return Some(Heading::Axes([x, y, z]));
    }
    let frame = (!base_frame).then_some(ReferenceFrame::Tool);
    let direction = jog_direction(motion, frame, &t.joints.map(|j| j.position));
    let joint = match motion {
        JogMotion::Joint { joint, direction } => {
            Some((usize::from(joint.clamp(1, 7) - 1), f64::from(direction)))
        }
        _ => None,
    };
    Some(Heading::Along {
        tool: direction.map_or([0.0; 3], |v| [v.x, v.y, v.z]),
        joint,
    })
}

/// No motion: only a tool already across the fence has anything to say.
pub const STILL: Heading = Heading::Along {
    tool: [0.0; 3],
    joint: None,
};

/// Below this the tool's reported speed is noise, not a direction, mm/s.
const MOVING_MM_S: f64 = 1.0;

/// A planned move (home, go-to, a stored run) as the telemetry shows it going: the tool's
/// direction, and its speed in mm/s.
pub fn going(t: &Telemetry) -> (Heading, f64) {
    let v = t.tcp.twist;
    let mm_s = [v.x, v.y, v.z].map(|m| f64::from(m) * 1000.0);
    let speed = mm_s.iter().map(|c| c * c).sum::<f64>().sqrt();
    if !speed.is_finite() || speed < MOVING_MM_S {
        return (STILL, 0.0);
    }
    let tool = unit(mm_s);
    (Heading::Along { tool, joint: None }, speed)
}

/// Why `command`'s target may not be gone to: outside the box, in a zone, or (a straight move)
/// through one. Home and stored runs are the arm's to plan: watched, not refused.
pub fn target_refusal(
    fence: &Fence,
    t: &Telemetry,
    command: &ArmCommand,
    book: &Book,
) -> Option<String> {
    let mm = |p: Pose| [p.x, p.y, p.z].map(|m| f64::from(m) * 1000.0);
    let from = mm(t.tcp.pose);
    let (target, straight) = match command {
        ArmCommand::Step(step) => (
            mm(step.target(t.tcp.pose)),
            matches!(step, StepMove::Cartesian { .. }),
        ),
        ArmCommand::MoveToPose(pose) => (mm(*pose), true),
        ArmCommand::GoToPosition { name } => {
            let entry = book.positions().get(name)?;
            if entry.anchor {
                return None;
            }
            (
                entry.cartesian?.map(|tenths| f64::from(tenths) / 10.0),
                false,
            )
        }
        _ => return None,
    };
    if !target.iter().chain(&from).all(|v| v.is_finite()) {
        return Some("the fence cannot place the tool (telemetry not a number)".into());
    }
    if let Some(why) = fence.refuse_target(target) {
        return Some(format!("the target is outside the fence: {why}"));
    }
    let zone = fence.refuse_path(from, target).filter(|_| straight)?;
    Some(format!("the straight path crosses {zone}"))
}

fn unit(v: [f64; 3]) -> [f64; 3] {
    let n = v.iter().map(|c| c * c).sum::<f64>().sqrt();
    if n > 1e-12 && n.is_finite() {
        v.map(|c| c / n)
    } else {
        [0.0; 3]
    }
}

/// The held motion with the axes the fence took out.
pub fn shaped(motion: JogMotion, verdict: &Verdict) -> JogMotion {
    match motion {
        JogMotion::Cartesian { .. } if verdict.axes != [0; 3] => {
            let [x, y, z] = verdict.axes;
            JogMotion::Cartesian { x, y, z }
        }
        other => other,
    }
}

/// The verdict's share per mille.
pub fn permille(verdict: &Verdict) -> u16 {
    (verdict.factor.clamp(0.0, 1.0) * f64::from(WHOLE)).round() as u16
}
