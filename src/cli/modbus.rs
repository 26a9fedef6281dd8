//! `armjog modbus`: the writes a technician needs from a shell, and what `armjog status`
//! shares with it (the connection options and exit codes).

use std::time::{Duration, Instant};

use clap::{Args, Subcommand};
use serde_json::{Value, json};

use super::Outcome;
use crate::kortex::arm_state::{abort_reason, at_rest, fault_reason};
use crate::kortex::commands::{self, Write};
use crate::kortex::{ActionStatus, Coded, StoredMotion, Telemetry};
use crate::link::modbus::{DEFAULT_HOME_ACTION_ID, DEFAULT_PORT, ModbusConfig, ModbusError};
use crate::link::{ModbusLink, WriteReport};

/// Exit status when the arm answered with a Modbus exception, or an action it was asked for
/// did not complete (aborted, faulted, never started, timed out).
pub const EXIT_EXCEPTION: i32 = 1;
/// Exit status when a value was refused before anything was sent.
pub const EXIT_REFUSED: i32 = 2;
/// Exit status when the arm could not be reached or the link failed.
pub const EXIT_LINK: i32 = 3;

/// Where the arm is. The options are `global`: accepted before or after a nested command
/// (`armjog modbus quick-stop --modbus A`); clap cannot require a global option, so `--modbus`
/// is checked when the arguments are read.
#[derive(Debug, Clone, Args)]
pub struct ArmAddress {
    /// The arm, HOST:PORT (port 502 if omitted). Required.
    #[arg(long, value_name = "HOST:PORT", global = true, required = false)]
    pub modbus: String,
    /// Modbus unit id.
    #[arg(long, default_value_t = crate::link::modbus::DEFAULT_UNIT, value_name = "N", global = true)]
    pub unit: u8,
    /// How long to wait for each reply, in milliseconds.
    #[arg(long, default_value_t = 500, value_name = "MS", global = true)]
    pub timeout: u64,
}

impl ArmAddress {
    /// A link that polls only on request and writes nothing on its own.
    pub fn config(&self) -> ModbusConfig {
        let mut config = ModbusConfig::new(super::with_default_port(&self.modbus, DEFAULT_PORT));
        config.unit = self.unit;
        config.request_timeout = Duration::from_millis(self.timeout);
        config.poll_rate_hz = None;
        config.twist_hold = None;
        config
    }
}

/// The exit status for a failed command.
pub fn exit_code(error: &ModbusError) -> i32 {
    if error.refused_before_sending() {
        EXIT_REFUSED
    } else if error.exception().is_some() {
        EXIT_EXCEPTION
    } else {
        EXIT_LINK
    }
}

#[derive(Debug, Args)]
pub struct ModbusArgs {
    #[command(flatten)]
    pub arm: ArmAddress,
    /// Print one JSON object instead of text.
    #[arg(long, global = true)]
    pub json: bool,
    #[command(subcommand)]
    pub command: ModbusCommand,
}

#[derive(Debug, Clone, Subcommand)]
pub enum ModbusCommand {
    /// Pulse the quick stop coil (0).
    QuickStop,
    /// Pulse the abort / manual stop coil (1).
    Abort,
    /// Pulse the fault reset coil (2). After a quick stop it may take more than one.
    FaultReset,
    /// Stop the running action, trajectory or twist (holding register 200 <- 2).
    Stop,
    /// Start the Home action and wait for its end (refused if the arm is in fault).
    Home {
        /// The arm's id of its Home action (see the Kortex Web App).
        #[arg(long, default_value_t = DEFAULT_HOME_ACTION_ID, value_name = "N")]
        action_id: u16,
        /// Return once the action is started, without waiting for its end.
        #[arg(long)]
        no_wait: bool,
        /// Longest wait for the end, seconds: past it the action is stopped and the exit status
        /// is 1.
        #[arg(long, default_value_t = 60.0, value_name = "S")]
        wait_timeout: f64,
    },
    /// Set the desired cartesian speed limits (holding registers 216-219).
    SpeedLimit {
        /// Linear limit, m/s (above 0, at most 0.5).
        #[arg(long, value_name = "M_S")]
        linear: f32,
        /// Angular limit, deg/s (above 0, at most 100).
        #[arg(long, value_name = "DEG_S")]
        angular: f32,
    },
}

impl ModbusCommand {
    pub fn name(&self) -> &'static str {
        match self {
            ModbusCommand::QuickStop => "quick_stop",
            ModbusCommand::Abort => "abort",
            ModbusCommand::FaultReset => "fault_reset",
            ModbusCommand::Stop => "stop",
            ModbusCommand::Home { .. } => "home",
            ModbusCommand::SpeedLimit { .. } => "speed_limit",
        }
    }

    async fn send(&self, link: &ModbusLink) -> Result<WriteReport, ModbusError> {
        match self {
            ModbusCommand::QuickStop => link.quick_stop().await,
            ModbusCommand::Abort => link.abort().await,
            ModbusCommand::FaultReset => link.fault_reset().await,
            ModbusCommand::Stop => link.stop().await,
            ModbusCommand::Home { action_id, .. } => {
                link.start_stored(*action_id, StoredMotion::Action).await
            }
            ModbusCommand::SpeedLimit { linear, angular } => {
                link.set_speed_limits(*linear, *angular).await
            }
        }
    }
}

impl Outcome {
    pub fn failed(error: &ModbusError) -> Outcome {
        Outcome {
            stdout: Vec::new(),
            stderr: Some(error.to_string()),
            exit_code: exit_code(error),
        }
    }
}

/// Runs `armjog modbus`.
pub async fn run(args: &ModbusArgs) -> Outcome {
    // Refuse bad values before connecting, so nothing reaches the arm.
    if let ModbusCommand::SpeedLimit { linear, angular } = &args.command
        && let Err(e) = commands::speed_limits(*linear, *angular)
    {
        return Outcome::failed(&e.into());
    }
    let home = match &args.command {
        ModbusCommand::Home {
            action_id,
            no_wait,
            wait_timeout,
        } => {
            if !(wait_timeout.is_finite() && *wait_timeout > 0.0 && *wait_timeout <= 86_400.0) {
                return Outcome {
                    stdout: Vec::new(),
                    stderr: Some(format!(
                        "--wait-timeout {wait_timeout}: must be above 0 and at most 86400 s"
                    )),
                    exit_code: EXIT_REFUSED,
                };
            }
            Some((
                *action_id,
                !*no_wait,
                Duration::from_secs_f64(*wait_timeout),
            ))
        }
        _ => None,
    };
    let link = match ModbusLink::connect(args.arm.config()).await {
        Ok((link, _events)) => link,
        Err(e) => return Outcome::failed(&e),
    };
    let outcome = match home {
        Some((action_id, wait, timeout)) => run_home(args, &link, action_id, wait, timeout).await,
        None => match args.command.send(&link).await {
            Ok(report) => Outcome {
                stdout: render(args, &report, None),
                stderr: None,
                exit_code: 0,
            },
            Err(e) => Outcome::failed(&e),
        },
    };
    let _ = link.close().await;
    outcome
}

/// How often a home's end is polled.
const HOME_POLL: Duration = Duration::from_millis(100);
/// A status read this soon after the start may still be the previous action's.
const HOME_STATUS_GRACE: Duration = Duration::from_millis(500);
/// An arm that has not taken the action id by then does not have it.
const HOME_START_LIMIT: Duration = Duration::from_secs(2);

/// How a home ended.
enum HomeEnd {
    Completed(Duration),
    Failed(String),
}

/// `armjog modbus home`: refuses an arm in fault, starts the action and (unless told not to)
/// waits for its end.
async fn run_home(
    args: &ModbusArgs,
    link: &ModbusLink,
    action_id: u16,
    wait: bool,
    timeout: Duration,
) -> Outcome {
    let failed = |reason: String, stdout: Vec<String>| Outcome {
        stdout,
        stderr: Some(format!("home failed: {reason}")),
        exit_code: EXIT_EXCEPTION,
    };
    match link.read_telemetry().await {
        Ok(t) => {
            if let Some(fault) = fault_reason(&t) {
                return failed(format!("{fault}; not started"), Vec::new());
            }
        }
        Err(e) => return Outcome::failed(&e),
    }
    let report = match args.command.send(link).await {
        Ok(report) => report,
        Err(e) => return Outcome::failed(&e),
    };
    if !wait {
        return Outcome {
            stdout: render(args, &report, Some("started")),
            stderr: None,
            exit_code: 0,
        };
    }
    match wait_for_home(link, action_id, timeout).await {
        Ok(HomeEnd::Completed(took)) => {
            let mut stdout = render(args, &report, Some("completed"));
            if !args.json {
                stdout.push(format!("home: completed in {:.1} s", took.as_secs_f64()));
            }
            Outcome {
                stdout,
                stderr: None,
                exit_code: 0,
            }
        }
        Ok(HomeEnd::Failed(reason)) => failed(reason, render(args, &report, Some("failed"))),
        Err(e) => Outcome::failed(&e),
    }
}

/// Polls the action status and faults until the action `action_id` ends. Past `timeout` it is
/// stopped.
async fn wait_for_home(
    link: &ModbusLink,
    action_id: u16,
    timeout: Duration,
) -> Result<HomeEnd, ModbusError> {
    let started = Instant::now();
    let mut seen_started = false;
    loop {
        let t = link.read_telemetry().await?;
        let elapsed = started.elapsed();
        if let Some(end) = home_end(&t, action_id, elapsed, &mut seen_started) {
            return Ok(end);
        }
        if elapsed >= timeout {
            let stopped = match link.stop().await {
                Ok(_) => "stopped",
                Err(_) => "and the STOP could not be written: the arm may still be moving",
            };
            return Ok(HomeEnd::Failed(format!(
                "no end within {:.1} s; {stopped}",
                timeout.as_secs_f64()
            )));
        }
        tokio::time::sleep(HOME_POLL).await;
    }
}

/// What one poll says about the home, if it ended.
fn home_end(
    t: &Telemetry,
    action_id: u16,
    elapsed: Duration,
    seen_started: &mut bool,
) -> Option<HomeEnd> {
    if let Some(fault) = fault_reason(t) {
        return Some(HomeEnd::Failed(fault));
    }
    let ours = t.action.id == action_id;
    if ours && t.action.status == Coded::Known(ActionStatus::Started) {
        *seen_started = true;
    }
    // Right after the start the status may still describe an earlier run of the same action.
    let current = ours && (*seen_started || elapsed >= HOME_STATUS_GRACE);
    match t.action.status {
        Coded::Known(ActionStatus::Aborted) if current => {
            let reason = abort_reason(t);
            Some(HomeEnd::Failed(if *seen_started {
                reason
            } else {
                format!("{reason} at once: does the arm have action {action_id}?")
            }))
        }
        Coded::Known(ActionStatus::Completed) if current && at_rest(t) => {
            Some(HomeEnd::Completed(elapsed))
        }
        _ if !ours && elapsed >= HOME_START_LIMIT => Some(HomeEnd::Failed(format!(
            "the arm did not take action {action_id} (it reports action {}): does it exist?",
            t.action.id
        ))),
        _ => None,
    }
}

/// The writes made; `action`: how a started action ended (`started` when not waited for).
fn render(args: &ModbusArgs, report: &WriteReport, action: Option<&str>) -> Vec<String> {
    let elapsed_ms = report.elapsed.as_secs_f64() * 1000.0;
    if args.json {
        let writes: Vec<Value> = report.writes.iter().map(write_json).collect();
        let mut object = json!({
            "command": args.command.name(),
            "writes": writes,
            "elapsed_ms": elapsed_ms,
        });
        if let Some(action) = action {
            object["action"] = json!(action);
        }
        return vec![object.to_string()];
    }
    let verb = if action.is_some() { "started" } else { "done" };
    let mut lines = vec![format!(
        "{}: {verb} [{elapsed_ms:.1} ms]",
        args.command.name()
    )];
    lines.extend(report.writes.iter().map(|w| format!("  {w}")));
    lines
}

/// A write as JSON: function code, first address, and the values written.
pub fn write_json(write: &Write) -> Value {
    match write {
        Write::Registers { addr, values } => {
            json!({"function_code": write.function_code(), "address": addr, "values": values})
        }
        Write::Coil { addr, value } => {
            json!({"function_code": write.function_code(), "address": addr, "value": value})
        }
    }
}
