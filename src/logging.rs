//! Logs go to files, never the terminal the console owns; a file per part of armjog.

use std::path::{Path, PathBuf};

use tracing::Metadata;
use tracing_appender::non_blocking::WorkerGuard;
use tracing_appender::rolling::{RollingFileAppender, Rotation};
use tracing_subscriber::EnvFilter;
use tracing_subscriber::filter::{FilterExt, filter_fn};
use tracing_subscriber::layer::SubscriberExt;
use tracing_subscriber::util::SubscriberInitExt;
use tracing_subscriber::{Layer, fmt};

/// The simulator's events go to its own file, also when built into the console.
const SIM_TARGET: &str = "armjog::sim";

/// Which program this process is: it picks the log file(s).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LogRole {
    /// The console: `armjog-console.DATE.log`, and `armjog-sim.DATE.log` for its simulator.
    Console,
    /// `armjog sim`: `armjog-sim.DATE.log`.
    Sim,
    /// One-shot commands (`send`, `status`, `modbus`): `armjog-cli.DATE.log`.
    Cli,
    /// The stop guard the console starts: `armjog-guard.DATE.log`.
    Guard,
}

impl LogRole {
    /// The prefix of this role's files (`PREFIX.YYYY-MM-DD.log`).
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

/// Log files roll over at UTC midnight; this many of each program's newest are kept. Newest by the
/// date in the name (`PREFIX.YYYY-MM-DD.log`), never the file's times (a restored file has new
/// ones).
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

/// Starts file logging for `role` ([`LogRole`]), filtered by `ARMJOG_LOG` (default `info`). Returns
/// the flush guards, or `None` if no log directory could be made: logging is then off, as it must
/// never stop an operator from stopping the arm.
pub fn init(role: LogRole) -> Option<LogGuards> {
    let dir = log_dir()?;
    std::fs::create_dir_all(&dir).ok()?;
    let file = |prefix: &str| {
        daily_files(&dir, prefix)
            .ok()
            .map(tracing_appender::non_blocking)
    };
    let (own, own_guard) = file(role.file_prefix())?;
    let mut guards = vec![own_guard];
    // The console's simulator logs to its own file, not the console's.
    let console = role == LogRole::Console;
    let sim = match console {
        true => {
            let (sim, sim_guard) = file(SIM_LOG_PREFIX)?;
            guards.push(sim_guard);
            Some(plain(sim).with_filter(level_filter().and(filter_fn(from_sim))))
        }
        false => None,
    };
    let own_events = filter_fn(move |m| !console || !from_sim(m));
    tracing_subscriber::registry()
        .with(plain(own).with_filter(level_filter().and(own_events)))
        .with(sim)
        .try_init()
        .ok()?;
    Some(LogGuards { _guards: guards })
}

/// A plain-text layer writing to `writer`.
fn plain<S, W>(writer: W) -> fmt::Layer<S, fmt::format::DefaultFields, fmt::format::Format, W>
where
    W: for<'w> fmt::MakeWriter<'w> + 'static,
{
    fmt::layer().with_writer(writer).with_ansi(false)
}

/// `dir/PREFIX.YYYY-MM-DD.log`, a file per UTC day, the [`KEPT_LOG_FILES`] newest kept (pruned now
/// and each new day). tracing-appender's own pruning goes by creation times and would delete any
/// file whose name merely starts with the prefix.
fn daily_files(
    dir: &Path,
    prefix: &str,
) -> Result<PrunedDaily, tracing_appender::rolling::InitError> {
    let appender = RollingFileAppender::builder()
        .rotation(Rotation::DAILY)
        .filename_prefix(prefix)
        .filename_suffix(LOG_SUFFIX)
        .build(dir)?;
    let mut files = PrunedDaily {
        appender,
        dir: dir.to_path_buf(),
        prefix: prefix.to_string(),
        pruned_on: None,
    };
    files.note_day(today());
    Ok(files)
}

/// Today's UTC date: the day the appender names its file after.
fn today() -> time::Date {
    time::OffsetDateTime::now_utc().date()
}

/// The daily files, pruned once each day they are written on.
struct PrunedDaily {
    appender: RollingFileAppender,
    dir: PathBuf,
    prefix: String,
    pruned_on: Option<time::Date>,
}

impl PrunedDaily {
    /// Prunes the directory when `day` is a day not pruned yet (a new file has started).
    fn note_day(&mut self, day: time::Date) {
        if self.pruned_on != Some(day) {
            self.pruned_on = Some(day);
            prune(&self.dir, &self.prefix, day, KEPT_LOG_FILES);
        }
    }
}

impl std::io::Write for PrunedDaily {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        // The appender starts the day's file as it writes; it is pruned after.
        let written = self.appender.write(buf)?;
        self.note_day(today());
        Ok(written)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.appender.flush()
    }
}

/// The real date in `PREFIX.YYYY-MM-DD.log`; `None` for any other name (never touched).
fn dated(name: &str, prefix: &str) -> Option<time::Date> {
    let date = name
        .strip_prefix(prefix)?
        .strip_prefix('.')?
        .strip_suffix(LOG_SUFFIX)?
        .strip_suffix('.')?;
    let digits = |s: &str, n: usize| s.len() == n && s.bytes().all(|b| b.is_ascii_digit());
    let mut parts = date.split('-');
    let (year, month, day) = (parts.next()?, parts.next()?, parts.next()?);
    if parts.next().is_some() || !digits(year, 4) || !digits(month, 2) || !digits(day, 2) {
        return None;
    }
    let month = time::Month::try_from(month.parse::<u8>().ok()?).ok()?;
    time::Date::from_calendar_date(year.parse().ok()?, month, day.parse().ok()?).ok()
}

/// Which of `names` to delete so `prefix`'s `keep` newest remain; never `today`'s.
fn to_delete<'a>(
    names: impl IntoIterator<Item = &'a str>,
    prefix: &str,
    today: time::Date,
    keep: usize,
) -> Vec<&'a str> {
    let mut daily: Vec<(time::Date, &str)> = names
        .into_iter()
        .filter_map(|name| Some((dated(name, prefix)?, name)))
        .collect();
    daily.sort_unstable_by(|a, b| b.cmp(a));
    let keep_others = if daily.iter().any(|(date, _)| *date == today) {
        keep.saturating_sub(1)
    } else {
        keep
    };
    daily
        .into_iter()
        .filter(|(date, _)| *date != today)
        .skip(keep_others)
        .map(|(_, name)| name)
        .collect()
}

/// Deletes `prefix`'s files beyond the `keep` newest ([`to_delete`]); failures ignored.
fn prune(dir: &Path, prefix: &str, today: time::Date, keep: usize) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let names: Vec<String> = entries
        .filter_map(Result::ok)
        .filter(|e| e.file_type().is_ok_and(|t| t.is_file()))
        .filter_map(|e| e.file_name().into_string().ok())
        .collect();
    for name in to_delete(names.iter().map(String::as_str), prefix, today, keep) {
        let _ = std::fs::remove_file(dir.join(name));
    }
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
    fn a_start_keeps_the_fourteen_newest_files_by_their_names_dates_and_nothing_else_is_touched() {
        let dir = tempfile::tempdir().expect("temp dir");
        // Twenty days of old files, created newest first (as a copy or a restore may make
        // them), and the neighbours of the directory: other programs' files, the audit, and
        // names that only look like the prefix's.
        let old: Vec<String> = (1..=20)
            .map(|day| format!("armjog-test.2000-01-{day:02}.log"))
            .collect();
        let neighbours = [
            "armjog-other.2000-01-01.log",
            "audit-2000-01-01.jsonl",
            "armjog-test.log",
            "armjog-test.notes.log",
            "armjog-test.2000-02-30.log",
            "armjog-test.1999-1-01.log",
            "armjog-test.1999-01-01.log.gz",
            "armjog-test-old.1999-01-01.log",
        ];
        for name in neighbours
            .iter()
            .copied()
            .chain(old.iter().rev().map(String::as_str))
        {
            std::fs::write(dir.path().join(name), "x\n").expect("write");
            // Creation times come from a coarse clock (a tick of up to 10 ms): apart, so that
            // pruning by them would keep the wrong files.
            std::thread::sleep(std::time::Duration::from_millis(25));
        }
        // A directory of a daily file's name is not a file to delete.
        std::fs::create_dir(dir.path().join("armjog-test.1998-01-01.log")).expect("mkdir");
        let _appender = daily_files(dir.path(), "armjog-test").expect("appender");
        let mut names: Vec<String> = std::fs::read_dir(dir.path())
            .expect("read dir")
            .filter_map(|e| Some(e.ok()?.file_name().to_str()?.to_string()))
            .collect();
        names.sort();
        let today = format!("armjog-test.{}.log", today());
        assert!(names.contains(&today), "{names:?}");
        // Thirteen old ones (the newest by name: days 8 to 20) and today's make fourteen.
        let kept: Vec<&String> = names
            .iter()
            .filter(|n| n.starts_with("armjog-test.2000-01-"))
            .collect();
        assert_eq!(kept, old[7..].iter().collect::<Vec<_>>(), "{names:?}");
        for neighbour in neighbours.iter().chain(&["armjog-test.1998-01-01.log"]) {
            assert!(
                names.iter().any(|n| n == neighbour),
                "{neighbour} removed: {names:?}"
            );
        }
    }

    fn date(y: i32, m: u8, d: u8) -> time::Date {
        time::Date::from_calendar_date(y, time::Month::try_from(m).expect("month"), d)
            .expect("date")
    }

    #[test]
    fn only_real_dates_in_the_exact_pattern_count() {
        let p = "armjog-cli";
        assert_eq!(
            dated("armjog-cli.2026-11-01.log", p),
            Some(date(2026, 11, 1))
        );
        for other in [
            "armjog-cli.log",
            "armjog-cli.2026-11-01.log.1",
            "armjog-cli.2026-11-31.log",
            "armjog-cli.2026-1-01.log",
            "armjog-cli.+2026-11-01.log",
            "armjog-cli.2026-11-01-01.log",
            "armjog-cli-2026-11-01.log",
            "armjog-cli.x.2026-11-01.log",
            "armjog-cli2.2026-11-01.log",
        ] {
            assert_eq!(dated(other, p), None, "{other}");
        }
    }

    #[test]
    fn the_oldest_by_name_go_and_todays_file_stays() {
        let names: Vec<String> = (1..=20).map(|d| format!("p.2026-11-{d:02}.log")).collect();
        let names = || names.iter().map(String::as_str);
        // Today among them: it and the 13 newest others stay.
        let gone = to_delete(names(), "p", date(2026, 11, 20), 14);
        assert_eq!(gone, names().take(6).rev().collect::<Vec<_>>());
        // Today's file not written yet: the 14 newest stay.
        let gone = to_delete(names(), "p", date(2026, 12, 1), 14);
        assert_eq!(gone, names().take(6).rev().collect::<Vec<_>>());
        // Files dated after today (a clock set wrong once) never push today's out.
        let gone = to_delete(names(), "p", date(2026, 11, 1), 3);
        assert!(!gone.contains(&"p.2026-11-01.log"), "{gone:?}");
        assert_eq!(gone.len(), 17, "{gone:?}");
    }

    #[test]
    fn a_new_day_prunes_again() {
        let dir = tempfile::tempdir().expect("temp dir");
        let mut files = daily_files(dir.path(), "armjog-test").expect("appender");
        for day in 1..=20 {
            let name = format!("armjog-test.2000-01-{day:02}.log");
            std::fs::write(dir.path().join(name), "x\n").expect("write");
        }
        // The same day: nothing more is pruned.
        files.note_day(today());
        let count = || std::fs::read_dir(dir.path()).expect("read dir").count();
        assert_eq!(count(), 21);
        files.note_day(today().next_day().expect("a next day"));
        assert_eq!(count(), KEPT_LOG_FILES);
    }
}
