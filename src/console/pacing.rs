//! When the console draws a frame: at most 30 a second after the technician's own input or
//! while the arm moves (a jog, an action, or joints turning in the telemetry), at most 7.5 a
//! second when only the arm's reports changed, every 2 s when only what ticks over at rest
//! changed (the latency, the telemetry polls' count, temperatures: see
//! [`View::differs_only_in_background`]), and never for a view that shows the same as the one
//! drawn last. The last two keep an idle console's CPU low (`benches/idle_ab.py`).
//!
//! The runtime sleeps until [`FramePacer::wake_at`] rather than waking on a fixed tick, so a
//! console with nothing to draw does not wake at all. A frame that only telemetry reports
//! changed is drawn in the turn of the first report at or after its due time (the console wakes
//! for those anyway); the timer is only a fallback for reports that stop. Everything
//! time-dependent a panel shows (ages, stale marks) is a value in the [`View`], worked out from
//! the app's clock when an input or a deadline tick arrives: a view that differs in any of them
//! is drawn.

use std::time::{Duration, Instant};

use super::view::View;

/// Shortest time between frames after a key, a resize or while jogging.
pub const FRAME: Duration = Duration::from_millis(33);
/// Shortest time between frames when only the arm's reports changed: four fast frames, the
/// rate the console had when it drew on a fixed 33 ms tick once 100 ms had passed (7.5 fps).
pub const IDLE_FRAME: Duration = Duration::from_millis(132);
/// Shortest time between frames when only what ticks over at rest changed.
/// A frame at rest costs the console several ms of CPU, its caches gone cold (the view, the
/// draw, the write): at one a second instead of one every 2 s, a resting console cost 1.3x the
/// CPU, side by side. What the technician must see at once (faults, stale marks, motion)
/// changes more than the background, so it is drawn at the faster rates.
pub const BACKGROUND_FRAME: Duration = Duration::from_secs(2);
/// How long after a change its frame starts at the soonest: the command a key sent (a release's
/// STOP above all) goes out before a frame's drawing competes with it for the CPU.
pub const SETTLE: Duration = Duration::from_millis(3);
/// How late a frame that only the arm's telemetry reports changed may be drawn, waiting for
/// the turn of a report the console wakes for anyway: more than a poll period at the default
/// 30 Hz (33 ms), so at rest such frames are drawn in a report's turn and the loop keeps no
/// wake-up of its own for them. With slower reports, or none, the frame comes this much later.
pub const REPORT_SLACK: Duration = Duration::from_millis(40);

/// Decides when to hand the painter a frame and whether it is worth drawing.
#[derive(Debug, Default)]
pub struct FramePacer {
    /// Something changed since the last frame was considered.
    changed: bool,
    /// The change came from the technician (a key, a resize, a message of the runtime's own).
    urgent: bool,
    /// Every change since the last frame was considered came in a telemetry report: its frame
    /// may wait [`REPORT_SLACK`] for a later report's turn.
    reports_only: bool,
    /// The first change since the last frame was considered.
    changed_at: Option<Instant>,
    last_paint: Option<Instant>,
    /// The last view handed to the painter.
    shown: Option<View>,
    /// A frame held back because only what ticks over at rest changed: when it is due.
    background_due: Option<Instant>,
    /// When the last frame was held back so: the next change is considered no sooner than a
    /// frame's period later, as after a drawn frame (views are not built at the report rate).
    held_at: Option<Instant>,
}

impl FramePacer {
    /// The app changed at `now`; `urgent` when the technician caused it (the faster rate).
    pub fn changed(&mut self, urgent: bool, now: Instant) {
        self.note(urgent, false, now);
    }

    /// A telemetry report changed the app at `now`: drawn at the rate of [`FramePacer::changed`]
    /// with `urgent` false, but [`FramePacer::wake_at`] leaves it [`REPORT_SLACK`] for a later
    /// report's turn.
    pub fn reported(&mut self, now: Instant) {
        self.note(false, true, now);
    }

    fn note(&mut self, urgent: bool, report: bool, now: Instant) {
        if !self.changed {
            self.changed_at = Some(now);
            self.reports_only = report;
        }
        self.reports_only &= report;
        self.changed = true;
        self.urgent |= urgent;
    }

    /// When the runtime must wake for a frame if no input comes first: [`FramePacer::due_at`],
    /// or [`REPORT_SLACK`] after it for a frame only reports changed (or one held back because
    /// only the background changed) while nothing moves. Such a frame is drawn in the first
    /// report's turn at or after its due time instead, so at rest the frames ride the reports'
    /// wake-ups.
    pub fn wake_at(&self, moving: bool) -> Option<Instant> {
        let due = self.due_at(moving)?;
        let slack = (!self.changed || self.reports_only) && !self.urgent && !moving;
        Some(if slack { due + REPORT_SLACK } else { due })
    }

    /// When the next frame is due, or `None` when nothing changed. `moving` (a jog, or the arm
    /// in motion: [`App::arm_in_motion`](super::app::App::arm_in_motion)) draws at the faster
    /// rate, so the motion shown keeps up with the arm.
    pub fn due_at(&self, moving: bool) -> Option<Instant> {
        let Some(changed_at) = self.changed_at.filter(|_| self.changed) else {
            return self.background_due;
        };
        let settled = changed_at + SETTLE;
        let period = if self.urgent || moving {
            FRAME
        } else {
            IDLE_FRAME
        };
        let last = self.last_paint.max(self.held_at);
        let due = last.map_or(settled, |last| settled.max(last + period));
        Some(
            self.background_due
                .map_or(due, |background| due.min(background)),
        )
    }

    /// At the due time: the view to paint, or `None` when it shows exactly what the last
    /// painted one did (the screen is already right). A view that differs only in what ticks
    /// over at rest waits until [`BACKGROUND_FRAME`] after the last frame, unless the
    /// technician caused it.
    pub fn frame(&mut self, mut view: View, now: Instant) -> Option<View> {
        let urgent = self.urgent;
        self.changed = false;
        self.urgent = false;
        self.background_due = None;
        if let Some(shown) = &self.shown {
            if *shown == view {
                return None;
            }
            if let Some(last) = self.last_paint
                && !urgent
                && now < last + BACKGROUND_FRAME
                && view.differs_only_in_background(shown)
            {
                self.background_due = Some(last + BACKGROUND_FRAME);
                self.held_at = Some(now);
                return None;
            }
        }
        self.last_paint = Some(now);
        self.held_at = None;
        self.shown = Some(view.clone());
        Some(view)
    }
}

#[cfg(test)]
mod tests;
