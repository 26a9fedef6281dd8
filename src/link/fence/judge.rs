//! One telemetry sample against the motion held: how fast, along which axes, or not at all.

use nalgebra::{SVector, Vector6};

use super::geometry::Barrier;
use super::{Fence, JOINT_SLOW_BAND_DEG, SLOWEST};
use crate::kortex::gen3::{condition_number, jacobian};

/// How far ahead of the tool a contact is called, at least, s ([`Pace::lookahead_s`]).
pub const MIN_LOOKAHEAD_S: f64 = 0.08;
/// The least stop margin toward a face, mm, and toward a soft limit, degrees.
const MIN_MARGIN_MM: f64 = 0.5;
const MIN_MARGIN_DEG: f64 = 0.3;
/// Below this a joint is not turning toward anything, deg/s.
const TURNING_DEG_S: f64 = 0.5;
/// Speed factors are kept to these steps, so a slow-down sends a command per step, not per sample.
const FACTOR_STEP: f64 = 0.05;
/// A factor this close under a step is on it: an f32 pose in metres is good to some 1e-5 mm.
const STEP_ROUNDING: f64 = 1e-4;

/// What a sample tells the fence.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// The tool point, mm, base frame.
    pub tool_mm: [f64; 3],
    /// Joint angles, degrees in (-180, 180].
    pub joints_deg: [f64; 7],
    /// Joint rates, deg/s.
    pub joint_rates: [f64; 7],
    /// The Jacobian's condition number now, and a small step along the motion (see [`kappa_ahead`]).
    pub kappa: Option<(f64, f64)>,
}

/// Where the motion held takes the tool.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Heading {
    /// A cartesian jog in the base frame: the held directions, each -1, 0 or 1. An axis toward a
    /// face at contact is taken out; the rest goes on (the tool slides along the face).
    Axes([i8; 3]),
    /// Anything else: the tool point's direction (unit, or zero), and for a joint jog the joint
    /// (0-6) and its direction. The whole motion stops at contact.
    Along {
        tool: [f64; 3],
        joint: Option<(usize, f64)>,
    },
}

/// What the fence makes of the held motion.
#[derive(Debug, Clone, PartialEq)]
pub struct Verdict {
    /// The directions that may go on ([`Heading::Axes`]); zero for any other heading.
    pub axes: [i8; 3],
    /// The fraction of the technician's speed, 0 to 1, in steps; 0: nothing may move.
    pub factor: f64,
    pub state: FenceState,
}

impl Verdict {
    pub fn blocked(&self) -> bool {
        self.factor == 0.0
    }
}

/// What the status bar says of the fence.
#[derive(Debug, Clone, PartialEq)]
pub enum FenceState {
    Clear,
    /// Slowed toward a face or zone `mm` away.
    Slowed {
        what: String,
        mm: f64,
    },
    /// Slowed near a soft limit `deg` away.
    SlowedJoint {
        joint: usize,
        deg: f64,
    },
    /// Slowed near a singularity.
    Singular {
        kappa: f64,
    },
    /// At a face or zone (or a soft limit, a singularity): the motion toward it taken out.
    AtFence {
        what: String,
    },
    /// The tool sphere `mm` across `what`; `deeper`: the motion held goes further in.
    Outside {
        what: String,
        mm: f64,
        deeper: bool,
    },
}

impl FenceState {
    /// The status bar's words, readable without colour.
    pub fn text(&self) -> Option<String> {
        Some(match self {
            FenceState::Clear => return None,
            FenceState::Slowed { what, mm } => format!("SLOWED: {what} {mm:.0} mm"),
            FenceState::SlowedJoint { joint, deg } => {
                format!("SLOWED: J{} soft limit {deg:.1}°", joint + 1)
            }
            FenceState::Singular { kappa } => format!("SLOWED: near singularity κ {kappa:.0}"),
            FenceState::AtFence { what } => format!("AT FENCE: {what}"),
            FenceState::Outside { what, mm, .. } => format!("OUTSIDE FENCE: {what}, {mm:.0} mm in"),
        })
    }

    /// How much it matters, to keep the one that says most.
    fn rank(&self) -> u8 {
        match self {
            FenceState::Clear => 0,
            FenceState::Singular { .. } => 1,
            FenceState::SlowedJoint { .. } | FenceState::Slowed { .. } => 2,
            FenceState::AtFence { .. } => 3,
            FenceState::Outside { .. } => 4,
        }
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn unit(v: [f64; 3]) -> [f64; 3] {
    let n = dot(v, v).sqrt();
    if n > 0.0 { v.map(|x| x / n) } else { [0.0; 3] }
}

/// How fast the held motion goes unslowed, and how far ahead a contact is called.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pace {
    /// The tool speed the technician's speed gives, mm/s.
    pub speed_mm_s: f64,
    /// A joint jog's rate, deg/s.
    pub joint_rate: f64,
    /// The telemetry's period and the link's latency, with room: a stop called now takes effect
    /// after the next sample at the latest. At least [`MIN_LOOKAHEAD_S`].
    pub lookahead_s: f64,
}

impl Pace {
    /// A stop margin for `speed` (per s) toward a limit, never under `least`.
    fn margin(&self, speed: f64, least: f64) -> f64 {
        (speed * self.lookahead_s.max(MIN_LOOKAHEAD_S)).max(least)
    }
}

/// The slow zone's factor at `clearance`: 1 at its edge, [`SLOWEST`] at contact.
fn slow_factor(clearance: f64, zone: f64) -> f64 {
    if zone <= 0.0 || clearance >= zone {
        1.0
    } else {
        SLOWEST + (1.0 - SLOWEST) * (clearance / zone).max(0.0)
    }
}

/// κ a small joint step along the tool direction `tool` (or a joint turn) from `q_deg`: whether the
/// motion lowers κ (MoveIt's rule: that motion goes at full speed).
pub fn kappa_ahead(q_deg: &[f64; 7], heading: &Heading) -> Option<(f64, f64)> {
    let q = q_deg.map(f64::to_radians);
    let now = condition_number(&q);
    if !now.is_finite() {
        return None;
    }
    let step: [f64; 7] = match heading {
        Heading::Along {
            joint: Some((j, dir)),
            ..
        } => std::array::from_fn(|i| if i == *j { *dir } else { 0.0 }),
        Heading::Axes(axes) => joint_step(&q, unit(axes.map(f64::from)))?,
        Heading::Along { tool, .. } => joint_step(&q, *tool)?,
    };
    let norm = step.iter().map(|s| s * s).sum::<f64>().sqrt();
    if norm == 0.0 {
        return Some((now, now));
    }
    let ahead: [f64; 7] = std::array::from_fn(|i| q[i] + step[i] / norm * 1e-3);
    Some((now, condition_number(&ahead)))
}

/// Joint rates that move the tool point along `tool` without turning it.
fn joint_step(q: &[f64; 7], tool: [f64; 3]) -> Option<[f64; 7]> {
    let pinv = jacobian(q).pseudo_inverse(1e-9).ok()?;
    let twist = Vector6::new(tool[0], tool[1], tool[2], 0.0, 0.0, 0.0);
    let rates: SVector<f64, 7> = pinv * twist;
    Some(std::array::from_fn(|i| rates[i]))
}

/// The state that says most, and the least factor.
struct Worst {
    factor: f64,
    state: FenceState,
    /// The rank-2 slow-downs compare by factor.
    slow_at: f64,
}

impl Worst {
    fn note(&mut self, factor: f64, state: FenceState) {
        let (rank, mine) = (state.rank(), self.state.rank());
        if rank > mine || (rank == mine && factor < self.slow_at) {
            self.state = state;
            self.slow_at = factor;
        }
        self.factor = self.factor.min(factor);
    }
}

impl Fence {
    /// The held motion against one sample, at `pace`.
    pub fn judge(&self, sample: &Sample, heading: Heading, pace: Pace) -> Verdict {
        let mut axes = match heading {
            Heading::Axes(axes) => axes,
            Heading::Along { .. } => [0; 3],
        };
        let direction = |axes: [i8; 3]| match heading {
            Heading::Axes(_) => unit(axes.map(f64::from)),
            Heading::Along { tool, .. } => tool,
        };
        let mut worst = Worst {
            factor: 1.0,
            state: FenceState::Clear,
            slow_at: 1.0,
        };
        let p = sample.tool_mm;
        // Across a barrier already: out at the slow speed, deeper not at all.
        let mut across: Option<Barrier> = None;
        let mut deeper = false;
        self.barriers(p, |b| {
            if b.clearance < 0.0 {
                deeper |= dot(direction(axes), b.away) < -1e-9;
                if across.is_none_or(|a| b.clearance < a.clearance) {
                    across = Some(b);
                }
            }
        });
        if let Some(b) = across {
            let factor = if deeper { 0.0 } else { SLOWEST };
            let (what, mm) = (b.name.to_string(), -b.clearance);
            worst.note(factor, FenceState::Outside { what, mm, deeper });
        } else {
            self.judge_approach(p, heading, &mut axes, direction, pace, &mut worst);
        }
        self.judge_joints(sample, heading, pace, &mut worst);
        self.judge_singularity(sample, &mut worst);
        let moving = match heading {
            Heading::Axes(_) => axes != [0; 3],
            Heading::Along { .. } => true,
        };
        let factor = if moving && worst.factor > 0.0 {
            ((worst.factor / FACTOR_STEP + STEP_ROUNDING).floor() * FACTOR_STEP)
                .max(SLOWEST.min(worst.factor))
        } else {
            0.0
        };
        Verdict {
            axes,
            factor,
            state: worst.state,
        }
    }

    /// Toward each barrier: contact takes the axes toward it out (or stops), the slow zone slows.
    fn judge_approach(
        &self,
        p: [f64; 3],
        heading: Heading,
        axes: &mut [i8; 3],
        direction: impl Fn([i8; 3]) -> [f64; 3],
        pace: Pace,
        worst: &mut Worst,
    ) {
        // Taking an axis out changes the direction: again until nothing changes (at most 3).
        for _ in 0..3 {
            let d = direction(*axes);
            let mut contact: Option<(&str, [f64; 3])> = None;
            self.barriers(p, |b| {
                let toward = -dot(d, b.away);
                let at_contact = pace.speed_mm_s * SLOWEST * toward;
                if toward > 1e-9 && b.clearance <= pace.margin(at_contact, MIN_MARGIN_MM) {
                    contact.get_or_insert((b.name, b.away));
                }
            });
            let Some((name, away)) = contact else { break };
            let what = name.to_string();
            match heading {
                Heading::Axes(_) => {
                    for i in 0..3 {
                        if f64::from(axes[i]) * away[i] < -1e-9 {
                            axes[i] = 0;
                        }
                    }
                    let factor = if *axes == [0; 3] { 0.0 } else { 1.0 };
                    worst.note(factor, FenceState::AtFence { what });
                }
                Heading::Along { .. } => {
                    worst.note(0.0, FenceState::AtFence { what });
                    return;
                }
            }
        }
        let d = direction(*axes);
        self.barriers(p, |b| {
            if -dot(d, b.away) > 1e-9 && b.clearance < self.slow_zone {
                let factor = slow_factor(b.clearance, self.slow_zone);
                let (what, mm) = (b.name.to_string(), b.clearance.max(0.0));
                worst.note(factor, FenceState::Slowed { what, mm });
            }
        });
    }

    /// Soft limits: a joint jog slows over the last [`JOINT_SLOW_BAND_DEG`] and stops at its
    /// limit; any other motion stops when a joint turning toward its limit reaches it.
    fn judge_joints(&self, sample: &Sample, heading: Heading, pace: Pace, worst: &mut Worst) {
        for (index, limits) in self.joints.iter().enumerate() {
            let Some([min, max]) = *limits else { continue };
            let q = sample.joints_deg[index];
            let jogged = match heading {
                Heading::Along {
                    joint: Some((j, dir)),
                    ..
                } if j == index => Some(dir),
                _ => None,
            };
            let (dir, rate) = match jogged {
                Some(dir) => (dir, pace.joint_rate),
                None => {
                    let rate = sample.joint_rates[index];
                    if rate.abs() < TURNING_DEG_S {
                        continue;
                    }
                    (rate.signum(), rate.abs())
                }
            };
            let left = if dir > 0.0 { max - q } else { q - min };
            let what = || format!("J{} soft limit", index + 1);
            let stop_at = match jogged {
                Some(_) => pace.margin(rate * SLOWEST, MIN_MARGIN_DEG),
                None => pace.margin(rate, MIN_MARGIN_DEG),
            };
            if left <= stop_at {
                worst.note(0.0, FenceState::AtFence { what: what() });
            } else if jogged.is_some() && left < JOINT_SLOW_BAND_DEG {
                let factor = slow_factor(left, JOINT_SLOW_BAND_DEG);
                worst.note(
                    factor,
                    FenceState::SlowedJoint {
                        joint: index,
                        deg: left,
                    },
                );
            }
        }
    }

    /// From κ = slow the speed falls to zero at κ = stop, unless the motion lowers κ.
    fn judge_singularity(&self, sample: &Sample, worst: &mut Worst) {
        let Some((now, ahead)) = sample.kappa else {
            return;
        };
        let s = self.singularity;
        if now <= s.slow || ahead < now {
            return;
        }
        let factor = ((s.stop - now) / (s.stop - s.slow)).clamp(0.0, 1.0);
        if factor == 0.0 {
            worst.note(
                0.0,
                FenceState::AtFence {
                    what: format!("singularity κ {now:.0}"),
                },
            );
        } else {
            worst.note(factor, FenceState::Singular { kappa: now });
        }
    }
}
