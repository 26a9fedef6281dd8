//! `armjog` with no subcommand: the console, on the built-in simulated arm unless told otherwise.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

use clap::{Args, ValueEnum};

use super::output::fail;

use crate::console::book_io;
use crate::console::keymap::Keymap;
use crate::console::positions::{BookError, PositionBook, book_key, default_path};
use crate::console::run::{ConsoleSetup, run};
use crate::kortex::PollPlan;
use crate::link::Dialect;
use crate::link::driver::DriverConfig;
use crate::link::fence::Fence;
use crate::link::guard::GuardPolicy;
use crate::link::modbus::{self, ModbusConfig};
use crate::link::speed::{SpeedCap, SpeedCapError};
use crate::link::talos::{self, TalosConfig};
use crate::sim::SimConfig;
use crate::sim::operator::RememberedPosition;
use crate::talos::Checksum;

/// How key releases are detected.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum KeyRelease {
    /// Probe the terminal: release events if it speaks the kitty protocol, else auto-repeat.
    Auto,
    /// Assume release events (kitty keyboard protocol).
    Events,
    /// Assume none: detect holds from auto-repeat.
    Repeat,
}

#[derive(Debug, Args)]
pub struct ConsoleArgs {
    /// Jog through a Talos operator, HOST:PORT (port 61616 if omitted).
    #[arg(long, value_name = "HOST:PORT")]
    pub talos: Option<String>,
    /// Reach a Kinova arm over Modbus TCP, HOST:PORT (port 502 if omitted). With --talos too,
    /// jogging goes through Talos and telemetry comes over Modbus.
    #[arg(long, value_name = "HOST:PORT")]
    pub modbus: Option<String>,
    /// Talos reply dialect.
    #[arg(long, default_value = "icd", value_parser = super::values::dialect_parser())]
    pub dialect: Dialect,
    /// Talos checksum dialect.
    #[arg(long, default_value = "crc16", value_parser = super::values::checksum_parser())]
    pub checksum: Checksum,
    /// Modbus unit id.
    #[arg(long, default_value_t = modbus::DEFAULT_UNIT)]
    pub unit: u8,
    /// Keymap: a built-in name (default, numpad) or a JSON file.
    #[arg(long, default_value = "default", value_name = "NAME|PATH")]
    pub keymap: String,
    /// The tool speed cap at 100 % speed, mm/s: bounds every motion (cartesian and polar jogs,
    /// joint jogs, steps, go to, home); the speed keys pick a percentage of it. Over Modbus the
    /// console commands within it; over Talos it sets the operator's speed to the percentage of
    /// --operator-full-speed that keeps within it. Where there is telemetry, a motion seen more
    /// than 10 % over it for three samples in a row is stopped.
    #[arg(long, default_value_t = 250.0, value_name = "MM_S", value_parser = super::values::tool_speed)]
    pub max_jog_speed: f64,
    /// The Talos operator's tool speed at its own 100 %, mm/s (the simulator's default is 250):
    /// Set Speed asks the operator for the percentage of it that keeps the tool under
    /// --max-jog-speed. Too low a value lets the operator run over the cap (the console then
    /// stops the motion where telemetry shows it). The built-in simulator runs at it.
    #[arg(long, default_value_t = 250.0, value_name = "MM_S", value_parser = super::values::tool_speed)]
    pub operator_full_speed: f64,
    /// How often a held jog is re-sent, per second (the operator's watchdog is 500 ms).
    #[arg(long, default_value_t = 10.0, value_name = "HZ", value_parser = super::values::refresh_hz)]
    pub refresh_hz: f64,
    /// Modbus telemetry polls per second.
    #[arg(long, default_value_t = 30.0, value_name = "HZ", value_parser = super::values::telemetry_hz)]
    pub telemetry_hz: f64,
    /// How key releases are detected.
    #[arg(long, value_enum, default_value_t = KeyRelease::Auto)]
    pub key_release: KeyRelease,
    /// The file of named positions (default: one per arm in the user's data directory).
    #[arg(long, value_name = "FILE")]
    pub positions: Option<PathBuf>,
    /// Id of the Home action on a Kinova arm (Modbus).
    #[arg(long, default_value_t = modbus::DEFAULT_HOME_ACTION_ID, value_parser = super::values::stored_action_id)]
    pub home_action_id: u16,
    /// Do not record the session (the flight recorder's MCAP file beside the audit log).
    #[arg(long)]
    pub no_record: bool,
}

/// Why the console's speed options cannot be used (together).
#[derive(Debug, PartialEq, thiserror::Error)]
enum BadSpeeds {
    #[error("--max-jog-speed {0} mm/s: {1}")]
    Cap(f64, SpeedCapError),
    #[error(
        "--max-jog-speed {cap} mm/s is below 1 % of --operator-full-speed {full} mm/s: the \
         operator's slowest speed would be over the cap"
    )]
    OperatorTooFast { cap: f64, full: f64 },
    #[error("--operator-full-speed {0} mm/s: {1}")]
    OperatorFullSpeed(f64, SpeedCapError),
}

impl ConsoleArgs {
    /// Checks what no one value says alone, before anything starts (each value's own range is
    /// its parser's: `cli::values`).
    fn validate(&self) -> Result<(), BadSpeeds> {
        // The driver's cap, made here first so a bad one is refused before anything starts.
        let (cap, full) = (self.max_jog_speed, self.operator_full_speed);
        let checked = SpeedCap::new(cap / 1000.0).map_err(|e| BadSpeeds::Cap(cap, e))?;
        match checked.with_operator(full / 1000.0) {
            Ok(_) => Ok(()),
            Err(SpeedCapError::OperatorTooFast) => Err(BadSpeeds::OperatorTooFast { cap, full }),
            Err(e) => Err(BadSpeeds::OperatorFullSpeed(full, e)),
        }
    }

    fn driver_config(
        &self,
        talos_addr: Option<String>,
        modbus_addr: Option<String>,
    ) -> DriverConfig {
        let talos = talos_addr.map(|addr| {
            let mut c = TalosConfig::new(super::with_default_port(&addr, talos::DEFAULT_PORT));
            c.dialect = self.dialect;
            c.checksum = self.checksum;
            c
        });
        let modbus = modbus_addr.map(|addr| {
            let mut c = ModbusConfig::new(super::with_default_port(&addr, modbus::DEFAULT_PORT));
            c.unit = self.unit;
            c.poll_rate_hz = Some(self.telemetry_hz);
            c.home_action_id = self.home_action_id;
            c.polar.max_linear_speed = (self.max_jog_speed / 1000.0) as f32;
            c
        });
        let mut config = DriverConfig::new(talos, modbus);
        config.max_jog_speed = self.max_jog_speed / 1000.0;
        config.operator_full_speed = self.operator_full_speed / 1000.0;
        config
    }
}

/// Runs the console; returns the exit status. `arm_name`: the profile `args` came from; `fence`:
/// its fence, checked as the profile was read.
pub async fn run_console(
    args: &ConsoleArgs,
    arm_name: Option<String>,
    fence: Option<Fence>,
    config_file: Option<PathBuf>,
) -> i32 {
    if let Err(reason) = args.validate() {
        return fail(reason, 2);
    }
    let keymap = match Keymap::load(&args.keymap) {
        Ok(keymap) => keymap,
        Err(e) => return fail(format!("bad keymap: {e}"), 2),
    };
    // With no arm named, the console opens on the built-in simulated arm.
    let on_simulator = args.talos.is_none() && args.modbus.is_none();
    let positions_file = args.positions.clone().or_else(|| {
        let book = book_key(arm_name.as_deref(), "simulator");
        on_simulator.then(|| default_path(&book)).flatten()
    });
    // The built-in operator starts with the book's positions: read once, shared with the console.
    let positions_read = match (&positions_file, on_simulator) {
        (Some(path), true) => Some(book_io::read(path).await),
        _ => None,
    };
    let mut simulator = None;
    let (talos_addr, modbus_addr) = match (&args.talos, &args.modbus) {
        (None, None) => match super::sim_thread::start(SimConfig {
            // The built-in operator runs at its own full speed, as an external `armjog sim` would.
            max_jog_speed: args.operator_full_speed / 1000.0,
            // And knows the positions saved in earlier runs.
            positions: positions_read
                .as_ref()
                .map(remembered_from_read)
                .unwrap_or_default(),
            ..SimConfig::ephemeral()
        })
        .await
        {
            Ok(sim) => {
                let talos = sim.talos_addr.to_string();
                let modbus = sim.modbus_addr.map(|a| a.to_string());
                simulator = Some(sim);
                (Some(talos), modbus)
            }
            Err(e) => return fail(format!("cannot start the simulated arm: {e}"), 1),
        },
        (t, m) => (t.clone(), m.clone()),
    };
    let mut driver = args.driver_config(talos_addr, modbus_addr);
    if simulator.is_some()
        && let Some(modbus) = driver.modbus.as_mut()
    {
        // The simulator answers only the ICD's addresses: read block by block from the start.
        modbus.plan = PollPlan::IcdBlocks;
    }
    // The built-in arm dies with the console; a real arm needs the guard.
    driver.guard = match &simulator {
        Some(_) => GuardPolicy::NotNeeded,
        None => GuardPolicy::Spawn(std::env::current_exe().unwrap_or_else(|e| {
            tracing::warn!("cannot name this program ({e}); starting the guard as /proc/self/exe");
            PathBuf::from("/proc/self/exe")
        })),
    };
    let setup = ConsoleSetup {
        driver,
        keymap,
        refresh: Duration::from_secs_f64(1.0 / args.refresh_hz),
        release_events: match args.key_release {
            KeyRelease::Auto => None,
            KeyRelease::Events => Some(true),
            KeyRelease::Repeat => Some(false),
        },
        positions_file,
        positions_read,
        simulated: simulator.is_some(),
        arm_name,
        fence: fence.map(Arc::new),
        config_file,
        new_profile: new_profile(args, simulator.is_some()),
        record: !args.no_record,
    };
    // Not `eprintln!`: it panics when stderr is gone after a hang-up.
    let code = match run(setup).await {
        Ok(()) => 0,
        Err(e) => fail(e, 1),
    };
    drop(simulator);
    code
}

/// The settings a profile made by teaching a fence gets: how this console reached the arm, and
/// its cap, as the options' text; none on the built-in simulator (its addresses are this run's).
fn new_profile(args: &ConsoleArgs, simulated: bool) -> Vec<(String, String)> {
    if simulated {
        return Vec::new();
    }
    let mut settings = Vec::new();
    let mut set = |key: &str, value: String| settings.push((key.to_string(), value));
    if let Some(talos) = &args.talos {
        set("talos", talos.clone());
        set("dialect", args.dialect.to_string());
        set("checksum", args.checksum.to_string());
        set("operator_full_speed", args.operator_full_speed.to_string());
    }
    if let Some(modbus) = &args.modbus {
        set("modbus", modbus.clone());
        set("unit", args.unit.to_string());
    }
    set("max_jog_speed", args.max_jog_speed.to_string());
    settings
}

/// The book's positions with coordinates, for the built-in simulator's operator at start.
pub fn remembered_for_simulator(book: &PositionBook) -> Vec<RememberedPosition> {
    book.entries()
        .filter_map(|(name, entry)| {
            let cartesian = entry.cartesian?;
            Some(RememberedPosition {
                name: name.to_string(),
                position_m: cartesian.map(|v| f64::from(v) / 10_000.0),
                orientation_deg: entry.orientation.map(|o| o.map(f64::from)),
                joints_deg: entry.joints.map(|j| j.map(f64::from)),
                parent: entry.parent.clone(),
                anchor: entry.anchor,
            })
        })
        .collect()
}

/// The built-in simulator's positions from a read of the book; none if unreadable.
pub fn remembered_from_read(read: &Result<PositionBook, BookError>) -> Vec<RememberedPosition> {
    match read {
        Ok(book) => remembered_for_simulator(book),
        Err(e) => {
            tracing::warn!("the simulated operator starts without remembered positions: {e}");
            Vec::new()
        }
    }
}

#[cfg(test)]
mod tests {
    use clap::Parser;

    use super::super::Cli;
    use super::BadSpeeds;

    fn validate(args: &[&str]) -> Result<(), BadSpeeds> {
        let cli = Cli::try_parse_from([&["armjog"], args].concat()).expect("parses");
        cli.console.validate()
    }

    #[test]
    fn the_operators_full_speed_is_checked_like_the_cap_and_against_it() {
        assert_eq!(validate(&[]), Ok(()));
        assert_eq!(
            validate(&["--max-jog-speed", "5", "--operator-full-speed", "500"]),
            Ok(())
        );
        for option in ["--max-jog-speed", "--operator-full-speed"] {
            for bad in ["0", "-5", "600", "nan", "inf"] {
                let err = Cli::try_parse_from(["armjog", &format!("{option}={bad}")])
                    .expect_err("refused");
                assert_eq!(err.kind(), clap::error::ErrorKind::ValueValidation);
                let text = err.to_string();
                assert!(
                    text.contains(&format!("'{bad}' for '{option} <MM_S>'"))
                        && text.contains("must be above 0 and at most 500 mm/s"),
                    "{text}"
                );
            }
        }
        let err = validate(&["--max-jog-speed", "4", "--operator-full-speed", "500"])
            .expect_err("below 1 %");
        assert_eq!(
            err.to_string(),
            "--max-jog-speed 4 mm/s is below 1 % of --operator-full-speed 500 mm/s: the \
             operator's slowest speed would be over the cap"
        );
    }

    #[test]
    fn the_operators_full_speed_reaches_the_driver() {
        let cli = Cli::try_parse_from(["armjog", "--operator-full-speed", "400"]).expect("parses");
        let config = cli.console.driver_config(Some("op".into()), None);
        assert!((config.operator_full_speed - 0.4).abs() < 1e-12);
        assert!((config.max_jog_speed - 0.25).abs() < 1e-12);
    }
}
