//! Joints close to their limits, for the status bar and the joints gauge. The Gen3 reports 0 to 360
//! and limits are symmetric about 0, so the margin is taken on the angle folded into (-180, 180];
//! continuous joints have none.

use crate::kortex::Telemetry;
use crate::kortex::gen3::limit_margin;

/// Within this many degrees of a limit a joint is named and its gauge warns.
pub const LIMIT_WARNING_DEG: f32 = 5.0;

/// A limited joint within [`LIMIT_WARNING_DEG`] of its limit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NearLimit {
    /// 1 to 7.
    pub joint: u8,
    /// Degrees left before the limit (0 or less: at or past it).
    pub margin_deg: f32,
}

impl NearLimit {
    /// `J4 2.1° from limit`, or `J4 at limit`.
    pub fn text(&self) -> String {
        if self.margin_deg <= 0.05 {
            format!("J{} at limit", self.joint)
        } else {
            format!("J{} {:.1}° from limit", self.joint, self.margin_deg)
        }
    }
}

/// The limited joints within [`LIMIT_WARNING_DEG`] of a limit, the nearest first.
pub fn near_limits(t: &Telemetry) -> Vec<NearLimit> {
    let mut near: Vec<NearLimit> = t
        .joints
        .iter()
        .enumerate()
        .filter_map(|(i, j)| {
            let margin_deg = limit_margin(i, j.position)?;
            (margin_deg < LIMIT_WARNING_DEG).then_some(NearLimit {
                joint: i as u8 + 1,
                margin_deg,
            })
        })
        .collect();
    near.sort_by(|a, b| a.margin_deg.total_cmp(&b.margin_deg));
    near
}
