//! The last 30 s of telemetry for the history panel (TCP speed, each joint's current and torque) in
//! fixed 250 ms buckets, so memory is bounded whatever the rate. A bucket keeps the peak speed (a
//! short burst must show) and the mean |current| and |torque|.

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use crate::kortex::{Telemetry, sanity};

/// One bucket's span.
pub const BUCKET: Duration = Duration::from_millis(250);
/// Buckets in the window (30 s / 250 ms).
pub const BUCKETS: usize = 120;
const JOINTS: usize = 7;

/// Which joint quantity the panel plots (a key cycles it).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum JointQuantity {
    #[default]
    Torque,
    Current,
}

impl JointQuantity {
    pub fn next(self) -> JointQuantity {
        match self {
            JointQuantity::Torque => JointQuantity::Current,
            JointQuantity::Current => JointQuantity::Torque,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            JointQuantity::Torque => "torque",
            JointQuantity::Current => "current",
        }
    }

    pub fn unit(self) -> &'static str {
        match self {
            JointQuantity::Torque => "Nm",
            JointQuantity::Current => "A",
        }
    }
}

/// One 250 ms slice of telemetry.
#[derive(Debug, Clone, PartialEq)]
struct Bucket {
    /// Its index counted from the store's origin.
    index: u64,
    /// Peak TCP linear speed, mm/s.
    speed_max: f64,
    abs_torque_sum: [f64; JOINTS],
    abs_current_sum: [f64; JOINTS],
    samples: u32,
    /// A sample out of physical range fell in this bucket: it reads NaN, not the nonsense.
    speed_insane: bool,
    torque_insane: [bool; JOINTS],
    current_insane: [bool; JOINTS],
}

#[derive(Debug, Clone, Default)]
pub struct History {
    origin: Option<Instant>,
    buckets: VecDeque<Bucket>,
    /// The previous TCP position (m) and time, for a speed when telemetry has no twist.
    last_position: Option<([f64; 3], Instant)>,
    /// The latest sample's speed, mm/s.
    latest_speed: f64,
    quantity: JointQuantity,
}

/// What the panel draws: a bucket each, oldest first, `None` where no telemetry came.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct HistorySeries {
    /// TCP linear speed, mm/s (peak per bucket).
    pub speed: Vec<Option<f64>>,
    /// The latest speed, mm/s.
    pub speed_now: Option<f64>,
    /// Per joint: the mean |quantity| per bucket.
    pub joints: [Vec<Option<f64>>; JOINTS],
    pub quantity: JointQuantity,
    /// The joint (1-7) with the largest mean |quantity| over the window, and that mean.
    pub hardest: Option<(u8, f64)>,
}

impl History {
    pub fn quantity(&self) -> JointQuantity {
        self.quantity
    }

    pub fn cycle_quantity(&mut self) {
        self.quantity = self.quantity.next();
    }

    /// Buckets held (at most [`BUCKETS`] + 1: the window and the one being filled).
    pub fn len(&self) -> usize {
        self.buckets.len()
    }

    pub fn is_empty(&self) -> bool {
        self.buckets.is_empty()
    }

    pub fn record(&mut self, t: &Telemetry, now: Instant) {
        let speed = self.speed_of(t, now);
        self.latest_speed = speed;
        let index = self.bucket_index(now);
        // A sample older than the newest bucket (clock went back) joins it, keeping order.
        if self.buckets.back().is_none_or(|b| b.index < index) {
            self.buckets.push_back(Bucket {
                index,
                speed_max: 0.0,
                abs_torque_sum: [0.0; JOINTS],
                abs_current_sum: [0.0; JOINTS],
                samples: 0,
                speed_insane: false,
                torque_insane: [false; JOINTS],
                current_insane: [false; JOINTS],
            });
        }
        if let Some(bucket) = self.buckets.back_mut() {
            if speed.is_finite() {
                bucket.speed_max = bucket.speed_max.max(speed);
            } else {
                bucket.speed_insane = true;
            }
            for (i, joint) in t.joints.iter().enumerate().take(JOINTS) {
                match sanity::JOINT_TORQUE_NM.sane(joint.torque) {
                    Some(torque) => bucket.abs_torque_sum[i] += f64::from(torque).abs(),
                    None => bucket.torque_insane[i] = true,
                }
                match sanity::CURRENT_A.sane(joint.current) {
                    Some(current) => bucket.abs_current_sum[i] += f64::from(current).abs(),
                    None => bucket.current_insane[i] = true,
                }
            }
            bucket.samples += 1;
        }
        self.age_out(index);
    }

    /// TCP speed, mm/s: the twist's, else from the last position; NaN out of physical range.
    fn speed_of(&mut self, t: &Telemetry, now: Instant) -> f64 {
        let twist = &t.tcp.twist;
        let p = &t.tcp.pose;
        let linear = [twist.x, twist.y, twist.z];
        let place = [p.x, p.y, p.z];
        if !linear
            .iter()
            .all(|v| sanity::TOOL_LINEAR_SPEED_M_S.sane(*v).is_some())
            || !place
                .iter()
                .all(|v| sanity::TOOL_POSITION_M.sane(*v).is_some())
        {
            self.last_position = None;
            return f64::NAN;
        }
        let from_twist = norm(linear.map(f64::from)) * 1000.0;
        let position = place.map(f64::from);
        let previous = self.last_position.replace((position, now));
        if from_twist.is_finite() && from_twist > 0.0 {
            return from_twist;
        }
        let Some((before, then)) = previous else {
            return 0.0;
        };
        let dt = now.saturating_duration_since(then).as_secs_f64();
        let moved = norm([0, 1, 2].map(|k| position[k] - before[k]));
        if dt > 0.0 && moved.is_finite() {
            moved / dt * 1000.0
        } else {
            0.0
        }
    }

    fn bucket_index(&mut self, now: Instant) -> u64 {
        let origin = *self.origin.get_or_insert(now);
        let since = now.saturating_duration_since(origin);
        (since.as_millis() / BUCKET.as_millis()) as u64
    }

    /// Drops buckets that ended more than the window before the `current` one.
    fn age_out(&mut self, current: u64) {
        let oldest = current.saturating_sub(BUCKETS as u64 - 1);
        while self.buckets.front().is_some_and(|b| b.index < oldest) {
            self.buckets.pop_front();
        }
    }

    /// The window ending at `now`, for drawing.
    pub fn series(&self, now: Instant) -> HistorySeries {
        let mut series = HistorySeries {
            quantity: self.quantity,
            ..HistorySeries::default()
        };
        let Some(origin) = self.origin else {
            return series;
        };
        let current =
            (now.saturating_duration_since(origin).as_millis() / BUCKET.as_millis()) as u64;
        // The filling bucket joins with its first sample (no blink).
        let newest = if self.buckets.back().is_some_and(|b| b.index >= current) {
            current
        } else {
            current.saturating_sub(1)
        };
        let first = newest.saturating_sub(BUCKETS as u64 - 1);
        let mut totals = [0.0; JOINTS];
        let mut samples = 0u32;
        let mut held = self.buckets.iter().filter(|b| b.index >= first).peekable();
        for index in first..=newest {
            let bucket = held.next_if(|b| b.index == index);
            series.speed.push(bucket.map(|b| {
                if b.speed_insane {
                    f64::NAN
                } else {
                    b.speed_max
                }
            }));
            for (i, joint) in series.joints.iter_mut().enumerate() {
                joint.push(bucket.map(|b| {
                    let (sums, insane) = match self.quantity {
                        JointQuantity::Torque => (&b.abs_torque_sum, &b.torque_insane),
                        JointQuantity::Current => (&b.abs_current_sum, &b.current_insane),
                    };
                    totals[i] += sums[i];
                    if insane[i] {
                        f64::NAN
                    } else {
                        sums[i] / f64::from(b.samples.max(1))
                    }
                }));
            }
            if let Some(b) = bucket {
                samples += b.samples;
                series.speed_now = Some(self.latest_speed);
            }
        }
        if samples > 0 {
            series.hardest = totals
                .iter()
                .enumerate()
                .map(|(i, total)| (i as u8 + 1, total / f64::from(samples)))
                .max_by(|a, b| a.1.total_cmp(&b.1));
        }
        series
    }
}

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}
