//! The parts of the console's state, each owning one concern's facts, handlers and view; [`App`]
//! holds one of each and routes inputs.
//!
//! [`App`]: super::App

mod arm;
mod book;
mod keys;
mod screen;
mod tour;

pub(super) use arm::Arm;
pub use arm::{ArmView, FenceScreenView, arm_refusal};
pub(super) use book::Book;
pub use book::BookView;
pub(super) use keys::Keys;
pub use keys::KeysView;
pub(super) use screen::Screen;
pub use screen::ScreenView;
pub use tour::TourView;
pub(super) use tour::{Leg, Tours};
