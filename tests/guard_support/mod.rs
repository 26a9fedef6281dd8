//! What the stop guard tests share: the in-test simulated arm and how to watch it move.

// Each test file uses its own part of this module.
#![allow(dead_code)]

use std::time::Duration;

use tokio::time::Instant;

use armjog::kortex::{ReferenceFrame, Twist};
use armjog::link::{ModbusConfig, ModbusLink};
use armjog::sim::{SimConfig, Simulator};

pub const BIN: &str = env!("CARGO_BIN_EXE_armjog");

pub async fn simulator() -> Simulator {
    Simulator::start(SimConfig::ephemeral())
        .await
        .expect("simulator")
}

pub fn modbus_addr(sim: &Simulator) -> String {
    sim.modbus_addr
        .expect("the simulator serves Modbus")
        .to_string()
}

pub fn log_dir() -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("armjog-guard-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// Whether the simulated arm moves, and its tool x in mm.
pub async fn arm_state(sim: &Simulator) -> (bool, f64) {
    sim.arm
        .with(|arm, _| (arm.is_moving(), arm.pose().position.x * 1000.0))
        .await
        .expect("simulated arm")
}

/// Polls until the arm's motion is `moving`; returns how long it took, or `None` after `within`.
pub async fn wait_moving(sim: &Simulator, moving: bool, within: Duration) -> Option<Duration> {
    let started = Instant::now();
    while started.elapsed() < within {
        if arm_state(sim).await.0 == moving {
            return Some(started.elapsed());
        }
        tokio::time::sleep(Duration::from_millis(5)).await;
    }
    None
}

/// Asserts the tool stays where it is for a while (the stop held, nothing restarted it).
pub async fn assert_still(sim: &Simulator) {
    let (_, x0) = arm_state(sim).await;
    tokio::time::sleep(Duration::from_millis(400)).await;
    let (moving, x1) = arm_state(sim).await;
    assert!(
        !moving && (x1 - x0).abs() < 0.05,
        "the arm keeps still: {x0:.3} -> {x1:.3} mm"
    );
}

/// A client standing in for the console's twist: 20 mm/s +X, far from any limit for seconds.
pub async fn start_twist(sim: &Simulator) -> ModbusLink {
    let mut config = ModbusConfig::new(modbus_addr(sim));
    config.poll_rate_hz = None;
    config.twist_hold = None;
    let (link, _events) = ModbusLink::connect(config).await.expect("connect");
    let twist = Twist {
        x: 0.02,
        ..Twist::default()
    };
    link.jog_twist(ReferenceFrame::Base, twist)
        .await
        .expect("twist");
    assert!(
        wait_moving(sim, true, Duration::from_secs(5))
            .await
            .is_some(),
        "the twist runs"
    );
    link
}
