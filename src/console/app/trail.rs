//! The tool point's recent path, a point per [`TRAIL_SPACING`] over [`TRAIL_SPAN`].

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use crate::console::arm_geometry;
use crate::kortex::Telemetry;

/// How far back the trail goes.
pub const TRAIL_SPAN: Duration = Duration::from_secs(10);
/// The shortest time between two kept points: at most 200 points per span.
pub const TRAIL_SPACING: Duration = Duration::from_millis(50);
/// The most points the trail holds (one more than the span over the spacing: both ends).
pub const TRAIL_CAPACITY: usize = 201;

/// A point's brightness in thirds of [`TRAIL_SPAN`], so a still trail does not redraw.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum TrailShade {
    Old,
    Mid,
    New,
}

impl TrailShade {
    pub fn of(age: Duration) -> TrailShade {
        let third = TRAIL_SPAN / 3;
        if age < third {
            TrailShade::New
        } else if age < 2 * third {
            TrailShade::Mid
        } else {
            TrailShade::Old
        }
    }
}

/// One point of the trail: when it was seen and where (base frame, m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrailPoint {
    pub at: Instant,
    pub position: [f64; 3],
}

/// A bounded ring of the newest tool points, oldest first.
#[derive(Debug, Clone, Default)]
pub struct ToolTrail {
    points: VecDeque<TrailPoint>,
}

impl ToolTrail {
    /// Takes `telemetry`'s tool point unless the last is newer than [`TRAIL_SPACING`]; ages out.
    pub fn record(&mut self, telemetry: &Telemetry, now: Instant) {
        self.age_out(now);
        if self
            .points
            .back()
            .is_some_and(|last| now.saturating_duration_since(last.at) < TRAIL_SPACING)
        {
            return;
        }
        let positions = telemetry.joints.map(|j| j.position);
        let tool = arm_geometry::arm_pose(&positions).tool();
        if !tool.iter().all(|v| v.is_finite()) {
            return;
        }
        if self.points.len() >= TRAIL_CAPACITY {
            self.points.pop_front();
        }
        self.points.push_back(TrailPoint {
            at: now,
            position: [tool.x, tool.y, tool.z],
        });
    }

    /// Drops the points older than [`TRAIL_SPAN`] at `now`.
    fn age_out(&mut self, now: Instant) {
        while self
            .points
            .front()
            .is_some_and(|p| now.saturating_duration_since(p.at) > TRAIL_SPAN)
        {
            self.points.pop_front();
        }
    }

    /// The points no older than [`TRAIL_SPAN`] at `now`, with their ages, oldest first.
    pub fn recent(&self, now: Instant) -> Vec<(Duration, [f64; 3])> {
        self.points
            .iter()
            .map(|p| (now.saturating_duration_since(p.at), p.position))
            .filter(|(age, _)| *age <= TRAIL_SPAN)
            .collect()
    }

    /// [`ToolTrail::recent`] as drawn, shaded; a run of identical points given once.
    pub fn shaded(&self, now: Instant) -> Vec<(TrailShade, [f64; 3])> {
        let mut shaded: Vec<(TrailShade, [f64; 3])> = Vec::new();
        for (age, position) in self.recent(now) {
            let point = (TrailShade::of(age), position);
            if shaded.last() != Some(&point) {
                shaded.push(point);
            }
        }
        shaded
    }

    pub fn len(&self) -> usize {
        self.points.len()
    }

    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }
}

impl super::App {
    /// The tool's path over the last [`TRAIL_SPAN`] with each point's age, oldest first.
    pub fn trail(&self) -> Vec<(Duration, [f64; 3])> {
        self.now
            .map(|now| self.arm.trail().recent(now))
            .unwrap_or_default()
    }

    /// The trail's buffer, bounded by [`TRAIL_CAPACITY`].
    pub fn trail_buffer(&self) -> &ToolTrail {
        self.arm.trail()
    }
}
