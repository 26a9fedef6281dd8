//! `armjog modbus`: the writes a technician needs from a shell, and what `armjog status`
//! shares with it (the connection options and exit codes).

use std::time::Duration;

use clap::{Args, Subcommand};
use serde_json::{Value, json};

use crate::kortex::StoredMotion;
use crate::kortex::commands::{self, Write};
use crate::link::modbus::{DEFAULT_HOME_ACTION_ID, DEFAULT_PORT, ModbusConfig, ModbusError};
use crate::link::{ModbusLink, WriteReport};

/// Exit status when the arm answered with a Modbus exception.
pub const EXIT_EXCEPTION: i32 = 1;
/// Exit status when a value was refused before anything was sent.
pub const EXIT_REFUSED: i32 = 2;
/// Exit status when the arm could not be reached or the link failed.
pub const EXIT_LINK: i32 = 3;

/// Where the arm is.
#[derive(Debug, Clone, Args)]
pub struct ArmAddress {
    /// The arm, HOST:PORT (port 502 if omitted).
    #[arg(long, value_name = "HOST:PORT")]
    pub modbus: String,
    /// Modbus unit id.
    #[arg(long, default_value_t = crate::link::modbus::DEFAULT_UNIT, value_name = "N")]
    pub unit: u8,
    /// How long to wait for each reply, in milliseconds.
    #[arg(long, default_value_t = 500, value_name = "MS")]
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
    #[arg(long)]
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
    /// Start the Home action.
    Home {
        /// The arm's id of its Home action (see the Kortex Web App).
        #[arg(long, default_value_t = DEFAULT_HOME_ACTION_ID, value_name = "N")]
        action_id: u16,
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
            ModbusCommand::Home { action_id } => {
                link.start_stored(*action_id, StoredMotion::Action).await
            }
            ModbusCommand::SpeedLimit { linear, angular } => {
                link.set_speed_limits(*linear, *angular).await
            }
        }
    }
}

/// What a one-shot command prints and how it exits.
pub struct Outcome {
    pub stdout: Vec<String>,
    pub stderr: Option<String>,
    pub exit_code: i32,
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
    let link = match ModbusLink::connect(args.arm.config()).await {
        Ok((link, _events)) => link,
        Err(e) => return Outcome::failed(&e),
    };
    let result = args.command.send(&link).await;
    let _ = link.close().await;
    match result {
        Ok(report) => Outcome {
            stdout: render(args, &report),
            stderr: None,
            exit_code: 0,
        },
        Err(e) => Outcome::failed(&e),
    }
}

fn render(args: &ModbusArgs, report: &WriteReport) -> Vec<String> {
    let elapsed_ms = report.elapsed.as_secs_f64() * 1000.0;
    if args.json {
        let writes: Vec<Value> = report.writes.iter().map(write_json).collect();
        let object = json!({
            "command": args.command.name(),
            "writes": writes,
            "elapsed_ms": elapsed_ms,
        });
        return vec![object.to_string()];
    }
    let mut lines = vec![format!(
        "{}: done [{elapsed_ms:.1} ms]",
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
