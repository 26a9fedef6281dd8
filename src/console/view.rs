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
    ///
    /// `self` is left as it was: its background is swapped for `shown`'s for the comparison
    /// and back, rather than compared on a copy (a whole view cloned several times a second at
    /// rest, only to be dropped).
    pub fn differs_only_in_background(&mut self, shown: &View) -> bool {
        if self.screen.log.len() != shown.screen.log.len() {
            return false;
        }
        let own = self.take_background_of(shown);
        let same = *self == *shown;
        self.put_background(own);
        same
    }

    /// Gives `self` the background values `shown` has, and returns its own.
    fn take_background_of(&mut self, shown: &View) -> Background {
        let mut own = Background {
            latency: std::mem::replace(&mut self.arm.latency, shown.arm.latency),
            temperatures: None,
            polls: Vec::new(),
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
        for (i, (entry, was)) in self
            .screen
            .log
            .iter_mut()
            .zip(&shown.screen.log)
            .enumerate()
        {
            if entry.poll && was.poll && entry.name == was.name && entry.outcome == was.outcome {
                let count = std::mem::replace(&mut entry.count, was.count);
                let latency = std::mem::replace(&mut entry.latency, was.latency);
                own.polls.push((i, count, latency));
            }
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
        for (i, count, latency) in own.polls {
            if let Some(entry) = self.screen.log.get_mut(i) {
                entry.count = count;
                entry.latency = latency;
            }
        }
    }
}

/// A view's own values of what ticks over at rest, while it holds another's for a comparison.
struct Background {
    latency: Option<std::time::Duration>,
    /// CPU, ambient and joint temperatures.
    temperatures: Option<(f32, f32, [f32; JOINTS])>,
    /// The poll log lines' index, count and latency.
    polls: Vec<(usize, u32, Option<std::time::Duration>)>,
}

const JOINTS: usize = crate::kortex::registers::input_register::JOINTS as usize;
