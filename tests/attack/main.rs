//! The simulator under attack, each test against its own `armjog sim` process: floods, exhausted
//! file descriptors, memory, neighbours.
//!
//! One test binary per folder (linking one binary per file cost most of a CI run): each module
//! is named for what it tests, so test paths read `<module>::<test>`. Helpers shared with other
//! binaries stay in `tests/<helper>/` and come in by path.

#[path = "../attack_support/mod.rs"]
mod attack_support;
#[path = "../log_files/mod.rs"]
mod log_files;

mod fd_limit;
mod memory;
mod modbus;
mod neighbours;
mod talos;
