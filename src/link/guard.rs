//! The stop guard, console side: a small process (`armjog guard`, `src/cli/guard.rs`) that stops
//! the arm on every link when the console dies, since a console killed outright runs no code and
//! neither link stops a motion on its own (no Modbus twist watchdog; a Talos go-to runs on after a
//! disconnect). It watches a pipe on its stdin: closed, it stops the arm and exits; no heartbeat
//! for [`HEARTBEAT_TIMEOUT`] (a frozen console), it stops the arm and keeps watching.
//!
//! The guard answers `ready`, `alive`, `down REASON`, `stopped REASON` and `stop-failed REASON` on
//! its stdout. No motion starts while no guard is ready ([`GuardSupervisor::refusal`]); a ready
//! guard silent for [`GUARD_SILENCE`] is ended and replaced. Over Talos it connects only once the
//! console's connection is gone (the operator serves one client at a time). It runs in its own
//! process group so a Ctrl-C aimed at the console does not take it down first. Details:
//! `docs/safety.md`, "the stop guard".

use std::path::PathBuf;
use std::process::Stdio;
use std::time::Duration;

use tokio::io::{AsyncBufReadExt, AsyncWriteExt, BufReader};
use tokio::process::{Child, ChildStdin, Command};
use tokio::sync::{mpsc, oneshot, watch};

use super::interface::{ArmError, ArmEvent, CommandKind, GuardStatus};
use super::{ModbusConfig, TalosConfig};
use crate::net::Deadline;

/// The byte the console writes to keep the guard from stopping the arm.
pub const HEARTBEAT: u8 = b'.';
/// Four beats in [`HEARTBEAT_TIMEOUT`]: three late or lost in a row still leave the arm alone.
pub const HEARTBEAT_PERIOD: Duration = Duration::from_millis(250);
/// A console silent this long is taken as frozen: the guard stops the arm.
pub const HEARTBEAT_TIMEOUT: Duration = Duration::from_secs(1);
/// How often a ready guard says `alive`.
pub const ALIVE_PERIOD: Duration = Duration::from_millis(500);
/// Silent this long, a guard is frozen; longer than its 3 s of stop retries.
pub const GUARD_SILENCE: Duration = Duration::from_secs(5);
/// First delay before restarting a guard that died; doubled up to [`RESTART_MAX_DELAY`].
const RESTART_DELAY: Duration = Duration::from_millis(500);
const RESTART_MAX_DELAY: Duration = Duration::from_secs(5);
/// A guard ready this long counts as healthy: the next restart starts with the short delay.
const HEALTHY_AFTER: Duration = Duration::from_secs(10);
/// A heartbeat the pipe does not take within this long means the guard no longer reads it.
const WRITE_TIMEOUT: Duration = Duration::from_secs(1);

/// Whether the driver starts a stop guard for its links.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum GuardPolicy {
    /// Start this program as `PROGRAM guard` with the links' addresses ([`guard_args`]; the
    /// armjog binary: `std::env::current_exe()` in the console, `CARGO_BIN_EXE_armjog` in tests).
    Spawn(PathBuf),
    /// No guard: an in-process simulated arm dies with the console; tests may opt out.
    NotNeeded,
}

/// The guard's command line for the console's links: `guard --modbus ADDR --unit N` and
/// `--talos ADDR --dialect D --checksum C --oid N`, as the console speaks to each.
pub fn guard_args(
    talos: Option<&TalosConfig>,
    modbus: Option<&ModbusConfig>,
    oid: u16,
) -> Vec<String> {
    let mut args = vec!["guard".to_string()];
    if let Some(mc) = modbus {
        let unit = mc.unit.to_string();
        args.extend(["--modbus", &mc.addr, "--unit", &unit].map(String::from));
    }
    if let Some(tc) = talos {
        args.extend([
            "--talos".into(),
            tc.addr.clone(),
            "--dialect".into(),
            tc.dialect.to_string(),
            "--checksum".into(),
            tc.checksum.to_string(),
            "--oid".into(),
            oid.to_string(),
        ]);
    }
    args
}

/// What the supervisor tells the driver.
#[derive(Debug, Clone, PartialEq)]
pub enum GuardReport {
    Status(GuardStatus),
    /// The guard wrote a stop on its own (it missed the heartbeat).
    StoppedArm {
        reason: String,
    },
    /// The guard tried to stop the arm on its own and could not: never said as a stop.
    StopFailed {
        reason: String,
    },
}

impl GuardReport {
    /// Whether the driver must stop motion: with the guard down nothing stops the arm if the
    /// console dies, and after the guard's own stop no motion may be believed running. (`Starting`
    /// needs no stop of its own, which could cut into another client's motion.)
    pub fn stops_motion(&self) -> bool {
        matches!(
            self,
            GuardReport::Status(GuardStatus::Down { .. })
                | GuardReport::StoppedArm { .. }
                | GuardReport::StopFailed { .. }
        )
    }

    /// The event the console sees.
    pub fn into_event(self) -> ArmEvent {
        let error = match self {
            GuardReport::Status(status) => return ArmEvent::Guard(status),
            GuardReport::StoppedArm { reason } => ArmError::GuardStoppedArm(reason),
            GuardReport::StopFailed { reason } => ArmError::GuardStopFailed(reason),
        };
        // As a failed jog: the console stops and forgets the held keys.
        let command = CommandKind::Jog;
        ArmEvent::Failed { command, error }
    }
}

/// Starts the guard, watches it, restarts it when it dies. Dropping it ends the guard.
#[derive(Debug)]
pub struct GuardSupervisor {
    status: watch::Receiver<GuardStatus>,
    _shutdown: oneshot::Sender<()>,
}

impl GuardSupervisor {
    /// Starts `program ARGS` ([`guard_args`]); reports every change of state.
    pub fn spawn(
        program: PathBuf,
        args: Vec<String>,
        reports: mpsc::UnboundedSender<GuardReport>,
    ) -> GuardSupervisor {
        let (status_tx, status) = watch::channel(GuardStatus::Starting);
        let (shutdown_tx, shutdown) = oneshot::channel();
        let reporter = Reporter {
            status: status_tx,
            reports,
        };
        tokio::spawn(supervise(program, args, reporter, shutdown));
        GuardSupervisor {
            status,
            _shutdown: shutdown_tx,
        }
    }

    /// Why motion is refused now, on any link, or `None` when the guard is ready.
    pub fn refusal(&self) -> Option<GuardNotRunning> {
        match &*self.status.borrow() {
            GuardStatus::Ready { .. } => None,
            GuardStatus::Starting => Some(GuardNotRunning::Starting),
            GuardStatus::Down { reason } => Some(GuardNotRunning::Down(reason.clone())),
        }
    }
}

/// Why no stop guard stands ready: no motion starts, on any link.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GuardNotRunning {
    #[error("stop guard not running: still starting")]
    Starting,
    /// The guard's [`GuardStatus::Down`] reason.
    #[error("stop guard not running: {0}")]
    Down(String),
    #[error("stop guard not running: none was started for this link")]
    NoneStarted,
}

struct Reporter {
    status: watch::Sender<GuardStatus>,
    reports: mpsc::UnboundedSender<GuardReport>,
}

impl Reporter {
    fn status(&self, status: GuardStatus) {
        if *self.status.borrow() == status {
            return;
        }
        match &status {
            GuardStatus::Down { reason } => tracing::error!("stop guard down: {reason}"),
            other => tracing::info!("stop guard: {other:?}"),
        }
        self.status.send_replace(status.clone());
        let _ = self.reports.send(GuardReport::Status(status));
    }
}

async fn supervise(
    program: PathBuf,
    args: Vec<String>,
    reporter: Reporter,
    mut shutdown: oneshot::Receiver<()>,
) {
    let mut delay = RESTART_DELAY;
    loop {
        reporter.status(GuardStatus::Starting);
        let started = tokio::time::Instant::now();
        // Dropping `run_once` (on shutdown) drops the pipe: the guard stops the arm and exits.
        let ended = tokio::select! {
            reason = run_once(&program, &args, &reporter) => reason,
            _ = &mut shutdown => return,
        };
        if started.elapsed() >= HEALTHY_AFTER {
            delay = RESTART_DELAY;
        }
        reporter.status(GuardStatus::Down {
            reason: format!("{ended}; restarting it in {:.1} s", delay.as_secs_f64()),
        });
        tokio::select! {
            _ = tokio::time::sleep(delay) => {}
            _ = &mut shutdown => return,
        }
        delay = (delay * 2).min(RESTART_MAX_DELAY);
    }
}

/// Runs one guard process until it ends; returns why it ended.
async fn run_once(program: &PathBuf, args: &[String], reporter: &Reporter) -> String {
    let spawned = Command::new(program)
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        // Its own process group: Ctrl-C or a group kill aimed at the console spares it.
        .process_group(0)
        .kill_on_drop(false)
        .spawn();
    let mut child = match spawned {
        Ok(child) => child,
        Err(e) => return format!("cannot start the stop guard {}: {e}", program.display()),
    };
    let pid = child.id().unwrap_or(0);
    let (Some(mut stdin), Some(stdout)) = (child.stdin.take(), child.stdout.take()) else {
        return "the stop guard's pipes were not set up".into();
    };
    if let Some(stderr) = child.stderr.take() {
        tokio::spawn(async move {
            let mut lines = BufReader::new(stderr).lines();
            while let Ok(Some(line)) = lines.next_line().await {
                tracing::warn!("stop guard {pid} stderr: {line}");
            }
        });
    }
    let mut lines = BufReader::new(stdout).lines();
    let mut beat = tokio::time::interval(HEARTBEAT_PERIOD);
    beat.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    // Armed once the guard is ready: from then on it speaks at least every ALIVE_PERIOD.
    let mut heard: Option<tokio::time::Instant> = None;
    let mut silent_until = Deadline::new();
    loop {
        silent_until.set(heard.map(|at| at + GUARD_SILENCE));
        tokio::select! {
            _ = silent_until.fired(), if silent_until.armed() => {
                let silence = format!(
                    "the stop guard {pid} stopped answering for {} s",
                    GUARD_SILENCE.as_secs()
                );
                return end(child, stdin, silence).await;
            }
            _ = beat.tick() => {
                if let Err(reason) = heartbeat(&mut stdin).await {
                    let reason = format!("the stop guard {pid} stopped reading: {reason}");
                    return end(child, stdin, reason).await;
                }
            }
            line = lines.next_line() => match line {
                Ok(Some(line)) => {
                    on_line(&line, pid, reporter);
                    if heard.is_some() || reporter.status.borrow().is_ready() {
                        heard = Some(tokio::time::Instant::now());
                    }
                }
                Ok(None) | Err(_) => {
                    let reason = format!("the stop guard {pid} closed its output");
                    return end(child, stdin, reason).await;
                }
            },
            status = child.wait() => {
                return match status {
                    Ok(status) => format!("the stop guard {pid} exited ({status})"),
                    Err(e) => format!("the stop guard {pid} cannot be watched: {e}"),
                };
            }
        }
    }
}

async fn heartbeat(stdin: &mut ChildStdin) -> std::io::Result<()> {
    let write = async {
        stdin.write_all(&[HEARTBEAT]).await?;
        stdin.flush().await
    };
    tokio::time::timeout(WRITE_TIMEOUT, write)
        .await
        .unwrap_or_else(|_| {
            let words = format!("the pipe took no byte for {WRITE_TIMEOUT:?}");
            Err(std::io::Error::new(std::io::ErrorKind::TimedOut, words))
        })
}

/// Ends a silent guard (stdin dropped first, so a live one stops the arm).
async fn end(mut child: Child, stdin: ChildStdin, reason: String) -> String {
    drop(stdin);
    if tokio::time::timeout(Duration::from_secs(1), child.wait())
        .await
        .is_err()
    {
        let _ = child.start_kill();
        let _ = tokio::time::timeout(Duration::from_secs(1), child.wait()).await;
    }
    reason
}

fn on_line(line: &str, pid: u32, reporter: &Reporter) {
    let (word, rest) = line.split_once(' ').unwrap_or((line, ""));
    match word {
        "ready" => reporter.status(GuardStatus::Ready { pid }),
        "alive" => {}
        "down" => reporter.status(GuardStatus::Down {
            reason: format!("the stop guard cannot reach the arm: {rest}"),
        }),
        "stopped" => {
            tracing::warn!("stop guard {pid} stopped the arm: {rest}");
            let reason = rest.to_string();
            let _ = reporter.reports.send(GuardReport::StoppedArm { reason });
        }
        "stop-failed" => {
            tracing::error!("stop guard {pid} could not stop the arm: {rest}");
            let reason = rest.to_string();
            let _ = reporter.reports.send(GuardReport::StopFailed { reason });
        }
        _ => tracing::info!("stop guard {pid}: {line}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_guard_is_told_every_link_as_the_console_speaks_to_it() {
        use crate::link::Dialect;
        use crate::talos::Checksum;
        let mut modbus = ModbusConfig::new("10.0.0.9:502");
        modbus.unit = 3;
        let mut talos = TalosConfig::new("10.0.0.8:61616");
        talos.dialect = Dialect::Ack;
        talos.checksum = Checksum::Xor8;
        assert_eq!(
            guard_args(None, Some(&modbus), 0),
            ["guard", "--modbus", "10.0.0.9:502", "--unit", "3"]
        );
        assert_eq!(
            guard_args(Some(&talos), None, 7),
            [
                "guard",
                "--talos",
                "10.0.0.8:61616",
                "--dialect",
                "ack",
                "--checksum",
                "xor8",
                "--oid",
                "7"
            ]
        );
        let both = guard_args(Some(&talos), Some(&modbus), 0);
        assert!(both.contains(&"--modbus".to_string()) && both.contains(&"--talos".to_string()));
    }

    #[test]
    fn a_guard_is_required_for_every_real_link() {
        use crate::link::Dialect;
        use crate::link::driver::DriverConfig;
        let modbus = || Some(ModbusConfig::new("10.0.0.9:502"));
        let talos = |dialect| {
            let mut t = TalosConfig::new("10.0.0.8:61616");
            t.dialect = dialect;
            Some(t)
        };
        let spawn = GuardPolicy::Spawn(PathBuf::from("/usr/bin/armjog"));
        let required = |t: Option<TalosConfig>, m: Option<ModbusConfig>, g: &GuardPolicy| {
            let mut config = DriverConfig::new(t, m);
            config.guard = g.clone();
            config.guard_required()
        };
        assert!(required(None, modbus(), &spawn), "Modbus-only jogs");
        assert!(
            required(talos(Dialect::Icd), modbus(), &spawn),
            "both links"
        );
        assert!(
            required(talos(Dialect::Icd), None, &spawn),
            "go-to, home and steps over Talos have no watchdog"
        );
        assert!(required(talos(Dialect::Ack), None, &spawn), "home and pans");
        assert!(!required(None, modbus(), &GuardPolicy::NotNeeded));
        assert!(!required(
            talos(Dialect::Icd),
            None,
            &GuardPolicy::NotNeeded
        ));
    }

    #[test]
    fn a_guard_going_down_or_stopping_the_arm_stops_motion() {
        assert!(!GuardReport::Status(GuardStatus::Ready { pid: 7 }).stops_motion());
        assert!(!GuardReport::Status(GuardStatus::Starting).stops_motion());
        let down = GuardStatus::Down {
            reason: "exited".into(),
        };
        assert!(GuardReport::Status(down).stops_motion());
        let stopped = GuardReport::StoppedArm {
            reason: "no heartbeat".into(),
        };
        assert!(stopped.stops_motion());
        assert!(matches!(
            stopped.into_event(),
            ArmEvent::Failed {
                command: CommandKind::Jog,
                error: ArmError::GuardStoppedArm(reason),
            } if reason.contains("no heartbeat")
        ));
        let failed = GuardReport::StopFailed {
            reason: "not answered".into(),
        };
        assert!(failed.stops_motion());
        let ArmEvent::Failed { command, error } = failed.into_event() else {
            panic!("a failed jog");
        };
        assert_eq!(command, CommandKind::Jog);
        assert_eq!(
            error.to_string(),
            "the stop guard could NOT stop the arm, it may still be moving: not answered"
        );
    }
}
