//! The speed cap, watched: a motion the console started that telemetry shows more than
//! [`CAP_TOLERANCE`] over the cap for [`OVER_CAP_SAMPLES`] samples in a row is stopped, held keys
//! latched, and the message line and audit say why. The tolerance absorbs tracking overshoot and
//! noise; the run of samples, one sample's spike.
//!
//! The tool's linear speed (a joint jog: the joint rate) is compared with the cap at 100 %, not the
//! cap scaled by the speed in force: the cap is the safety rule, and the speed in force changes
//! while the arm decelerates. Without telemetry nothing is watched (the status bar says so).
//! Applied per sample by `App::watch_cap` in `arm.rs`.

use crate::console::jog::JogMotion;
use crate::kortex::Telemetry;

/// How far over the cap a sample may be before it counts as over (a factor): 10 %.
pub const CAP_TOLERANCE: f64 = 1.1;
/// Over-cap samples in a row that stop the motion: two may be a spike, the third is not.
pub const OVER_CAP_SAMPLES: u32 = 3;

/// The watch's state: the run of over-cap samples, and the stops it made.
#[derive(Debug, Clone, Default)]
pub struct CapWatch {
    over_in_a_row: u32,
    stops: u64,
    last_stop: Option<String>,
}

impl CapWatch {
    /// A sample `over` the cap (in words) or not: the stop's text after [`OVER_CAP_SAMPLES`] over.
    pub(super) fn sample(&mut self, over: Option<String>) -> Option<String> {
        let Some(why) = over else {
            self.over_in_a_row = 0;
            return None;
        };
        self.over_in_a_row += 1;
        if self.over_in_a_row < OVER_CAP_SAMPLES {
            return None;
        }
        self.over_in_a_row = 0;
        let text = format!("stopped: {why}");
        self.stops += 1;
        self.last_stop = Some(text.clone());
        Some(text)
    }

    /// How many motions the watch stopped and why the last, for the audit.
    pub fn stops(&self) -> (u64, Option<&str>) {
        (self.stops, self.last_stop.as_deref())
    }
}

/// What a telemetry sample shows over its bound, in words, or `None` within it.
pub(super) fn over_cap(
    t: &Telemetry,
    jog: Option<JogMotion>,
    cap_mm_s: f64,
    joint_deg_s: f64,
) -> Option<String> {
    let twist = &t.tcp.twist;
    let tool_mm_s = [twist.x, twist.y, twist.z]
        .map(f64::from)
        .iter()
        .map(|v| v * v)
        .sum::<f64>()
        .sqrt()
        * 1000.0;
    // A reading that is not a number says nothing either way.
    if tool_mm_s.is_finite() && tool_mm_s > cap_mm_s * CAP_TOLERANCE {
        return Some(format!(
            "tool at {tool_mm_s:.0} mm/s, over the {cap_mm_s:.0} mm/s cap; is --operator-full-speed right?"
        ));
    }
    if matches!(jog, Some(JogMotion::Joint { .. })) {
        let fastest = t
            .joints
            .iter()
            .enumerate()
            .map(|(i, j)| (i + 1, f64::from(j.velocity).abs()))
            .filter(|(_, rate)| rate.is_finite())
            .max_by(|a, b| a.1.total_cmp(&b.1));
        if let Some((joint, rate)) = fastest
            && rate > joint_deg_s * CAP_TOLERANCE
        {
            return Some(format!(
                "J{joint} at {rate:.0} deg/s, over the {joint_deg_s:.0} deg/s joint jog speed"
            ));
        }
    }
    None
}
