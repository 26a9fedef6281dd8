//! `armjog sim --near-limit 4` end to end: the simulator starts with J4 2 degrees inside its
//! limit, and a console over Modbus names it in the status bar and colours its gauge.

use crate::event_loop;
use std::time::{Duration, Instant};

use armjog::console::app::Input;
use armjog::console::positions::PositionBook;
use armjog::console::view::View;
use armjog::link::ModbusConfig;
use armjog::link::driver::{Driver, DriverConfig};
use armjog::link::interface::LinkStatus;
use armjog::sim::arm_model::Arm;
use armjog::sim::kinematics::{near_limit_pose_deg, to_radians};
use armjog::sim::{SimConfig, Simulator};

#[tokio::test]
async fn a_console_over_modbus_names_j4_two_degrees_from_its_limit() {
    let pose = near_limit_pose_deg(4).expect("J4 has limits");
    let sim = Simulator::start(SimConfig {
        arm: Arm::at(to_radians(&pose)),
        ..SimConfig::ephemeral()
    })
    .await
    .expect("simulator");
    let modbus = ModbusConfig::new(sim.modbus_addr.expect("modbus").to_string());
    let config = DriverConfig::new(None, Some(modbus));
    let mut app = event_loop::app_for(&config, PositionBook::new());
    let (driver, mut events) = Driver::spawn(config);
    // Generous: a loaded CI machine may take a while to connect and poll.
    let within = tokio::time::Instant::now() + Duration::from_secs(20);
    while !(matches!(app.link(), LinkStatus::Up { .. }) && app.telemetry().is_some()) {
        let event = tokio::time::timeout_at(within, events.recv())
            .await
            .expect("link up with telemetry within 20 s")
            .expect("driver events");
        // Nothing here moves the arm: the app's effects (stop on link changes) are not needed.
        app.handle(Input::Arm(event), Instant::now());
    }
    let view = View::new(&app);
    let nearest = view
        .arm
        .near_limits
        .first()
        .expect("a joint near its limit");
    assert_eq!(nearest.joint, 4, "{:?}", view.arm.near_limits);
    assert!(
        (nearest.margin_deg - 2.0).abs() < 0.05,
        "{:?}",
        view.arm.near_limits
    );
    assert_eq!(view.arm.near_limits.len(), 1, "{:?}", view.arm.near_limits);

    let status = event_loop::status_line(&view);
    assert!(status.contains("J4 2.0° from limit"), "{status}");
    driver.shutdown().await;
}
