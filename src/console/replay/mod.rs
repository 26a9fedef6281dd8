//! `armjog replay FILE`: a recorded session played back in the console's own panels, with no
//! link opened and no key able to move anything. `recording` reads the file back as the app's
//! inputs, `player` feeds them to the app on a clock of its own, `run` is the terminal's end.

mod chunks;
mod player;
pub mod recording;
mod run;
mod telemetry;

pub use player::{Control, Player, config_of};
pub use recording::{Happened, Recording, RecordingError};
pub use run::run;
