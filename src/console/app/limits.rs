//! Joints close to their limits, for the status bar and the joints gauge. The Gen3 reports 0 to 360
//! and limits are symmetric about 0, so the margin is taken on the angle folded into (-180, 180];
//! continuous joints have none.

use crate::kortex::Telemetry;
use crate::kortex::gen3::JOINT_LIMITS_DEG;

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

/// A reported angle folded into (-180, 180].
fn signed(deg: f32) -> f32 {
    let wrapped = deg.rem_euclid(360.0);
    if wrapped > 180.0 {
        wrapped - 360.0
    } else {
        wrapped
    }
}

/// Joint `joint`'s (1-7) margin to its nearer limit, deg; `None` if continuous or not finite.
pub fn limit_margin(joint: usize, position_deg: f32) -> Option<f32> {
    let limit = JOINT_LIMITS_DEG
        .get(joint.checked_sub(1)?)
        .copied()
        .flatten()? as f32;
    position_deg
        .is_finite()
        .then(|| limit - signed(position_deg).abs())
}

/// The limited joints within [`LIMIT_WARNING_DEG`] of a limit, the nearest first.
pub fn near_limits(t: &Telemetry) -> Vec<NearLimit> {
    let mut near: Vec<NearLimit> = t
        .joints
        .iter()
        .enumerate()
        .filter_map(|(i, j)| {
            let margin_deg = limit_margin(i + 1, j.position)?;
            (margin_deg < LIMIT_WARNING_DEG).then_some(NearLimit {
                joint: i as u8 + 1,
                margin_deg,
            })
        })
        .collect();
    near.sort_by(|a, b| a.margin_deg.total_cmp(&b.margin_deg));
    near
}
