//! Logs go to a file, never to the terminal (the console owns it). Each part of armjog writes
//! its own file, so the simulator's chatter never hides the console's story and the reverse.

use std::path::{Path, PathBuf};

use tracing::Metadata;
use tracing_appender::non_blocking::WorkerGuard;
use tracing_appender::rolling::{RollingFileAppender, Rotation};
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
    /// The jog console: `armjog-console.DATE.log`, and `armjog-sim.DATE.log` for its built-in
    /// simulator.
    Console,
    /// `armjog sim`: `armjog-sim.DATE.log`.
    Sim,
    /// One-shot commands (`send`, `status`, `modbus`): `armjog-cli.DATE.log`.
    Cli,
    /// The stop guard the console starts: `armjog-guard.DATE.log`.
    Guard,
}

impl LogRole {
    /// The name the files of everything this role logs start with (all but the simulator's
    /// events in the console): `PREFIX.YYYY-MM-DD.log`.
    pub fn file_prefix(self) -> &'static str {
        match self {
            LogRole::Console => "armjog-console",
            LogRole::Sim => SIM_LOG_PREFIX,
            LogRole::Cli => "armjog-cli",
            LogRole::Guard => "armjog-guard",
        }
    }
}

/// The prefix of the simulator's log files, standalone or built into the console.
pub const SIM_LOG_PREFIX: &str = "armjog-sim";

/// Every log file ends so: `armjog-cli.2026-12-01.log`.
pub const LOG_SUFFIX: &str = "log";

/// Log files roll over at UTC midnight; this many of each program's newest are kept (two
/// weeks of days with a run), older ones deleted as a new one starts.
pub const KEPT_LOG_FILES: usize = 14;

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
    let file = |prefix: &str| {
        daily_files(&dir, prefix)
            .ok()
            .map(tracing_appender::non_blocking)
    };
    let (own, own_guard) = file(role.file_prefix())?;
    if role == LogRole::Console {
        let (sim, sim_guard) = file(SIM_LOG_PREFIX)?;
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

/// `dir/PREFIX.YYYY-MM-DD.log`, a new file each UTC day, the [`KEPT_LOG_FILES`] newest kept.
fn daily_files(
    dir: &Path,
    prefix: &str,
) -> Result<RollingFileAppender, tracing_appender::rolling::InitError> {
    RollingFileAppender::builder()
        .rotation(Rotation::DAILY)
        .filename_prefix(prefix)
        .filename_suffix(LOG_SUFFIX)
        .max_log_files(KEPT_LOG_FILES)
        .build(dir)
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
        let names = [LogRole::Console, LogRole::Sim, LogRole::Cli, LogRole::Guard]
            .map(LogRole::file_prefix);
        // Pruning keeps the newest files whose name starts with a prefix: no prefix may start
        // another, or one program's files would crowd out another's.
        for (i, a) in names.iter().enumerate() {
            for (j, b) in names.iter().enumerate() {
                assert!(i == j || !b.starts_with(a), "{a} prefixes {b}");
            }
        }
    }

    #[test]
    fn files_roll_daily_under_the_prefix_and_the_fourteen_newest_are_kept() {
        let dir = tempfile::tempdir().expect("temp dir");
        let before = time::OffsetDateTime::now_utc().date();
        let mut appender = daily_files(dir.path(), "armjog-test").expect("appender");
        std::io::Write::write_all(&mut appender, b"a line\n").expect("write");
        let after = time::OffsetDateTime::now_utc().date();
        let names: Vec<String> = std::fs::read_dir(dir.path())
            .expect("read dir")
            .filter_map(|e| Some(e.ok()?.file_name().to_str()?.to_string()))
            .collect();
        // By hand: `PREFIX.YYYY-MM-DD.log`, today's UTC date (either side of a midnight).
        let expected = [before, after].map(|d| format!("armjog-test.{d}.log"));
        assert_eq!(names.len(), 1, "{names:?}");
        assert!(expected.contains(&names[0]), "{names:?} vs {expected:?}");
    }

    #[test]
    fn a_start_keeps_the_fourteen_newest_files_of_its_own_prefix_and_nothing_else_is_touched() {
        let dir = tempfile::tempdir().expect("temp dir");
        // Twenty days of old files, created oldest first, and the neighbours of the directory.
        let old: Vec<String> = (1..=20)
            .map(|day| format!("armjog-test.2000-01-{day:02}.log"))
            .collect();
        let neighbours = ["armjog-other.2000-01-01.log", "audit-2000-01-01.jsonl"];
        for name in old.iter().map(String::as_str).chain(neighbours) {
            std::fs::write(dir.path().join(name), "x\n").expect("write");
            // The appender sorts by creation time, which file systems stamp from a coarse
            // clock (a tick of up to 10 ms).
            std::thread::sleep(std::time::Duration::from_millis(25));
        }
        let _appender = daily_files(dir.path(), "armjog-test").expect("appender");
        let mut names: Vec<String> = std::fs::read_dir(dir.path())
            .expect("read dir")
            .filter_map(|e| Some(e.ok()?.file_name().to_str()?.to_string()))
            .collect();
        names.sort();
        let today = names
            .iter()
            .filter(|n| n.starts_with("armjog-test.") && !n.starts_with("armjog-test.2000-"))
            .count();
        assert_eq!(today, 1, "{names:?}");
        // Thirteen old ones (the newest: days 8 to 20) and today's make fourteen.
        let kept: Vec<&String> = names
            .iter()
            .filter(|n| n.starts_with("armjog-test.2000-"))
            .collect();
        assert_eq!(kept, old[7..].iter().collect::<Vec<_>>(), "{names:?}");
        for neighbour in neighbours {
            assert!(
                names.iter().any(|n| n == neighbour),
                "{neighbour} removed: {names:?}"
            );
        }
    }
}
