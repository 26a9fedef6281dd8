//! Distances from the tool sphere to the box's faces and to the zones, mm, base frame.

use super::Fence;

/// An axis-aligned box, mm, base frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

/// One thing the tool sphere must not cross, as seen from where the tool is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Barrier<'a> {
    /// `floor`, `+X side`, or a zone's name.
    pub name: &'a str,
    /// Between the sphere and the barrier, mm; negative: the sphere is that deep across it.
    pub clearance: f64,
    /// The unit direction that takes the tool away from it (out of a zone it is in).
    pub away: [f64; 3],
}

/// The box's faces as a technician names them: -X side, +X side, -Y, +Y, floor, ceiling.
pub const FACE_NAMES: [[&str; 2]; 3] = [
    ["-X side", "+X side"],
    ["-Y side", "+Y side"],
    ["floor", "ceiling"],
];

fn unit(axis: usize, sign: f64) -> [f64; 3] {
    let mut v = [0.0; 3];
    v[axis] = sign;
    v
}

impl Aabb {
    /// The sphere of `radius` at `p`: its clearance to this box and the way out or away.
    pub fn clearance(&self, p: [f64; 3], radius: f64) -> (f64, [f64; 3]) {
        let closest: [f64; 3] = std::array::from_fn(|i| p[i].clamp(self.min[i], self.max[i]));
        let gap: [f64; 3] = std::array::from_fn(|i| p[i] - closest[i]);
        let distance = gap.iter().map(|g| g * g).sum::<f64>().sqrt();
        if distance > 0.0 {
            return (distance - radius, gap.map(|g| g / distance));
        }
        // Inside (or on a face): out through the nearest face.
        let mut best = (f64::INFINITY, [0.0; 3]);
        for (axis, at) in p.iter().enumerate() {
            let below = at - self.min[axis];
            let above = self.max[axis] - at;
            if below < best.0 {
                best = (below, unit(axis, -1.0));
            }
            if above < best.0 {
                best = (above, unit(axis, 1.0));
            }
        }
        (-best.0 - radius, best.1)
    }

    /// The least clearance of the sphere of `radius` moved straight from `a` to `b`. The distance
    /// to a convex box is convex along a line, so a ternary search finds it.
    pub fn least_clearance_along(&self, a: [f64; 3], b: [f64; 3], radius: f64) -> f64 {
        let at = |t: f64| std::array::from_fn(|i| a[i] + (b[i] - a[i]) * t);
        let clearance = |t: f64| self.clearance(at(t), radius).0;
        let (mut lo, mut hi) = (0.0f64, 1.0f64);
        for _ in 0..60 {
            let (m1, m2) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
            if clearance(m1) <= clearance(m2) {
                hi = m2;
            } else {
                lo = m1;
            }
        }
        clearance((lo + hi) / 2.0)
            .min(clearance(0.0))
            .min(clearance(1.0))
    }
}

impl Fence {
    /// Every barrier kept now, seen from the tool point `p` (mm): the box's six faces, then the
    /// enabled zones. Calls `each` rather than collecting: this runs on every telemetry sample.
    pub fn barriers<'a>(&'a self, p: [f64; 3], mut each: impl FnMut(Barrier<'a>)) {
        let r = self.tool_radius;
        if let Some(inside) = &self.inside {
            for axis in 0..3 {
                let [low, high] = FACE_NAMES[axis];
                each(Barrier {
                    name: low,
                    clearance: p[axis] - inside.min[axis] - r,
                    away: unit(axis, 1.0),
                });
                each(Barrier {
                    name: high,
                    clearance: inside.max[axis] - p[axis] - r,
                    away: unit(axis, -1.0),
                });
            }
        }
        for zone in self.zones() {
            let (clearance, away) = zone.zone.clearance(p, r);
            each(Barrier {
                name: &zone.name,
                clearance,
                away,
            });
        }
    }

    /// The barrier nearest the tool sphere at `p` (mm), and its clearance: what the tool panel
    /// shows.
    pub fn nearest(&self, p: [f64; 3]) -> Option<(&str, f64)> {
        let mut nearest: Option<(&str, f64)> = None;
        self.barriers(p, |b| {
            if nearest.is_none_or(|(_, c)| b.clearance < c) {
                nearest = Some((b.name, b.clearance));
            }
        });
        nearest
    }

    /// Why a tool point at `target` (mm) may not be gone to: the barrier the sphere would cross.
    pub fn refuse_target(&self, target: [f64; 3]) -> Option<String> {
        let mut worst: Option<(f64, &str)> = None;
        self.barriers(target, |b| {
            if b.clearance < 0.0 && worst.is_none_or(|(c, _)| b.clearance < c) {
                worst = Some((b.clearance, b.name));
            }
        });
        worst.map(|(c, name)| format!("{name} ({:.0} mm in)", -c))
    }

    /// The zone a straight move from `from` to `to` (mm) passes through, if any. The box is convex:
    /// a target inside it ([`Fence::refuse_target`]) keeps the path inside.
    /// A path that grazes a zone (clearance down to -0.01 mm, rounding) is let through.
    pub fn refuse_path(&self, from: [f64; 3], to: [f64; 3]) -> Option<&str> {
        self.zones()
            .find(|z| z.zone.least_clearance_along(from, to, self.tool_radius) < -0.01)
            .map(|z| z.name.as_str())
    }
}
