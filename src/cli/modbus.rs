//! `armjog modbus`: a technician's writes from a shell, with options and exit codes shared.

use std::time::Duration;

use clap::{Args, Subcommand};
use serde_json::{Value, json};

use super::Outcome;
use crate::kortex::commands::{self, Write};
use crate::kortex::{ControlCoil, Stored, StoredMotion};
use crate::link::modbus::{DEFAULT_HOME_ACTION_ID, DEFAULT_PORT, ModbusConfig, ModbusError};
use crate::link::{ModbusLink, WriteReport};

mod stored;

pub use stored::StoredOptions;

/// Exit status for a Modbus exception, or an action that did not complete.
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
        #[arg(long, default_value_t = DEFAULT_HOME_ACTION_ID, value_name = "N", value_parser = super::values::stored_action_id)]
        action_id: u16,
        #[command(flatten)]
        options: StoredOptions,
    },
    /// Start a stored action by id and wait for its end (holding registers 200-202, move
    /// type 0). A real arm's ids are on its Web App's Actions page.
    Action {
        /// The action's id.
        #[arg(long, value_name = "N", value_parser = super::values::stored_action_id)]
        id: u16,
        #[command(flatten)]
        options: StoredOptions,
    },
    /// Start a stored sequence by id and wait for its end (holding registers 200-202, move
    /// type 1). A real arm's ids are on its Web App's Actions page.
    Sequence {
        /// The sequence's id.
        #[arg(long, value_name = "N", value_parser = super::values::stored_action_id)]
        id: u16,
        #[command(flatten)]
        options: StoredOptions,
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
            ModbusCommand::Action { .. } => "action",
            ModbusCommand::Sequence { .. } => "sequence",
            ModbusCommand::SpeedLimit { .. } => "speed_limit",
        }
    }

    async fn send(&self, link: &ModbusLink) -> Result<WriteReport, ModbusError> {
        match self {
            ModbusCommand::QuickStop => link.pulse(ControlCoil::QuickStop).await,
            ModbusCommand::Abort => link.pulse(ControlCoil::Abort).await,
            ModbusCommand::FaultReset => link.pulse(ControlCoil::FaultReset).await,
            ModbusCommand::Stop => link.stop().await,
            // Capped while the link watches them: the limits go back when they end.
            ModbusCommand::Home {
                action_id: id,
                options,
            }
            | ModbusCommand::Action { id, options } => {
                let action = Stored {
                    motion: StoredMotion::Action,
                    id: *id,
                };
                link.start_stored(action, Some(options.cap())).await
            }
            ModbusCommand::Sequence { id, options } => {
                let sequence = Stored {
                    motion: StoredMotion::Sequence,
                    id: *id,
                };
                link.start_stored(sequence, Some(options.cap())).await
            }
            ModbusCommand::SpeedLimit { linear, angular } => {
                link.set_speed_limits(*linear, *angular).await
            }
        }
    }
}

impl Outcome {
    pub fn failed(error: &ModbusError) -> Outcome {
        Outcome::error(error.to_string(), exit_code(error))
    }
}

pub async fn run(args: &ModbusArgs) -> Outcome {
    // Refuse bad values before connecting, so nothing reaches the arm.
    if let ModbusCommand::SpeedLimit { linear, angular } = &args.command
        && let Err(e) = commands::speed_limits(*linear, *angular)
    {
        return Outcome::failed(&e.into());
    }
    let stored = args.command.stored();
    if let Some(Err(why)) = stored.as_ref().map(|(_, options)| options.check()) {
        return Outcome::error(why.to_string(), EXIT_REFUSED);
    }
    let link = match ModbusLink::connect(args.arm.config()).await {
        Ok((link, _events)) => link,
        Err(e) => return Outcome::failed(&e),
    };
    let outcome = match stored {
        Some((stored, options)) => stored::run(args, &link, stored, options).await,
        None => match args.command.send(&link).await {
            Ok(report) => Outcome::printed(render(args, &report, None)),
            Err(e) => Outcome::failed(&e),
        },
    };
    let _ = link.close().await;
    outcome
}

impl ModbusCommand {
    /// The stored action or sequence a command starts (home is the action with the home id),
    /// with how it is waited for and capped.
    fn stored(&self) -> Option<(Stored, &StoredOptions)> {
        let (motion, id, options) = match self {
            ModbusCommand::Home { action_id, options } => {
                (StoredMotion::Action, *action_id, options)
            }
            ModbusCommand::Action { id, options } => (StoredMotion::Action, *id, options),
            ModbusCommand::Sequence { id, options } => (StoredMotion::Sequence, *id, options),
            _ => return None,
        };
        Some((Stored { motion, id }, options))
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
        if let Some((stored, _)) = args.command.stored() {
            object["id"] = json!(stored.id);
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
