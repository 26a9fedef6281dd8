//! `armjog status`: a Kinova arm's snapshot over Modbus, as a table or JSON, once or watching.

use std::time::{Duration, SystemTime};

use clap::Args;

use super::Outcome;
use super::modbus::ArmAddress;
use super::output::{self, Printed};
use super::units::{arm_line, fixed, linear_speed, tool_lines};
use super::values::BadValue;
use crate::console::audit::rfc3339_ms;
use crate::kortex::{CodeName, Flag, FlagSet, Telemetry};
use crate::link::ModbusLink;

#[derive(Debug, Args)]
pub struct StatusArgs {
    #[command(flatten)]
    pub arm: ArmAddress,
    /// Print one JSON object (one per line with --watch) instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Keep printing snapshots, HZ a second (1 if no value), until interrupted. Every line
    /// starts with the time of its snapshot (RFC 3339, UTC); JSON objects get a "time" field.
    #[arg(
        long,
        value_name = "HZ",
        num_args = 0..=1,
        default_missing_value = "1",
        value_parser = parse_rate
    )]
    pub watch: Option<f64>,
}

fn parse_rate(s: &str) -> Result<f64, BadValue> {
    match s.parse::<f64>() {
        Ok(hz) if hz.is_finite() && hz > 0.0 && hz <= 100.0 => Ok(hz),
        _ => Err(BadValue::NotARate(s.into())),
    }
}

/// Runs `armjog status`; `--watch` reports failed reads and goes on; Ctrl-C ends with 0.
pub async fn run(args: &StatusArgs) -> Outcome {
    let link = match ModbusLink::connect(args.arm.config()).await {
        Ok((link, _events)) => link,
        Err(e) => return Outcome::failed(&e),
    };
    let Some(hz) = args.watch else {
        return match link.read_telemetry().await {
            Ok(telemetry) => Outcome::printed(render(&telemetry, args.json)),
            Err(e) => Outcome::failed(&e),
        };
    };
    let mut ticks = tokio::time::interval(Duration::from_secs_f64(1.0 / hz));
    ticks.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    let interrupted = tokio::signal::ctrl_c();
    tokio::pin!(interrupted);
    loop {
        tokio::select! {
            _ = &mut interrupted => break,
            _ = ticks.tick() => {}
        }
        match link.read_telemetry().await {
            Ok(telemetry) => {
                let mut lines = watch_lines(&telemetry, args.json, SystemTime::now());
                // A blank line between tables.
                lines.extend((!args.json).then(String::new));
                match output::print_lines(&lines) {
                    Ok(Printed::All) => {}
                    // The reader went away (a closed pipe): nothing left to do.
                    Ok(Printed::ReaderGone) => break,
                    Err(e) => return Outcome::error(format!("cannot write the output: {e}"), 1),
                }
            }
            Err(e) => output::print_error(&e.to_string()),
        }
    }
    Outcome::printed(Vec::new())
}

/// The snapshot as the `--json` object or the readable table.
pub fn render(telemetry: &Telemetry, json: bool) -> Vec<String> {
    if json {
        return match serde_json::to_string(telemetry) {
            Ok(line) => vec![line],
            Err(e) => vec![format!("{{\"error\":\"{e}\"}}")],
        };
    }
    table(telemetry)
}

/// A `--watch` snapshot, stamped (RFC 3339, UTC, ms) per table line or as a JSON `"time"`.
pub fn watch_lines(telemetry: &Telemetry, json: bool, at: SystemTime) -> Vec<String> {
    let time = rfc3339_ms(at);
    if json {
        return match serde_json::to_value(telemetry) {
            Ok(serde_json::Value::Object(mut object)) => {
                object.insert("time".into(), serde_json::Value::String(time));
                vec![serde_json::Value::Object(object).to_string()]
            }
            Ok(_) => vec![format!(
                "{{\"time\":\"{time}\",\"error\":\"not an object\"}}"
            )],
            Err(e) => vec![format!("{{\"time\":\"{time}\",\"error\":\"{e}\"}}")],
        };
    }
    table(telemetry)
        .into_iter()
        .map(|line| format!("{time}  {line}"))
        .collect()
}

fn flag_list(flags: FlagSet) -> String {
    if flags.is_empty() {
        return "none".into();
    }
    flags
        .names()
        .into_iter()
        .map(|name| match Flag::ALL.iter().find(|f| f.key() == name) {
            Some(flag) => format!("{name} ({})", flag.description()),
            None => name,
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The readable table: one line per group, one row per joint.
pub fn table(t: &Telemetry) -> Vec<String> {
    let mut lines = vec![format!("robot state   {}", t.robot_state)];
    if let Some(from_inputs) = t.state_from_inputs
        && t.robot_state.known() != Some(from_inputs)
    {
        lines.push(format!(
            "              but the arm state inputs (discrete inputs 0-9) say {from_inputs}"
        ));
    }
    lines.push(format!("faults        {}", flag_list(t.faults)));
    lines.push(format!("warnings      {}", flag_list(t.warnings)));
    let f = |v: f32, decimals: usize| fixed(f64::from(v), decimals);
    let arm = t.arm;
    lines.push(arm_line([
        arm.current,
        arm.voltage,
        arm.cpu_temperature,
        arm.ambient_temperature,
    ]));
    lines.push(format!(
        "action        {}   id {}   move type {}",
        t.action.status, t.action.id, t.action.move_type
    ));
    lines.push(format!(
        "speed limits  linear {}   angular {} deg/s",
        linear_speed(f64::from(t.speed_limits.linear)),
        f(t.speed_limits.angular, 1)
    ));
    // Holding register 0 is left out: the ICD gives it no meaning beyond a list of coils.
    lines.push(
        "joint  position deg  velocity deg/s  torque N m  current A  temperature C".to_string(),
    );
    for (i, j) in t.joints.iter().enumerate() {
        lines.push(format!(
            "{:>5}  {:>12}  {:>14}  {:>10}  {:>9}  {:>13}",
            i + 1,
            f(j.position, 3),
            f(j.velocity, 3),
            f(j.torque, 3),
            f(j.current, 3),
            f(j.temperature, 1)
        ));
    }
    let p = t.tcp.pose;
    lines.extend(tool_lines(
        [p.x, p.y, p.z].map(|m| f64::from(m) * 1000.0),
        [p.theta_x, p.theta_y, p.theta_z],
        &t.tcp.twist.to_array(),
        &t.tcp.wrench.to_array(),
    ));
    lines
}
