//! The fence: a box the tool stays in, named keep-out zones, soft joint limits and a singularity
//! slow-down, per arm (its profile's `[arms.NAME.fence]`). Pure: [`Fence::judge`] takes one
//! telemetry sample and the motion held and says how fast, along which axes, or not at all. What it
//! keeps is the sphere of `tool_radius` about the tool point, nothing of the arm's links.

mod geometry;
mod judge;

pub use geometry::{Aabb, Barrier, FACE_NAMES};
pub use judge::{FenceState, Heading, MIN_LOOKAHEAD_S, Pace, Sample, Verdict, kappa_ahead};

use crate::kortex::gen3::JOINT_LIMITS_DEG;

/// The fence's share of the speed when it takes none, per mille (`ArmCommand::FenceSpeed`).
pub const WHOLE: u16 = 1000;
/// The slowest a motion toward a face goes before contact: this fraction of the technician's speed.
pub const SLOWEST: f64 = 0.1;
/// A joint jog slows over this many degrees before a soft limit.
pub const JOINT_SLOW_BAND_DEG: f64 = 10.0;

/// A named box the tool sphere must stay out of, mm in the base frame.
#[derive(Debug, Clone, PartialEq)]
pub struct KeepOut {
    pub name: String,
    pub zone: Aabb,
    pub enabled: bool,
}

/// κ from which cartesian speed falls, and at which it is zero (MoveIt Servo's defaults).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Singularity {
    pub slow: f64,
    pub stop: f64,
}

impl Default for Singularity {
    fn default() -> Singularity {
        Singularity {
            slow: 17.0,
            stop: 30.0,
        }
    }
}

/// One arm's fence. Every part is optional; [`Fence::check`] says what cannot be one.
#[derive(Debug, Clone, PartialEq)]
pub struct Fence {
    /// The box the tool sphere stays in, mm, base frame.
    pub inside: Option<Aabb>,
    /// The sphere about the tool point that must stay clear, mm.
    pub tool_radius: f64,
    /// Toward a face, speed falls linearly to [`SLOWEST`] over this distance, mm.
    pub slow_zone: f64,
    /// Soft limits per joint (J1..J7), degrees in (-180, 180], inside the arm's own.
    pub joints: [Option<[f64; 2]>; 7],
    pub singularity: Singularity,
    pub keep_out: Vec<KeepOut>,
}

impl Default for Fence {
    fn default() -> Fence {
        Fence {
            inside: None,
            tool_radius: 0.0,
            slow_zone: 60.0,
            joints: [None; 7],
            singularity: Singularity::default(),
            keep_out: Vec::new(),
        }
    }
}

/// What makes a fence unusable, naming the key as the profile spells it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FenceError {
    #[error("{key}: {value} is not a finite number")]
    NotFinite { key: String, value: f64 },
    #[error("{key}: min {min} is not below max {max} on {axis}")]
    MinNotBelowMax {
        key: String,
        axis: &'static str,
        min: f64,
        max: f64,
    },
    #[error("{key}: {value} is negative")]
    Negative { key: String, value: f64 },
    #[error("{key}: the arm has joints j1 to j7")]
    UnknownJoint { key: String },
    #[error("{key}: [{min}, {max}] is outside the arm's own limits of ±{limit}°")]
    OutsideArmLimit {
        key: String,
        min: f64,
        max: f64,
        limit: f64,
    },
    #[error("{key}: slow {slow} must be at least 1 and below stop {stop}")]
    SingularityOrder { key: String, slow: f64, stop: f64 },
    #[error("{key}: a zone needs a name")]
    Unnamed { key: String },
    #[error("{key}: a second zone named '{name}'")]
    DuplicateName { key: String, name: String },
}

impl FenceError {
    /// The key the error is about, dotted as in the profile (`keep_out[2].min`).
    pub fn key(&self) -> &str {
        match self {
            FenceError::NotFinite { key, .. }
            | FenceError::MinNotBelowMax { key, .. }
            | FenceError::Negative { key, .. }
            | FenceError::UnknownJoint { key }
            | FenceError::OutsideArmLimit { key, .. }
            | FenceError::SingularityOrder { key, .. }
            | FenceError::Unnamed { key }
            | FenceError::DuplicateName { key, .. } => key,
        }
    }
}

const AXES: [&str; 3] = ["x", "y", "z"];

impl Fence {
    /// The joint named `j1`..`j7` as its index 0..6.
    pub fn joint_index(name: &str) -> Option<usize> {
        let n: usize = name.strip_prefix('j')?.parse().ok()?;
        (1..=7).contains(&n).then(|| n - 1)
    }

    /// Whether this fence can be kept; the first thing wrong, naming its key.
    pub fn check(&self) -> Result<(), FenceError> {
        if let Some(inside) = &self.inside {
            check_box("inside", inside)?;
        }
        for (key, value) in [
            ("tool_radius", self.tool_radius),
            ("slow_zone", self.slow_zone),
        ] {
            finite(key, value)?;
            if value < 0.0 {
                return Err(FenceError::Negative {
                    key: key.into(),
                    value,
                });
            }
        }
        for (index, limits) in self.joints.iter().enumerate() {
            let Some([min, max]) = *limits else { continue };
            let key = format!("joints.j{}", index + 1);
            finite(&key, min)?;
            finite(&key, max)?;
            if min >= max {
                let axis = "the joint";
                return Err(FenceError::MinNotBelowMax {
                    key,
                    axis,
                    min,
                    max,
                });
            }
            let limit = JOINT_LIMITS_DEG[index].unwrap_or(180.0);
            if min < -limit || max > limit {
                return Err(FenceError::OutsideArmLimit {
                    key,
                    min,
                    max,
                    limit,
                });
            }
        }
        let Singularity { slow, stop } = self.singularity;
        finite("singularity.slow", slow)?;
        finite("singularity.stop", stop)?;
        if slow < 1.0 || slow >= stop {
            let key = "singularity".into();
            return Err(FenceError::SingularityOrder { key, slow, stop });
        }
        for (index, zone) in self.keep_out.iter().enumerate() {
            let key = format!("keep_out[{}]", index + 1);
            if zone.name.trim().is_empty() {
                return Err(FenceError::Unnamed {
                    key: format!("{key}.name"),
                });
            }
            if self.keep_out[..index].iter().any(|z| z.name == zone.name) {
                let name = zone.name.clone();
                return Err(FenceError::DuplicateName {
                    key: format!("{key}.name"),
                    name,
                });
            }
            check_box(&key, &zone.zone)?;
        }
        Ok(())
    }

    /// The zones kept now.
    pub fn zones(&self) -> impl Iterator<Item = &KeepOut> {
        self.keep_out.iter().filter(|z| z.enabled)
    }
}

fn finite(key: &str, value: f64) -> Result<(), FenceError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(FenceError::NotFinite {
            key: key.into(),
            value,
        })
    }
}

fn check_box(key: &str, zone: &Aabb) -> Result<(), FenceError> {
    for (axis, name) in AXES.iter().enumerate() {
        finite(&format!("{key}.min"), zone.min[axis])?;
        finite(&format!("{key}.max"), zone.max[axis])?;
        if zone.min[axis] >= zone.max[axis] {
            return Err(FenceError::MinNotBelowMax {
                key: key.into(),
                axis: name,
                min: zone.min[axis],
                max: zone.max[axis],
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests;
