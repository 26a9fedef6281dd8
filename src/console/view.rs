//! What one frame shows, built once per frame from the app (oxker's `FrameData`): the panels
//! draw from it alone, and the drawing thread gets it instead of a copy of the whole app.
//!
//! It is made of the parts' own views ([`App::view`]): each holds plain values, worked out once
//! (ages, the motion shown) and cut to what a screen can show (the part of the book around the
//! selection, the newest log lines), so building it costs the same whatever the book's or the
//! log's size. A new panel value is written in its part's view and drawn in its panel.

use super::app::{App, ArmView, BookView, KeysView, ScreenView, SessionView, TourView, TruthView};

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
    pub fn differs_only_in_background(&self, shown: &View) -> bool {
        if self.screen.log.len() != shown.screen.log.len() {
            return false;
        }
        let mut same = self.clone();
        same.arm.latency = shown.arm.latency;
        if let (Some(now), Some(was)) = (same.arm.telemetry.as_mut(), shown.arm.telemetry.as_ref())
        {
            now.arm.cpu_temperature = was.arm.cpu_temperature;
            now.arm.ambient_temperature = was.arm.ambient_temperature;
            for (joint, before) in now.joints.iter_mut().zip(&was.joints) {
                joint.temperature = before.temperature;
            }
        }
        for (entry, was) in same.screen.log.iter_mut().zip(&shown.screen.log) {
            if entry.poll && was.poll && entry.name == was.name && entry.outcome == was.outcome {
                entry.count = was.count;
                entry.latency = was.latency;
            }
        }
        same == *shown
    }
}
