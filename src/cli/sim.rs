//! `armjog sim`: the simulated Gen3 arm, standalone, serving Talos and Kinova Modbus.

use std::time::Duration;

use clap::Args;

use super::output;

use crate::link::Dialect;
use crate::sim::arm_model::Arm;
use crate::sim::kinematics::{self, HOME_DEG, NoNearLimit};
use crate::sim::talos_server::{NetworkFaults, TalosServerConfig};
use crate::sim::{
    DEFAULT_MODBUS_LISTEN, DEFAULT_TALOS_LISTEN, SimConfig, Simulator, UnlistedReads,
};
use crate::talos::Checksum;

#[derive(Debug, Args)]
pub struct SimArgs {
    /// Where the Talos operator listens.
    #[arg(long, default_value = DEFAULT_TALOS_LISTEN, value_name = "ADDR")]
    pub talos_listen: String,
    /// Where the Kinova Modbus server listens.
    #[arg(long, default_value = DEFAULT_MODBUS_LISTEN, value_name = "ADDR")]
    pub modbus_listen: String,
    /// Run no Modbus server.
    #[arg(long)]
    pub no_modbus: bool,
    /// The operator's reply dialect: typed ICD replies, or the deployed operator's "ACK\0".
    #[arg(long, default_value = "icd", value_parser = super::values::dialect_parser())]
    pub dialect: Dialect,
    /// The operator's checksum dialect.
    #[arg(long, default_value = "crc16", value_parser = super::values::checksum_parser())]
    pub checksum: Checksum,
    /// Serve one Talos client at a time, as the deployed operator does: a second connection is
    /// accepted by the kernel but gets no answer until the first one closes.
    #[arg(long)]
    pub one_client: bool,
    /// The operator's tool speed cap at 100 % speed, mm/s: bounds every motion it commands
    /// (cartesian and polar, continuous and discrete, joint jogs, go to, home).
    #[arg(long, default_value_t = 250.0, value_name = "MM_S", value_parser = super::values::tool_speed)]
    pub max_jog_speed: f64,
    /// Fault injection: wait this long before every reply, ms.
    #[arg(long, default_value_t = 0, value_name = "MS")]
    pub reply_delay: u64,
    /// Fault injection: drop every Nth reply (1 drops all).
    #[arg(long, default_value_t = 0, value_name = "N")]
    pub drop_every: u32,
    /// Fault injection: close each Talos connection after N frames.
    #[arg(long, value_name = "N")]
    pub close_after: Option<u32>,
    /// Fault injection: start with this Kinova fault bit raised (0-30, e.g. 4 joint fault).
    #[arg(long, value_name = "BIT", value_parser = clap::value_parser!(u32).range(0..=30))]
    pub fault: Option<u32>,
    /// Start with this joint (2, 4 or 6; the others turn continuously) 2 degrees short of its
    /// upper limit, the others at home: the console then names it (`J4 2.0° from limit`).
    #[arg(long, value_name = "JOINT", value_parser = clap::value_parser!(u8).range(1..=7))]
    pub near_limit: Option<u8>,
    /// Start with the elbow (J4) 3 degrees short of straight, the others at home: the console
    /// then names the arm as near a singularity (`near singularity (κ 253)`).
    #[arg(long, conflicts_with = "near_limit")]
    pub near_singularity: bool,
    /// Answer Modbus reads that span addresses the ICD does not list (zeros there), as many
    /// Modbus servers do, rather than refuse them ("illegal data address") as a strict arm does.
    /// The console then reads a snapshot in 4 requests instead of 9.
    #[arg(long)]
    pub answer_unlisted_reads: bool,
}

impl SimArgs {
    pub fn config(&self) -> Result<SimConfig, NoNearLimit> {
        let q = match (self.near_limit, self.near_singularity) {
            (Some(joint), _) => kinematics::near_limit_pose_deg(joint)?,
            (None, true) => kinematics::near_singularity_pose_deg(),
            (None, false) => HOME_DEG,
        };
        let mut arm = Arm::at(kinematics::to_radians(&q));
        if let Some(bit) = self.fault {
            arm.raise_fault(bit);
        }
        Ok(SimConfig {
            talos_listen: self.talos_listen.clone(),
            modbus_listen: (!self.no_modbus).then(|| self.modbus_listen.clone()),
            talos: TalosServerConfig {
                checksum: self.checksum,
                dialect: self.dialect,
                one_client: self.one_client,
                ..TalosServerConfig::default()
            },
            faults: NetworkFaults {
                reply_delay: Duration::from_millis(self.reply_delay),
                drop_every_nth_reply: self.drop_every,
                close_after_frames: self.close_after,
            },
            arm,
            max_jog_speed: self.max_jog_speed / 1000.0,
            positions: Vec::new(),
            unlisted_reads: if self.answer_unlisted_reads {
                UnlistedReads::Zero
            } else {
                UnlistedReads::Refuse
            },
        })
    }
}

/// Runs the simulator until SIGINT or SIGTERM. Returns the exit status.
pub async fn run(args: &SimArgs) -> i32 {
    let config = match args.config() {
        Ok(config) => config,
        Err(reason) => return output::fail(reason, 2),
    };
    let sim = match Simulator::start(config).await {
        Ok(sim) => sim,
        Err(e) => return output::fail(e, 1),
    };
    // Serves until signalled even if no one reads the banner (`| head`).
    let banner = [
        // Said first and plainly: whoever reads this terminal must not take it for a real arm.
        format!(
            "armjog sim: SIMULATED ARM (no hardware): a Kinova Gen3 model {}",
            match (args.near_limit, args.near_singularity) {
                (Some(joint), _) =>
                    format!("at the home pose but J{joint}, 2 deg short of its limit"),
                (None, true) => format!(
                    "at the home pose but J4, {} deg short of straight (near a singularity)",
                    kinematics::NEAR_SINGULARITY_ELBOW_DEG
                ),
                (None, false) => "at the home pose".to_string(),
            }
        ),
        format!(
            "  talos operator  {} ({}, {}{})",
            sim.talos_addr,
            args.dialect,
            args.checksum,
            if args.one_client {
                ", one client at a time"
            } else {
                ""
            }
        ),
        match sim.modbus_addr {
            Some(addr) => format!("  kinova modbus   {addr} (any unit id)"),
            None => "  kinova modbus   off".to_string(),
        },
        "Ctrl-C stops it.".to_string(),
    ];
    if let Err(e) = output::print_lines(&banner) {
        tracing::warn!("sim: cannot print the banner: {e}");
    }
    wait_for_signal().await;
    if let Err(e) = output::print_line("armjog sim: stopped") {
        tracing::warn!("sim: cannot print the last line: {e}");
    }
    0
}

async fn wait_for_signal() {
    use tokio::signal::unix::{SignalKind, signal};
    match (
        signal(SignalKind::interrupt()),
        signal(SignalKind::terminate()),
    ) {
        (Ok(mut int), Ok(mut term)) => {
            tokio::select! {
                _ = int.recv() => {}
                _ = term.recv() => {}
            }
        }
        _ => {
            let _ = tokio::signal::ctrl_c().await;
        }
    }
}
