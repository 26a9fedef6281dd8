//! Logs go to a file, never to the terminal (the console owns it). Each part of armjog writes
//! its own file, so the simulator's chatter never hides the console's story and the reverse.

use std::path::PathBuf;

use tracing::Metadata;
use tracing_appender::non_blocking::WorkerGuard;
use tracing_subscriber::EnvFilter;
use tracing_subscriber::filter::{FilterExt, filter_fn};
use tracing_subscriber::layer::SubscriberExt;
use tracing_subscriber::util::SubscriberInitExt;
use tracing_subscriber::{Layer, fmt};

/// The simulator's module path: its events go to the simulator's file, also when the console
/// runs the built-in simulator in its own process.
const SIM_TARGET: &str = "armjog::sim";

/// Which program this process is: it picks the log file(s).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LogRole {
    /// The jog console: `armjog-console.log`, and `armjog-sim.log` for its built-in simulator.
    Console,
    /// `armjog sim`: `armjog-sim.log`.
    Sim,
    /// One-shot commands (`send`, `status`, `modbus`): `armjog-cli.log`.
    Cli,
    /// The stop guard the console starts: `armjog-guard.log`.
    Guard,
}

impl LogRole {
    /// The file everything this role logs goes to, but the simulator's events in the console.
    pub fn file_name(self) -> &'static str {
        match self {
            LogRole::Console => "armjog-console.log",
            LogRole::Sim => SIM_LOG,
            LogRole::Cli => "armjog-cli.log",
            LogRole::Guard => "armjog-guard.log",
        }
    }
}

/// The simulator's log file, standalone or built into the console.
pub const SIM_LOG: &str = "armjog-sim.log";

/// Where logs are written: `$ARMJOG_LOG_DIR`, else the user's state (or local data) directory.
pub fn log_dir() -> Option<PathBuf> {
    if let Some(dir) = std::env::var_os("ARMJOG_LOG_DIR") {
        return Some(PathBuf::from(dir));
    }
    dirs::state_dir()
        .or_else(dirs::data_local_dir)
        .map(|d| d.join("armjog"))
}

/// Whether an event or span comes from the simulator's modules.
fn from_sim(meta: &Metadata<'_>) -> bool {
    is_sim_target(meta.target())
}

fn is_sim_target(target: &str) -> bool {
    target == SIM_TARGET
        || target
            .strip_prefix(SIM_TARGET)
            .is_some_and(|rest| rest.starts_with("::"))
}

/// `ARMJOG_LOG` (default `info`); built once per file, as a filter belongs to one layer.
fn level_filter() -> EnvFilter {
    EnvFilter::try_from_env("ARMJOG_LOG").unwrap_or_else(|_| EnvFilter::new("info"))
}

/// Guards that flush the log files when dropped.
pub struct LogGuards {
    _guards: Vec<WorkerGuard>,
}

/// Starts file logging for `role` (see [`LogRole`]). Filter with `ARMJOG_LOG` (default `info`).
/// Returns the guards that flush on drop, or `None` if no log directory could be made (logging
/// is then off: it must never stop an operator from stopping the arm).
pub fn init(role: LogRole) -> Option<LogGuards> {
    let dir = log_dir()?;
    std::fs::create_dir_all(&dir).ok()?;
    let file =
        |name: &str| tracing_appender::non_blocking(tracing_appender::rolling::never(&dir, name));
    let (own, own_guard) = file(role.file_name());
    if role == LogRole::Console {
        let (sim, sim_guard) = file(SIM_LOG);
        tracing_subscriber::registry()
            .with(
                fmt::layer()
                    .with_writer(own)
                    .with_ansi(false)
                    .with_filter(level_filter().and(filter_fn(|m| !from_sim(m)))),
            )
            .with(
                fmt::layer()
                    .with_writer(sim)
                    .with_ansi(false)
                    .with_filter(level_filter().and(filter_fn(from_sim))),
            )
            .try_init()
            .ok()?;
        return Some(LogGuards {
            _guards: vec![own_guard, sim_guard],
        });
    }
    tracing_subscriber::registry()
        .with(
            fmt::layer()
                .with_writer(own)
                .with_ansi(false)
                .with_filter(level_filter()),
        )
        .try_init()
        .ok()?;
    Some(LogGuards {
        _guards: vec![own_guard],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_sim_modules_count_as_the_sim() {
        let is_sim = is_sim_target;
        assert!(is_sim("armjog::sim"));
        assert!(is_sim("armjog::sim::talos_server"));
        assert!(!is_sim("armjog::simulated"));
        assert!(!is_sim("armjog::link::modbus::task"));
    }

    #[test]
    fn each_role_has_its_own_file() {
        let names =
            [LogRole::Console, LogRole::Sim, LogRole::Cli, LogRole::Guard].map(LogRole::file_name);
        for (i, a) in names.iter().enumerate() {
            for b in &names[i + 1..] {
                assert_ne!(a, b);
            }
        }
    }
}
