//! What one frame shows, built once per frame from the app (oxker's `FrameData`): the panels
//! draw from it alone, and the drawing thread gets it instead of a copy of the whole app.
//!
//! It is made of the parts' own views ([`App::view`]): each holds plain values, worked out once
//! (ages, the motion shown) and cut to what a screen can show (the part of the book around the
//! selection, the newest log lines), so building it costs the same whatever the book's or the
//! log's size. A new panel value is written in its part's view and drawn in its panel.

use std::collections::VecDeque;
use std::sync::Arc;

use super::app::{App, ArmView, BookView, KeysView, ScreenView, SessionView, TourView, TruthView};
use crate::link::interface::LogEntry;

/// Everything the panels draw. Compared with the last one drawn to skip a frame that would
/// show the same (see [`super::pacing`]): every field must take part in `PartialEq`.
#[derive(Debug, Clone, PartialEq)]
pub struct View {
    /// The session's fixed facts and what this link offers.
    pub session: SessionView,
    /// The jog engine's mode and joint, the step.
    pub keys: KeysView,
    /// The link, the telemetry and what is kept of it.
    pub arm: ArmView,
    /// The motion shown and what is stale.
    pub truth: TruthView,
    /// The part of the position book a screen can show.
    pub book: BookView,
    /// The overlay, the bottom line, the newest log lines, the size.
    pub screen: ScreenView,
    /// The tour being played: `TOUR 2/5 → bench`.
    pub tour: Option<TourView>,
}

impl View {
    pub fn new(app: &App) -> View {
        app.view()
    }
}

impl View {
    /// Whether `self` shows the same as `shown` but for what ticks over while the arm is at
    /// rest: the measured latency, the count and latency of the telemetry polls' log line, and
    /// temperatures (they creep for minutes after a start, in steps far below the 0.1 °C
    /// shown). The frame pacer draws those at a slower rate (see [`super::pacing`]).
    ///
    /// `self` is left as it was: its background is swapped for `shown`'s for the comparison
    /// and back, rather than compared on a copy (a whole view cloned several times a second at
    /// rest, only to be dropped).
    pub fn differs_only_in_background(&mut self, shown: &View) -> bool {
        let same_lines = self.screen.log.len() == shown.screen.log.len()
            && (self.screen.log.iter())
                .zip(&shown.screen.log)
                .all(|(line, was)| {
                    Arc::ptr_eq(line, was) || line == was || same_but_poll_count(line, was)
                });
        if !same_lines {
            return false;
        }
        let own = self.take_background_of(shown);
        let same = *self == *shown;
        self.put_background(own);
        same
    }

    /// Gives `self` the background values `shown` has, and returns its own.
    fn take_background_of(&mut self, shown: &View) -> Background {
        // The lines were compared already: `shown`'s are put in whole (their `Arc`s, not copies).
        let mut own = Background {
            latency: std::mem::replace(&mut self.arm.latency, shown.arm.latency),
            temperatures: None,
            log: std::mem::replace(&mut self.screen.log, shown.screen.log.clone()),
        };
        if let (Some(now), Some(was)) = (self.arm.telemetry.as_mut(), shown.arm.telemetry.as_ref())
        {
            let cpu = std::mem::replace(&mut now.arm.cpu_temperature, was.arm.cpu_temperature);
            let ambient = std::mem::replace(
                &mut now.arm.ambient_temperature,
                was.arm.ambient_temperature,
            );
            let joints = std::array::from_fn(|j| {
                std::mem::replace(&mut now.joints[j].temperature, was.joints[j].temperature)
            });
            own.temperatures = Some((cpu, ambient, joints));
        }
        own
    }

    /// Puts back what [`View::take_background_of`] took.
    fn put_background(&mut self, own: Background) {
        self.arm.latency = own.latency;
        if let (Some(t), Some((cpu, ambient, joints))) =
            (self.arm.telemetry.as_mut(), own.temperatures)
        {
            t.arm.cpu_temperature = cpu;
            t.arm.ambient_temperature = ambient;
            for (joint, temperature) in t.joints.iter_mut().zip(joints) {
                joint.temperature = temperature;
            }
        }
        self.screen.log = own.log;
    }
}

/// The same line but for what a telemetry poll's line counts over at rest: its count and
/// latency. Every field is named, so a new one must be placed here.
fn same_but_poll_count(line: &LogEntry, was: &LogEntry) -> bool {
    let LogEntry {
        id,
        poll,
        count: _,
        name,
        outcome,
        ok,
        latency: _,
        traffic,
    } = line;
    *poll
        && was.poll
        && *id == was.id
        && *name == was.name
        && *outcome == was.outcome
        && *ok == was.ok
        && *traffic == was.traffic
}

/// A view's own values of what ticks over at rest, while it holds another's for a comparison.
struct Background {
    latency: Option<std::time::Duration>,
    /// CPU, ambient and joint temperatures.
    temperatures: Option<(f32, f32, [f32; JOINTS])>,
    /// The log lines.
    log: VecDeque<Arc<LogEntry>>,
}

const JOINTS: usize = crate::kortex::registers::input_register::JOINTS as usize;
