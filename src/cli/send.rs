//! `armjog send`: one Talos command, its reply printed for a person or a script.

use std::time::Duration;

use clap::{Args, Subcommand};
use serde_json::{Map, Value, json};

use super::Outcome;
use super::values::{self, BadValue};
use crate::link::talos::{DEFAULT_PORT, Exchange, first_exchange_error};
use crate::link::{Answer, Dialect, TalosConfig, TalosError, TalosLink};
use crate::talos::hardware::HwReply;
use crate::talos::hex::spaced_hex;
use crate::talos::{Checksum, PositionName, Request};

/// Exit status when the operator answered with a non-zero return code.
pub const EXIT_RETURN_CODE: i32 = 1;
/// Exit status when the operator could not be reached or answered nonsense.
pub const EXIT_LINK: i32 = 3;

/// Every option is `global`: accepted before or after the command (`armjog send get-speed
/// --talos A --json`). A global option cannot be `required` in clap, so `--talos` is checked when
/// the arguments are read instead.
#[derive(Debug, Args)]
pub struct SendArgs {
    /// The operator, HOST:PORT (port 61616 if omitted). Required.
    #[arg(long, value_name = "HOST:PORT", global = true, required = false)]
    pub talos: String,
    /// How the operator replies: typed ICD replies, or the deployed operator's "ACK\0".
    #[arg(long, default_value = "icd", value_parser = values::dialect_parser(), global = true)]
    pub dialect: Dialect,
    /// Checksum dialect of every frame.
    #[arg(long, default_value = "crc16", value_parser = values::checksum_parser(), global = true)]
    pub checksum: Checksum,
    /// Print one JSON object instead of a line of text.
    #[arg(long, global = true)]
    pub json: bool,
    /// Also print the frames sent and received, in hex.
    #[arg(long, global = true)]
    pub hex: bool,
    /// How long to wait for the reply, in milliseconds.
    #[arg(long, default_value_t = 500, value_name = "MS", global = true)]
    pub timeout: u64,
    #[command(subcommand)]
    pub command: SendCommand,
}

fn parse_name(s: &str) -> Result<String, BadValue> {
    Ok(PositionName::new(s)?.as_str().to_owned())
}

fn parse_parent(s: &str) -> Result<String, BadValue> {
    if s.is_empty() {
        Ok(String::new())
    } else {
        parse_name(s)
    }
}

/// Bytes given as hex on the command line.
#[derive(Debug, Clone, Default)]
pub struct HexBytes(pub Vec<u8>);

fn parse_hex(s: &str) -> Result<HexBytes, BadValue> {
    let cleaned: String = s.chars().filter(|c| !c.is_whitespace()).collect();
    Ok(HexBytes(hex::decode(&cleaned)?))
}

const DIRECTION: std::ops::RangeInclusive<i64> = -1..=1;

/// One subcommand per ICD command; units as in the ICD.
#[derive(Debug, Subcommand)]
pub enum SendCommand {
    /// 0x0000: ask the operator for its version.
    Handshake {
        /// Operator-arm model id.
        #[arg(long, default_value_t = 0)]
        oid: u16,
    },
    /// 0x0001: pan by a number of degrees.
    PolarPan {
        #[arg(long, allow_hyphen_values = true)]
        azimuth: i32,
        #[arg(long, allow_hyphen_values = true)]
        altitude: i32,
        /// Wait before starting, ms.
        #[arg(long, default_value_t, value_name = "MS", allow_hyphen_values = true)]
        delay: u32,
        /// Duration of the pan, ms.
        #[arg(long, default_value_t, value_name = "MS", allow_hyphen_values = true)]
        time: u32,
    },
    /// 0x0002: go to the home pose.
    Home {
        #[arg(long, default_value_t, value_name = "MS", allow_hyphen_values = true)]
        delay: u32,
    },
    /// 0x0003: start or refresh a continuous pan; each direction is -1, 0 or 1.
    PolarStart {
        #[arg(long, allow_hyphen_values = true, value_parser = clap::value_parser!(i8).range(DIRECTION))]
        azimuth: i8,
        #[arg(long, allow_hyphen_values = true, value_parser = clap::value_parser!(i8).range(DIRECTION))]
        altitude: i8,
    },
    /// 0x0004: stop a continuous pan.
    PolarStop,
    /// 0x0005: move by tenths of millimetres.
    CartMove {
        #[arg(long, allow_hyphen_values = true)]
        x: i32,
        #[arg(long, allow_hyphen_values = true)]
        y: i32,
        #[arg(long, allow_hyphen_values = true)]
        z: i32,
        #[arg(long, default_value_t, value_name = "MS", allow_hyphen_values = true)]
        delay: u32,
        #[arg(long, default_value_t, value_name = "MS", allow_hyphen_values = true)]
        time: u32,
    },
    /// 0x0006: start or refresh a continuous cartesian move; each direction is -1, 0 or 1.
    CartStart {
        #[arg(long, allow_hyphen_values = true, value_parser = clap::value_parser!(i8).range(DIRECTION))]
        x: i8,
        #[arg(long, allow_hyphen_values = true, value_parser = clap::value_parser!(i8).range(DIRECTION))]
        y: i8,
        #[arg(long, allow_hyphen_values = true, value_parser = clap::value_parser!(i8).range(DIRECTION))]
        z: i8,
    },
    /// 0x0007: stop a continuous cartesian move.
    CartStop,
    /// 0x0008: a hardware operation (see docs/hardware-icd.md).
    HwOp {
        /// Subcommand value.
        #[arg(long)]
        sub: u16,
        /// Subcommand payload as hex bytes, e.g. 01 or "00 01".
        #[arg(long, value_parser = parse_hex, default_value = "")]
        payload: HexBytes,
    },
    /// 0x0009: read the speed (percent of the maximum jog speed).
    GetSpeed,
    /// 0x000A: set the speed (armjog's operators take 1-100 percent).
    SetSpeed { speed: u8 },
    /// 0x000B: save the current pose under a name.
    Save {
        #[arg(value_parser = parse_name)]
        name: String,
        /// Move with the parent position.
        #[arg(long)]
        anchor: bool,
        /// Parent (reference) position; empty for the operator's default.
        #[arg(long, value_parser = parse_parent, default_value = "")]
        parent: String,
    },
    /// 0x000C: delete a named position.
    Delete {
        #[arg(value_parser = parse_name)]
        name: String,
    },
    /// 0x000D: move to a named position.
    Goto {
        #[arg(value_parser = parse_name)]
        name: String,
    },
    /// 0x000E: define a position in polar coordinates (tenths of degrees / of distance).
    SetPolar {
        #[arg(value_parser = parse_name)]
        name: String,
        #[arg(long, allow_hyphen_values = true)]
        delta: i32,
        #[arg(long, allow_hyphen_values = true)]
        azimuth: i32,
        #[arg(long, allow_hyphen_values = true)]
        radius: i32,
    },
    /// 0x000F: read a position's polar coordinates.
    GetPolar {
        #[arg(value_parser = parse_name)]
        name: String,
    },
    /// 0x0010: define a position in tenths of millimetres.
    SetCart {
        #[arg(value_parser = parse_name)]
        name: String,
        #[arg(long, allow_hyphen_values = true)]
        x: i32,
        #[arg(long, allow_hyphen_values = true)]
        y: i32,
        #[arg(long, allow_hyphen_values = true)]
        z: i32,
    },
    /// 0x0011: read a position's cartesian coordinates.
    GetCart {
        #[arg(value_parser = parse_name)]
        name: String,
    },
}

impl SendCommand {
    pub fn to_request(&self) -> Request {
        match self {
            SendCommand::Handshake { oid } => Request::Handshake { oid: Some(*oid) },
            SendCommand::PolarPan {
                azimuth,
                altitude,
                delay,
                time,
            } => Request::PolarPan {
                delta_azimuth: *azimuth,
                delta_altitude: *altitude,
                delay_ms: *delay,
                time_ms: *time,
            },
            SendCommand::Home { delay } => Request::Home { delay_ms: *delay },
            SendCommand::PolarStart { azimuth, altitude } => Request::PolarPanStart {
                moving_azimuth: *azimuth,
                moving_altitude: *altitude,
            },
            SendCommand::PolarStop => Request::PolarPanStop,
            SendCommand::CartMove {
                x,
                y,
                z,
                delay,
                time,
            } => Request::CartesianMove {
                delta_x: *x,
                delta_y: *y,
                delta_z: *z,
                delay_ms: *delay,
                time_ms: *time,
            },
            SendCommand::CartStart { x, y, z } => Request::CartesianMoveStart {
                moving_x: *x,
                moving_y: *y,
                moving_z: *z,
            },
            SendCommand::CartStop => Request::CartesianMoveStop,
            SendCommand::HwOp { sub, payload } => Request::HardwareOperation {
                subcommand: *sub,
                reserved: 0,
                payload: payload.0.clone(),
            },
            SendCommand::GetSpeed => Request::GetSpeed,
            SendCommand::SetSpeed { speed } => Request::SetSpeed { speed: *speed },
            SendCommand::Save {
                name,
                anchor,
                parent,
            } => Request::SavePosition {
                name: name.clone(),
                anchor: *anchor,
                parent: parent.clone(),
            },
            SendCommand::Delete { name } => Request::DeletePosition { name: name.clone() },
            SendCommand::Goto { name } => Request::GoToPosition { name: name.clone() },
            SendCommand::SetPolar {
                name,
                delta,
                azimuth,
                radius,
            } => Request::SetPolarPosition {
                name: name.clone(),
                delta: *delta,
                azimuth: *azimuth,
                radius: *radius,
            },
            SendCommand::GetPolar { name } => Request::GetPolarPosition { name: name.clone() },
            SendCommand::SetCart { name, x, y, z } => Request::SetCartesianPosition {
                name: name.clone(),
                x: *x,
                y: *y,
                z: *z,
            },
            SendCommand::GetCart { name } => Request::GetCartesianPosition { name: name.clone() },
        }
    }
}

pub async fn run(args: &SendArgs) -> Outcome {
    let mut config = TalosConfig::new(super::with_default_port(&args.talos, DEFAULT_PORT));
    config.dialect = args.dialect;
    config.checksum = args.checksum;
    config.request_timeout = Duration::from_millis(args.timeout);
    // A reply that never completes under our checksum (xor8 to crc16 is a byte short) is given up
    // before the request times out, so the error can name the checksum it fits.
    config.frame_deadline = config.frame_deadline.min(config.request_timeout / 2);
    let request = args.command.to_request();
    let addr = config.addr.clone();
    let result = match TalosLink::connect(config.clone()).await {
        Ok((link, _events)) => link.request(request).await,
        Err(e) => Err(e),
    };
    log_exchange(&addr, &result);
    match result {
        Ok(exchange) => Outcome::printed(render(args, &exchange)),
        Err(TalosError::ReturnCode { exchange }) => Outcome {
            stdout: render(args, &exchange),
            stderr: Some(format!(
                "{} (id {}) failed: return code {}",
                exchange.request.command(),
                exchange.id,
                exchange.return_code()
            )),
            exit_code: EXIT_RETURN_CODE,
        },
        Err(e) => Outcome::error(first_exchange_error(&e, &config, None), EXIT_LINK),
    }
}

/// The exchange in `armjog-cli.log`: both frames in hex, the answer and the round trip.
fn log_exchange(addr: &str, result: &Result<Exchange, TalosError>) {
    let exchange = match result {
        Ok(exchange) => exchange,
        Err(TalosError::ReturnCode { exchange }) => &**exchange,
        Err(e) => {
            tracing::info!("send to {addr}: no exchange: {e}");
            return;
        }
    };
    // `describe` names the command, its id, the answer and the round trip.
    tracing::info!(
        "send to {addr}: request [{}], reply [{}]: {}",
        spaced_hex(&exchange.request_bytes),
        spaced_hex(&exchange.reply_bytes),
        describe(exchange)
    );
}

fn render(args: &SendArgs, exchange: &Exchange) -> Vec<String> {
    if args.json {
        return vec![to_json(exchange, args.hex).to_string()];
    }
    let mut lines = vec![describe(exchange)];
    if let Some(reply) = decoded_hardware_reply(exchange) {
        lines.extend(super::hw_text::lines(&reply));
    }
    if args.hex {
        lines.push(format!("sent     {}", spaced_hex(&exchange.request_bytes)));
        lines.push(format!("received {}", spaced_hex(&exchange.reply_bytes)));
    }
    lines
}

/// The reply's fields but the return code, in ICD order; a hardware payload decoded too.
fn reply_fields(exchange: &Exchange) -> Map<String, Value> {
    let Answer::Reply(reply) = &exchange.answer else {
        return Map::new();
    };
    let Ok(Value::Object(mut map)) = serde_json::to_value(reply) else {
        return Map::new();
    };
    map.remove("return_code");
    if let Some(decoded) = decoded_hardware_reply(exchange)
        && let Ok(value) = serde_json::to_value(&decoded)
    {
        map.insert("decoded".into(), value);
    }
    map
}

/// A successful hardware operation's reply payload, decoded by the companion ICD.
fn decoded_hardware_reply(exchange: &Exchange) -> Option<HwReply> {
    match &exchange.answer {
        Answer::Reply(crate::talos::Reply::HardwareOperation {
            subcommand,
            payload,
            return_code,
        }) if return_code.is_ok() => HwReply::decode(*subcommand, payload).ok(),
        _ => None,
    }
}

/// One readable line: command, id, outcome, fields, latency. A hardware payload goes to the lines
/// under it (`hw_text`); a failed reply shows only its status (its fields are zeros).
pub fn describe(exchange: &Exchange) -> String {
    let command = exchange.request.command();
    let (outcome, failed) = match exchange.answer {
        Answer::Ack => ("ACK".to_string(), false),
        Answer::Reply(_) => {
            let code = exchange.return_code();
            (code.to_string(), !code.is_ok())
        }
    };
    let mut line = format!("{command} (id {}): {outcome}", exchange.id);
    let decoded = decoded_hardware_reply(exchange).is_some();
    let fields = if failed {
        Map::new()
    } else {
        reply_fields(exchange)
    };
    for (key, value) in fields {
        // An empty payload says nothing; a decoded one is shown on the lines below.
        let empty = value.as_str().is_some_and(str::is_empty);
        if empty || (decoded && matches!(key.as_str(), "decoded" | "payload")) {
            continue;
        }
        let shown = match value {
            Value::String(s) => s,
            other => other.to_string(),
        };
        line.push_str(&format!(" {key}={shown}"));
    }
    let ms = exchange.latency.as_secs_f64() * 1000.0;
    line.push_str(&format!(" [{ms:.1} ms]"));
    line
}

/// The `--json` object: command, id, return code, then the reply's fields as the ICD names them.
pub fn to_json(exchange: &Exchange, with_hex: bool) -> Value {
    let mut object = json!({"command": exchange.request.command().name(), "id": exchange.id});
    match &exchange.answer {
        Answer::Reply(_) => {
            let code = exchange.return_code();
            object["return_code"] = json!(code.0);
            object["return_code_name"] = json!(code.name());
        }
        Answer::Ack => object["ack"] = json!(true),
    }
    if let Value::Object(map) = &mut object {
        map.extend(reply_fields(exchange));
    }
    object["latency_ms"] = json!(exchange.latency.as_secs_f64() * 1000.0);
    if with_hex {
        object["request_hex"] = json!(hex::encode_upper(&exchange.request_bytes));
        object["reply_hex"] = json!(hex::encode_upper(&exchange.reply_bytes));
    }
    object
}
