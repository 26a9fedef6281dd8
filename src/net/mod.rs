//! IO helpers shared by the link (client) and the simulator (server). Imports neither.

pub mod connect;
pub mod deadline;
pub mod frame_reader;
pub mod io_error_text;

pub use connect::{ConnectError, connect_with_timeout};
pub use deadline::Deadline;
pub use frame_reader::{DEFAULT_FRAME_DEADLINE, FrameReader};
pub use io_error_text::io_error_words;
