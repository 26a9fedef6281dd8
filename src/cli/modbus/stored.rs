//! `armjog modbus home|action|sequence`: one capped path, waited to its end ([`StoredRun`]).

use std::time::{Duration, Instant};

use clap::Args;

use super::{EXIT_EXCEPTION, ModbusArgs, ModbusCommand, render};
use crate::cli::Outcome;
use crate::kortex::{Progress, SpeedLimits, Stored, StoredRun, Telemetry, fault_reason};
use crate::link::ModbusLink;
use crate::link::modbus::ModbusError;
use crate::link::speed::SpeedCap;

/// How a stored motion is waited for and capped.
#[derive(Debug, Clone, Args)]
pub struct StoredOptions {
    /// Return once it is started, without waiting for its end. Nothing is left to put the arm's
    /// speed limits back then, so neither is lowered: the run is refused (exit 1) when the
    /// arm's linear limit is above --max-jog-speed or its angular limit above the turn rate
    /// (30 deg/s).
    #[arg(long)]
    pub no_wait: bool,
    /// Longest wait for the end, seconds: past it the motion is stopped and the exit status
    /// is 1.
    #[arg(long, default_value_t = 60.0, value_name = "S")]
    pub wait_timeout: f64,
    /// The tool speed cap, mm/s (the console's): while the motion runs the arm's linear speed
    /// limit is lowered to it and its angular limit to the turn rate (30 deg/s, the console's
    /// at 100 %), never raised, and both are put back at its end.
    #[arg(long, default_value_t = 250.0, value_name = "MM_S", value_parser = crate::cli::values::tool_speed)]
    pub max_jog_speed: f64,
}

/// A `--wait-timeout` no run could have.
#[derive(Debug, thiserror::Error)]
#[error("--wait-timeout {0}: must be above 0 and at most 86400 s")]
pub struct BadWaitTimeout(f64);

impl StoredOptions {
    /// Refuses values a technician could get wrong, before anything connects.
    pub fn check(&self) -> Result<(), BadWaitTimeout> {
        let timeout = self.wait_timeout;
        let sane = timeout.is_finite() && timeout > 0.0 && timeout <= 86_400.0;
        sane.then_some(()).ok_or(BadWaitTimeout(timeout))
    }

    /// The cap as the arm's limits for the run (m/s, deg/s), at full speed (these commands have no
    /// speed setting).
    pub fn cap(&self) -> SpeedLimits {
        // The option's parser took only a speed a cap may be (`cli::values::tool_speed`).
        SpeedCap::configured(self.max_jog_speed / 1000.0).move_cap(FULL_SPEED)
    }
}

/// The percentage of --max-jog-speed a run is capped at: all of it.
const FULL_SPEED: u8 = 100;

/// How often the end is polled.
const POLL: Duration = Duration::from_millis(100);

/// The run as messages name it: `home`, or `action 5`, `sequence 1`.
struct Named {
    stored: Stored,
    home: bool,
}

impl Named {
    fn completed(&self, took: Duration) -> String {
        let (name, secs) = (self.name(), took.as_secs_f64());
        let colon = if self.home { ":" } else { "" };
        format!("{name}{colon} completed in {secs:.1} s")
    }

    fn failed(&self, why: &str) -> String {
        format!("{} failed: {why}", self.name())
    }

    fn name(&self) -> String {
        match self.home {
            true => "home".into(),
            false => self.stored.to_string(),
        }
    }

    /// The message of a run that ended other than completed.
    fn failure(&self, progress: &Progress) -> Option<String> {
        match progress {
            // `aborted, J4 at its limit`
            Progress::Aborted(reason) if !self.home => Some(format!("{} {reason}", self.stored)),
            // `the arm did not take sequence 9: ...`
            Progress::NotTaken(sentence) if !self.home => Some(sentence.clone()),
            Progress::Aborted(why) | Progress::NotTaken(why) | Progress::Fault(why) => {
                Some(self.failed(why))
            }
            // `action 5 failed: MOVED BY ANOTHER CLIENT: the arm runs action 3, not our action 5`
            Progress::OtherMove(which) => {
                Some(self.failed(&format!("MOVED BY ANOTHER CLIENT: {which}")))
            }
            Progress::Pending | Progress::Started | Progress::Running | Progress::Completed => None,
        }
    }
}

/// How a waited run ended.
enum End {
    Completed(Duration),
    Failed(String),
}

/// Refuses an arm in fault, starts the run capped and (unless told not to) waits for its end.
pub(super) async fn run(
    args: &ModbusArgs,
    link: &ModbusLink,
    stored: Stored,
    options: &StoredOptions,
) -> Outcome {
    let named = Named {
        stored,
        home: matches!(args.command, ModbusCommand::Home { .. }),
    };
    let failed = |message: String, stdout: Vec<String>| Outcome {
        stdout,
        stderr: Some(message),
        exit_code: EXIT_EXCEPTION,
    };
    let t = match link.read_telemetry().await {
        Ok(t) => t,
        Err(e) => return Outcome::failed(&e),
    };
    if let Some(fault) = fault_reason(&t) {
        return failed(named.failed(&format!("{fault}; not started")), Vec::new());
    }
    if options.no_wait {
        return start_unwatched(args, link, &named, options, &t).await;
    }
    let report = match args.command.send(link).await {
        Ok(report) => report,
        Err(e) => return Outcome::failed(&e),
    };
    let timeout = Duration::from_secs_f64(options.wait_timeout);
    match wait_for_end(link, &named, timeout).await {
        Ok(End::Completed(took)) => {
            let mut stdout = render(args, &report, Some("completed"));
            if !args.json {
                stdout.push(named.completed(took));
            }
            Outcome::printed(stdout)
        }
        Ok(End::Failed(message)) => failed(message, render(args, &report, Some("failed"))),
        Err(e) => Outcome::failed(&e),
    }
}

/// `--no-wait`: nothing puts limits back, so it starts only if the arm's limits keep the cap.
async fn start_unwatched(
    args: &ModbusArgs,
    link: &ModbusLink,
    named: &Named,
    options: &StoredOptions,
    t: &Telemetry,
) -> Outcome {
    let cap = options.cap();
    let in_force = t.speed_limits;
    let valid = |v: f32| v.is_finite() && v > 0.0;
    if !(valid(in_force.linear) && valid(in_force.angular)) {
        return Outcome::failed(&ModbusError::SpeedLimitsUnknown {
            linear: in_force.linear,
            angular: in_force.angular,
        });
    }
    // The arm's limits are the integrator's: lowered only while something waits to put them back.
    // Nothing would here, so a limit above the cap refuses the run.
    let over = if in_force.linear > cap.linear {
        Some(format!(
            "linear limit is {} m/s, over the {} m/s cap",
            in_force.linear, cap.linear
        ))
    } else if in_force.angular > cap.angular {
        Some(format!(
            "angular limit is {} deg/s, over the {} deg/s turn rate",
            in_force.angular, cap.angular
        ))
    } else {
        None
    };
    if let Some(over) = over {
        let why = format!(
            "{} not started: the arm's {over}, and with --no-wait nothing is left to lower it \
             for the run and put it back; drop --no-wait (the command then waits for the end)",
            named.stored
        );
        return Outcome::error(why, 1);
    }
    let report = match link.start_stored(named.stored, None).await {
        Ok(started) => started,
        Err(e) => return Outcome::failed(&e),
    };
    let stdout = render(args, &report, Some("started"));
    Outcome::printed(stdout)
}

/// The fault flags are read before the status: a fault raised between them shows as an abort with
/// no fault; the next snapshot names it.
async fn fault_behind_abort(
    link: &ModbusLink,
    named: &Named,
    progress: &Progress,
) -> Option<String> {
    if !matches!(progress, Progress::Aborted(_)) {
        return None;
    }
    let fault = fault_reason(&link.read_telemetry().await.ok()?)?;
    named.failure(&Progress::Fault(fault))
}

/// Polls until the run ends. Past `timeout` it is stopped.
async fn wait_for_end(
    link: &ModbusLink,
    named: &Named,
    timeout: Duration,
) -> Result<End, ModbusError> {
    let started = Instant::now();
    let mut run = StoredRun::new(named.stored);
    loop {
        let t = link.read_telemetry().await?;
        let elapsed = started.elapsed();
        let progress = run.observe(&t, elapsed);
        if progress == Progress::Completed {
            return Ok(End::Completed(elapsed));
        }
        if let Some(message) = named.failure(&progress) {
            return Ok(End::Failed(
                fault_behind_abort(link, named, &progress)
                    .await
                    .unwrap_or(message),
            ));
        }
        if elapsed >= timeout {
            let stopped = match link.stop().await {
                Ok(_) => "stopped",
                Err(_) => "and the STOP could not be written: the arm may still be moving",
            };
            let why = format!("no end within {:.1} s; {stopped}", timeout.as_secs_f64());
            return Ok(End::Failed(named.failed(&why)));
        }
        tokio::time::sleep(POLL).await;
    }
}
