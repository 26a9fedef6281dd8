//! The simulator's Talos and Modbus servers through real sockets.
//!
//! One test binary per folder (linking one binary per file cost most of a CI run): each module
//! is named for what it tests, so test paths read `<module>::<test>`. Helpers shared with other
//! binaries stay in `tests/<helper>/` and come in by path.

#[path = "../log_capture/mod.rs"]
mod log_capture;

mod hostile_names;
mod modbus;
mod modbus_hostile;
mod speed_cap;
mod talos;
mod talos_disconnect;
mod talos_handshake;
mod talos_one_client;
mod talos_reject_log;
mod talos_split;
