//! `armjog sim --near-singularity` end to end: the simulator starts with the elbow 3 degrees
//! short of straight; a console whose link reports joint angles (Modbus, Talos hardware
//! telemetry) names the arm as near a singularity, and one over the ack dialect, which reports
//! nothing, shows no estimate.

use crate::event_loop;
use std::time::{Duration, Instant};

use armjog::console::app::Input;
use armjog::console::positions::PositionBook;
use armjog::console::view::View;
use armjog::link::driver::{Driver, DriverConfig};
use armjog::link::interface::{LinkStatus, TelemetrySource};
use armjog::link::{Dialect, ModbusConfig, TalosConfig};
use armjog::sim::arm_model::Arm;
use armjog::sim::kinematics::{near_singularity_pose_deg, to_radians};
use armjog::sim::talos_server::TalosServerConfig;
use armjog::sim::{SimConfig, Simulator};

enum Link {
    Modbus,
    TalosHardware,
    TalosAck,
}

/// The console's view and status bar once the link is up (and, when the link has any, with
/// telemetry), on a simulator at the near-singular pose.
async fn status_over(link: Link) -> (View, String) {
    let dialect = match link {
        Link::TalosAck => Dialect::Ack,
        _ => Dialect::Icd,
    };
    let sim = Simulator::start(SimConfig {
        arm: Arm::at(to_radians(&near_singularity_pose_deg())),
        talos: TalosServerConfig {
            dialect,
            ..TalosServerConfig::default()
        },
        ..SimConfig::ephemeral()
    })
    .await
    .expect("simulator");
    let talos = TalosConfig {
        dialect,
        ..TalosConfig::new(sim.talos_addr.to_string())
    };
    let config = match link {
        Link::Modbus => DriverConfig::new(
            None,
            Some(ModbusConfig::new(
                sim.modbus_addr.expect("modbus").to_string(),
            )),
        ),
        Link::TalosHardware | Link::TalosAck => DriverConfig::new(Some(talos), None),
    };
    let expects_telemetry = config.telemetry_source() != TelemetrySource::None;
    let mut app = event_loop::app_for(&config, PositionBook::new());
    let (driver, mut events) = Driver::spawn(config);
    // Generous: a loaded CI machine may take a while to connect and poll.
    let within = tokio::time::Instant::now() + Duration::from_secs(20);
    while !(matches!(app.link(), LinkStatus::Up { .. })
        && (app.telemetry().is_some() || !expects_telemetry))
    {
        let event = tokio::time::timeout_at(within, events.recv())
            .await
            .expect("link up (with telemetry where the link has it) within 20 s")
            .expect("driver events");
        // Nothing here moves the arm: the app's effects are not needed.
        app.handle(Input::Arm(event), Instant::now());
    }
    if !expects_telemetry {
        // Half a second more of whatever the link sends: still no angles.
        let until = tokio::time::Instant::now() + Duration::from_millis(500);
        while let Ok(Some(event)) = tokio::time::timeout_at(until, events.recv()).await {
            app.handle(Input::Arm(event), Instant::now());
        }
    }
    let view = View::new(&app);
    let status = event_loop::status_line(&view);
    driver.shutdown().await;
    (view, status)
}

#[tokio::test]
async fn a_console_over_modbus_names_the_singularity() {
    let (view, status) = status_over(Link::Modbus).await;
    let kappa = view.arm.near_singularity.expect("near a singularity");
    // The reported angles are f32: the estimate is the model's 253 to within a unit.
    assert!((kappa - 253.3).abs() < 1.0, "{kappa}");
    assert!(status.contains("near singularity (κ 253)"), "{status}");
    assert!(
        view.arm.near_limits.is_empty(),
        "{:?}",
        view.arm.near_limits
    );
}

#[tokio::test]
async fn a_console_over_talos_hardware_telemetry_names_the_singularity() {
    let (view, status) = status_over(Link::TalosHardware).await;
    let kappa = view.arm.near_singularity.expect("near a singularity");
    // Within what the hardware telemetry's angle resolution allows.
    assert!((kappa - 253.3).abs() < 5.0, "{kappa}");
    assert!(
        status.contains(&format!("near singularity (κ {kappa:.0})")),
        "{status}"
    );
}

#[tokio::test]
async fn a_console_over_the_ack_dialect_shows_no_estimate() {
    let (view, status) = status_over(Link::TalosAck).await;
    assert_eq!(view.arm.telemetry, None);
    assert_eq!(view.arm.near_singularity, None);
    assert!(!status.contains("singularity"), "{status}");
}
