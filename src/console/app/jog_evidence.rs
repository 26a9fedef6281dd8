//! What one sample says about the held jog; `other_client` acts on it.

use crate::console::coords::describe_motion;
use crate::console::jog::JogMotion;
use crate::kortex::Telemetry;
use crate::kortex::arm_state::{REST_LINEAR_M_S, at_rest};

/// Idle, a tool point faster than this (m/s) is commanded motion: 5x the at-rest threshold.
pub const OTHER_MOTION_M_S: f32 = 5.0 * REST_LINEAR_M_S;
/// Idle, a joint faster than this (deg/s) is commanded motion (a tool turn moves joints).
pub const OTHER_MOTION_JOINT_DEG_S: f32 = 2.0;
/// Under this fraction of its steady speed a jog is far slower (a Gen3 tracks within a few %).
pub const SLOW_FRACTION: f64 = 0.5;
/// Under this fraction of its speed along our direction (over 60° off), the tool goes elsewhere.
pub const ALONG_FRACTION: f64 = 0.5;

/// How a sample contradicts the jog we hold.
#[derive(Debug, Clone, PartialEq)]
pub enum Contradiction {
    /// The arm at rest.
    AtRest,
    /// Running at `seen`, under [`SLOW_FRACTION`] of the `steady` speed it ran (mm/s or deg/s).
    Slow {
        seen: f64,
        steady: f64,
        unit: &'static str,
    },
    /// The tool moving fast in another direction: `seen` in words (`+Z`).
    Elsewhere { seen: String },
}

impl Contradiction {
    /// Why the console stops, after `stopped by another client: `.
    pub fn words(&self, motion: JogMotion) -> String {
        let ours = describe_motion(motion);
        match self {
            Contradiction::AtRest => format!("the arm is at rest while we jog {ours}"),
            Contradiction::Slow { seen, steady, unit } => format!(
                "the arm runs at {seen:.0} {unit}, not the {steady:.0} {unit} of our {ours} jog"
            ),
            Contradiction::Elsewhere { seen } => {
                format!("the arm moves {seen}, not our {ours}")
            }
        }
    }
}

/// The jog's progress in `t`: the speed along our direction (cartesian base frame, mm/s), else of
/// what the jog moves (tool point mm/s, rotation or joint deg/s). NaN: `None`.
pub fn progress(t: &Telemetry, motion: JogMotion, base_frame: bool) -> Option<(f64, &'static str)> {
    let v = t.tcp.twist;
    let linear = [v.x, v.y, v.z].map(f64::from);
    let norm = |c: [f64; 3]| c.iter().map(|x| x * x).sum::<f64>().sqrt();
    let value = match motion {
        JogMotion::Cartesian { x, y, z } if base_frame => {
            let d = [x, y, z].map(f64::from);
            let along: f64 = (0..3).map(|i| linear[i] * d[i]).sum::<f64>() / norm(d);
            (along * 1000.0, "mm/s")
        }
        JogMotion::Cartesian { .. } | JogMotion::Polar { .. } => (norm(linear) * 1000.0, "mm/s"),
        JogMotion::Orientation { .. } => {
            let angular = [v.theta_x, v.theta_y, v.theta_z].map(f64::from);
            (norm(angular), "deg/s")
        }
        JogMotion::Joint { joint, .. } => {
            let index = usize::from(joint.saturating_sub(1));
            let rate = t.joints.get(index).map(|j| f64::from(j.velocity).abs())?;
            (rate, "deg/s")
        }
    };
    value.0.is_finite().then_some(value)
}

/// The tool moving fast with under [`ALONG_FRACTION`] of its speed along our direction: where it
/// goes, in words. Only for a cartesian jog in the base frame, the frame of the twist.
pub fn off_our_direction(t: &Telemetry, motion: JogMotion, base_frame: bool) -> Option<String> {
    let JogMotion::Cartesian { .. } = motion else {
        return None;
    };
    if !base_frame {
        return None;
    }
    let v = t.tcp.twist;
    let linear = [v.x, v.y, v.z].map(f64::from);
    let speed = linear.iter().map(|x| x * x).sum::<f64>().sqrt();
    if !speed.is_finite() || speed <= f64::from(OTHER_MOTION_M_S) {
        return None;
    }
    let (along, _) = progress(t, motion, true)?;
    if along / 1000.0 >= ALONG_FRACTION * speed {
        return None;
    }
    // The axes that carry a third of the speed or more, as a jog would be named.
    let sign = |c: f64| -> i8 {
        match c {
            c if c >= speed / 3.0 => 1,
            c if c <= -speed / 3.0 => -1,
            _ => 0,
        }
    };
    let seen = JogMotion::Cartesian {
        x: sign(linear[0]),
        y: sign(linear[1]),
        z: sign(linear[2]),
    };
    Some(describe_motion(seen))
}

/// How `t` contradicts `motion`, given its `steady` progress and whether rest is telling.
pub fn contradiction(
    t: &Telemetry,
    motion: JogMotion,
    base_frame: bool,
    steady: Option<f64>,
    rest_telling: bool,
) -> Option<Contradiction> {
    if rest_telling && at_rest(t) {
        return Some(Contradiction::AtRest);
    }
    if let Some(seen) = off_our_direction(t, motion, base_frame) {
        return Some(Contradiction::Elsewhere { seen });
    }
    let (seen, unit) = progress(t, motion, base_frame)?;
    let steady = steady.filter(|_| rest_telling)?;
    (seen < SLOW_FRACTION * steady).then_some(Contradiction::Slow { seen, steady, unit })
}
