//! The simulator's Talos and Modbus servers through real sockets.
//!
//! One test binary for several former ones (linking one binary per file cost most of a CI
//! run): each module is one former `tests/<name>.rs`, so test paths read `<name>::<test>`.
//! Helpers shared with other binaries stay in `tests/<helper>/` and come in by path.

#[path = "../log_capture/mod.rs"]
mod log_capture;

mod sim_hostile_names;
mod sim_modbus;
mod sim_modbus_hostile;
mod sim_speed_cap;
mod sim_talos;
mod sim_talos_disconnect;
mod sim_talos_handshake;
mod sim_talos_reject_log;
mod sim_talos_split;
