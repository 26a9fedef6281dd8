//! When the console draws a frame, at one of two rates. Live, at most 30 a second ([`FRAME`]):
//! after the technician's input, for every event that is not a routine report, while anything
//! moves or may (a jog, an action, a joint turning, a STOP being confirmed, a doubt shown) and
//! for the change that ends it, and when what forbids motion changes ([`Watched`]: a fault, a
//! stale link, the guard). At rest, one frame every [`REST_FRAME`]: when only routine reports
//! (telemetry, its latency, a poll's log line) changed the app, which they do with every poll
//! as the readings tick over (the latency, the polls' count, temperatures). A view equal to
//! the last one drawn (`View`'s `PartialEq`) is never drawn.
//!
//! The runtime sleeps until [`FramePacer::due_at`], so a console with nothing to draw does not
//! wake. Everything time-dependent a panel shows (ages, stale marks) is a value in the
//! [`View`], worked out from the app's clock when an input or a deadline tick arrives.

use std::time::{Duration, Instant};

use super::app::{App, Input, arm_refusal};
use super::view::View;
use crate::link::interface::ArmEvent;

/// Shortest time between frames at the live rate.
pub const FRAME: Duration = Duration::from_millis(33);
/// Shortest time between frames at rest: a frame at rest is costly, its caches gone cold (the
/// figures are in docs/development.md).
pub const REST_FRAME: Duration = Duration::from_secs(2);
/// How long after a change its frame starts at the soonest: the command a key sent (a release's
/// STOP above all) goes out before a frame's drawing competes with it for the CPU.
pub const SETTLE: Duration = Duration::from_millis(3);

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Pace {
    Rest,
    Live,
}

/// What the technician waits on, read from the app after every input: whether the arm moves
/// or may ([`App::arm_in_motion`]), and what forbids motion (the gate's answer,
/// [`App::motion_refusal`], and what the arm's report forbids, [`arm_refusal`], which the
/// gate hides behind a link or guard refusal). A change in it is drawn at the live rate even
/// when a routine report made it.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Watched {
    moving: bool,
    gate: Option<String>,
    report: Option<String>,
}

impl Watched {
    pub fn of(app: &App) -> Watched {
        Watched {
            moving: app.arm_in_motion(),
            gate: app.motion_refusal(),
            report: app.telemetry().and_then(arm_refusal),
        }
    }
}

/// Decides when to hand the painter a frame and whether it is worth drawing.
#[derive(Debug, Default)]
pub struct FramePacer {
    /// The changes not drawn yet: their pace and when the first came.
    pending: Option<(Pace, Instant)>,
    last_paint: Option<Instant>,
    shown: Option<View>,
    /// What the technician waits on, as of the last change.
    watched: Watched,
}

impl FramePacer {
    /// The app changed at `now`, `routine` when only a routine report changed it: drawn at rest
    /// unless it changed what the technician waits on, or anything moves or just stopped.
    pub fn changed(&mut self, routine: bool, app: &App, now: Instant) {
        let watched = Watched::of(app);
        let live = !routine || watched.moving || self.watched.moving || watched != self.watched;
        self.watched = watched;
        let pace = if live { Pace::Live } else { Pace::Rest };
        self.pending = Some(match self.pending {
            Some((was, first)) => (was.max(pace), first),
            None => (pace, now),
        });
    }

    pub fn due_at(&self) -> Option<Instant> {
        let (pace, first) = self.pending?;
        let period = match pace {
            Pace::Live => FRAME,
            Pace::Rest => REST_FRAME,
        };
        let settled = first + SETTLE;
        Some(
            self.last_paint
                .map_or(settled, |last| settled.max(last + period)),
        )
    }

    /// At the due time: the view to paint, or `None` when it shows exactly what the last
    /// painted one did (the screen is already right).
    pub fn frame(&mut self, view: View, now: Instant) -> Option<View> {
        self.pending = None;
        if self.shown.as_ref() == Some(&view) {
            return None;
        }
        self.last_paint = Some(now);
        self.shown = Some(view.clone());
        Some(view)
    }
}

/// A routine report: what a link sends with every telemetry poll (the snapshot, its latency,
/// and its log line when the poll succeeded). At rest its frame comes at the rest rate.
pub fn is_routine_report(input: &Input) -> bool {
    match input {
        Input::Arm(ArmEvent::Telemetry(_) | ArmEvent::Latency(_)) => true,
        Input::Arm(ArmEvent::Log(entry)) => entry.poll && entry.ok,
        _ => false,
    }
}

#[cfg(test)]
mod tests;
