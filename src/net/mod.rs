//! IO helpers shared by the link (client) and the simulator (server). Imports neither.

pub mod connect;
pub mod frame_reader;

pub use connect::{ConnectError, connect_with_timeout};
pub use frame_reader::{DEFAULT_FRAME_DEADLINE, FrameReader};
