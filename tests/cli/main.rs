//! The command line: `armjog send`, `status`, `modbus`, arm profiles, `sim`'s options, the file
//! limits and the guard.
//!
//! One test binary per folder (linking one binary per file cost most of a CI run): each module
//! is named for what it tests, so test paths read `<module>::<test>`. Helpers shared with other
//! binaries stay in `tests/<helper>/` and come in by path.

#[path = "../common/mod.rs"]
mod common;
#[path = "../guard_support/mod.rs"]
mod guard_support;
#[path = "../log_files/mod.rs"]
mod log_files;
#[path = "../modbus_fake/mod.rs"]
mod modbus_fake;
// Shared with the attack tests, which use the rest of it.
#[allow(dead_code)]
#[path = "../attack_support/process.rs"]
mod sim_process;

mod armjog_run;
mod broken_pipe;
mod doc_links;
mod errors;
mod file_limits;
mod guard;
mod guard_console;
mod guard_kill;
mod guard_talos;
mod logs;
mod modbus;
mod modbus_home;
mod options;
mod outside_text;
mod profile_commands;
mod profile_fence;
mod profile_precedence;
mod profile_values;
mod profiles;
mod replay;
mod send;
mod sim_args_near_limit;
mod sim_args_near_singularity;
mod stored;
mod stored_limits;
mod version;
