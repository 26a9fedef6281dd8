//! Logs go to a file, never to the terminal (the console owns it).

use std::path::PathBuf;

use tracing_appender::non_blocking::WorkerGuard;
use tracing_subscriber::EnvFilter;

/// Where logs are written: `$ARMJOG_LOG_DIR`, else the user's state (or local data) directory.
pub fn log_dir() -> Option<PathBuf> {
    if let Some(dir) = std::env::var_os("ARMJOG_LOG_DIR") {
        return Some(PathBuf::from(dir));
    }
    dirs::state_dir()
        .or_else(dirs::data_local_dir)
        .map(|d| d.join("armjog"))
}

/// Starts file logging to `armjog.log`. Filter with `ARMJOG_LOG` (default `info`). Returns the
/// guard that flushes on drop, or `None` if no log directory could be made (logging is then off:
/// it must never stop an operator from stopping the arm).
pub fn init() -> Option<WorkerGuard> {
    let dir = log_dir()?;
    std::fs::create_dir_all(&dir).ok()?;
    let appender = tracing_appender::rolling::never(&dir, "armjog.log");
    let (writer, guard) = tracing_appender::non_blocking(appender);
    let filter = EnvFilter::try_from_env("ARMJOG_LOG").unwrap_or_else(|_| EnvFilter::new("info"));
    tracing_subscriber::fmt()
        .with_writer(writer)
        .with_ansi(false)
        .with_env_filter(filter)
        .try_init()
        .ok()?;
    Some(guard)
}
