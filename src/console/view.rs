//! What one frame shows, built once per frame from the app (oxker's `FrameData`): the panels
//! draw from it alone, and the drawing thread gets it instead of a copy of the whole app.
//!
//! It is made of the parts' own views ([`App::view`]): each holds plain values, worked out once
//! (ages, the motion shown) and cut to what a screen can show (the part of the book around the
//! selection, the newest log lines), so building it costs the same whatever the book's or the
//! log's size. A new panel value is written in its part's view and drawn in its panel.

use super::app::{App, ArmView, BookView, KeysView, ScreenView, SessionView, TourView, TruthView};

/// Everything the panels draw. Compared with the last one drawn to skip a frame that would
/// show the same (see [`super::pacing`]).
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
