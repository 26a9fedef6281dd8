//! The simulator under attack, each test against its own `armjog sim` process: floods, exhausted
//! file descriptors, memory, neighbours.
//!
//! One test binary for several former ones (linking one binary per file cost most of a CI
//! run): each module is one former `tests/<name>.rs`, so test paths read `<name>::<test>`.
//! Helpers shared with other binaries stay in `tests/<helper>/` and come in by path.

#[path = "../attack_support/mod.rs"]
mod attack_support;
#[path = "../log_files/mod.rs"]
mod log_files;

mod sim_attack_fd_limit;
mod sim_attack_memory;
mod sim_attack_modbus;
mod sim_attack_neighbours;
mod sim_attack_talos;
