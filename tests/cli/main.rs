//! The command line: `armjog send`, `status`, `modbus`, arm profiles, the file limits, the
//! guard, and the layering rules of the source tree.
//!
//! One test binary for several former ones (linking one binary per file cost most of a CI
//! run): each module is one former `tests/<name>.rs`, so test paths read `<name>::<test>`.
//! Helpers shared with other binaries stay in `tests/<helper>/` and come in by path.

#[path = "../common/mod.rs"]
mod common;
#[path = "../guard_support/mod.rs"]
mod guard_support;
#[path = "../layers_scan/mod.rs"]
mod layers_scan;
#[path = "../modbus_fake/mod.rs"]
mod modbus_fake;

mod armjog_run;
mod cli_broken_pipe;
mod cli_errors;
mod cli_logs;
mod cli_options;
mod cli_send;
mod file_limits;
mod guard;
mod guard_console;
mod layers;
mod modbus_cli;
mod profiles;
mod sim_near_limit;
mod sim_near_singularity;
