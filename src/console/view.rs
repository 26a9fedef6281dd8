//! What one frame shows, built once per frame from the parts' own views ([`App::view`]): the
//! panels draw from it alone, and the drawing thread gets it instead of a copy of the app. Each
//! part's view holds plain values cut to what a screen can show, so it costs the same whatever
//! the book's or the log's size. A new panel value goes in its part's view and its panel.

use super::app::{
    App, ArmView, BookView, KeysView, MotionStatusView, ScreenView, SessionView, TourView,
};

/// Everything the panels draw. Compared with the last one drawn to skip a frame that would
/// show the same (see [`super::pacing`]).
#[derive(Debug, Clone, PartialEq)]
pub struct View {
    pub session: SessionView,
    pub keys: KeysView,
    pub arm: ArmView,
    pub motion_status: MotionStatusView,
    pub book: BookView,
    pub screen: ScreenView,
    /// The tour being played: `TOUR 2/5 → bench`.
    pub tour: Option<TourView>,
}

impl View {
    pub fn new(app: &App) -> View {
        app.view()
    }
}
