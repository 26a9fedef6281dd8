//! `armjog status`: one complete snapshot of a Kinova arm over Modbus, as a table or JSON, once
//! or repeatedly.

use std::time::Duration;

use clap::Args;

use super::Outcome;
use super::modbus::ArmAddress;
use super::output::{self, Printed};
use crate::kortex::{CodeName, Flag, FlagSet, Telemetry};
use crate::link::ModbusLink;

/// Snapshots per second of `--watch` without a value.
pub const DEFAULT_WATCH_HZ: f64 = 1.0;

#[derive(Debug, Args)]
pub struct StatusArgs {
    #[command(flatten)]
    pub arm: ArmAddress,
    /// Print one JSON object (one per line with --watch) instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Keep printing snapshots, HZ a second (1 if no value), until interrupted.
    #[arg(
        long,
        value_name = "HZ",
        num_args = 0..=1,
        default_missing_value = "1",
        value_parser = parse_rate
    )]
    pub watch: Option<f64>,
}

fn parse_rate(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(hz) if hz.is_finite() && hz > 0.0 && hz <= 100.0 => Ok(hz),
        _ => Err(format!("'{s}' is not a rate in (0, 100] Hz")),
    }
}

/// Runs `armjog status`, printing each snapshot as it comes. With `--watch`, a failed read is
/// reported on stderr and watching goes on (the link reconnects); Ctrl-C ends it with status 0.
pub async fn run(args: &StatusArgs) -> Outcome {
    let link = match ModbusLink::connect(args.arm.config()).await {
        Ok((link, _events)) => link,
        Err(e) => return Outcome::failed(&e),
    };
    let Some(hz) = args.watch else {
        return match link.read_telemetry().await {
            Ok(telemetry) => Outcome {
                stdout: render(&telemetry, args.json),
                stderr: None,
                exit_code: 0,
            },
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
                let mut lines = render(&telemetry, args.json);
                if !args.json {
                    // A blank line between tables.
                    lines.push(String::new());
                }
                match output::print_lines(&lines) {
                    Ok(Printed::All) => {}
                    // The reader went away (a closed pipe): nothing left to do.
                    Ok(Printed::ReaderGone) => break,
                    Err(e) => {
                        return Outcome {
                            stdout: Vec::new(),
                            stderr: Some(format!("cannot write the output: {e}")),
                            exit_code: 1,
                        };
                    }
                }
            }
            Err(e) => output::print_error(&e.to_string()),
        }
    }
    Outcome {
        stdout: Vec::new(),
        stderr: None,
        exit_code: 0,
    }
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

fn flag_list(flags: FlagSet) -> String {
    if flags.is_empty() {
        return "none".into();
    }
    flags
        .names()
        .into_iter()
        .map(|name| {
            let described = Flag::ALL.iter().find(|f| f.key() == name);
            match described {
                Some(flag) => format!("{name} ({})", flag.description()),
                None => name,
            }
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
            "              (discrete inputs 0-9 say {from_inputs})"
        ));
    }
    lines.push(format!("faults        {}", flag_list(t.faults)));
    lines.push(format!("warnings      {}", flag_list(t.warnings)));
    lines.push(format!(
        "arm           current {:.3} A   voltage {:.3} V   cpu {:.1} C   ambient {:.1} C",
        t.arm.current, t.arm.voltage, t.arm.cpu_temperature, t.arm.ambient_temperature
    ));
    lines.push(format!(
        "action        {}   id {}   move type {}",
        t.action.status, t.action.id, t.action.move_type
    ));
    lines.push(format!(
        "speed limits  linear {:.3} m/s   angular {:.1} deg/s",
        t.speed_limits.linear, t.speed_limits.angular
    ));
    // The ICD gives register 0 no meaning beyond a list of the coils' actions.
    lines.push(format!(
        "holding reg 0 {} (the ICD lists 0 quick_stop, 1 abort, 2 fault_reset)",
        t.control.code()
    ));
    lines.push(
        "joint  position deg  velocity deg/s  torque N m  current A  temperature C".to_string(),
    );
    for (i, j) in t.joints.iter().enumerate() {
        lines.push(format!(
            "{:>5}  {:>12.3}  {:>14.3}  {:>10.3}  {:>9.3}  {:>13.1}",
            i + 1,
            j.position,
            j.velocity,
            j.torque,
            j.current,
            j.temperature
        ));
    }
    let p = t.tcp.pose;
    lines.push(format!(
        "tcp pose      x {:.4} m   y {:.4} m   z {:.4} m   theta x {:.2}   y {:.2}   z {:.2} deg",
        p.x, p.y, p.z, p.theta_x, p.theta_y, p.theta_z
    ));
    let v = t.tcp.twist;
    lines.push(format!(
        "tcp twist     x {:.4}   y {:.4}   z {:.4} m/s   theta x {:.2}   y {:.2}   z {:.2} deg/s",
        v.x, v.y, v.z, v.theta_x, v.theta_y, v.theta_z
    ));
    let w = t.tcp.wrench;
    lines.push(format!(
        "tcp wrench    force x {:.2}   y {:.2}   z {:.2} N   torque x {:.3}   y {:.3}   z {:.3} N m",
        w.force_x, w.force_y, w.force_z, w.torque_x, w.torque_y, w.torque_z
    ));
    lines
}
