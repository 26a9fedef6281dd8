//! The stop guard: a dead or frozen console cannot leave a Modbus twist running.
//!
//! The simulated arm runs in the test (its Modbus twist, like a real Kinova's, has no
//! watchdog); the guard is the real binary (`armjog guard`), fed through a pipe the test holds
//! like a console would, or started by the arm driver as the console starts it.
//! `guard_console.rs` kills the real console binary mid-jog. Bounds are generous for a
//! loaded CI; the design target of 300 ms from the console's death to the stop is logged, not
//! asserted.

use crate::guard_support;

use std::time::Duration;

use tokio::sync::mpsc::UnboundedReceiver;
use tokio::time::Instant;

use armjog::kortex::{ReferenceFrame, Twist};
use armjog::link::driver::{Driver, DriverConfig};
use armjog::link::guard::GuardPolicy;
use armjog::link::interface::{ArmCommand, ArmError, ArmEvent, CommandKind};
use armjog::link::{ModbusConfig, ModbusLink};
use armjog::sim::Simulator;
use guard_support::{
    BIN, Guard, arm_state, assert_moving, assert_still, guard_down, guard_killed_and_replaced,
    guard_ready, modbus_addr, send_signal, simulator, start_twist, wait_event, wait_moving,
};

/// The guard for the simulator's Modbus server, beaten once, and the console's twist running.
async fn twist_with_guard(sim: &Simulator) -> (Guard, ModbusLink) {
    let mut guard = Guard::start(&["--modbus", &modbus_addr(sim), "--unit", "1"]).await;
    guard.beat().await;
    let console_link = start_twist(sim).await;
    (guard, console_link)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_guard_stops_a_running_twist_when_the_console_pipe_closes() {
    let sim = simulator().await;
    let (mut guard, _console_link) = twist_with_guard(&sim).await;
    guard.beat_for(Duration::from_millis(300)).await;
    assert!(
        arm_state(&sim).await.0,
        "still moving with the console alive"
    );

    // The console dies: its end of the pipe closes.
    drop(guard.stdin.take());
    let took = wait_moving(&sim, false, Duration::from_secs(2))
        .await
        .expect("the guard stops the twist within 2 s of the pipe closing");
    eprintln!(
        "pipe closed -> arm stopped in {:.1} ms",
        took.as_secs_f64() * 1000.0
    );
    assert_still(&sim).await;

    let said = guard.said().await;
    assert!(
        said.starts_with("stopped the console is gone"),
        "the guard reports its stop: {said:?}"
    );
    let status = guard.exit_status("the guard exits after the stop").await;
    assert!(status.success(), "exit status {status}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_silent_console_gets_its_twist_stopped_and_the_guard_keeps_watching() {
    let sim = simulator().await;
    let (mut guard, console_link) = twist_with_guard(&sim).await;

    // The pipe stays open but no heartbeat comes: a frozen console.
    let took = wait_moving(&sim, false, Duration::from_secs(4))
        .await
        .expect("the guard stops the twist after the heartbeat timeout (1 s)");
    eprintln!(
        "heartbeat lost -> arm stopped after {:.0} ms",
        took.as_secs_f64() * 1000.0
    );
    let said = guard.said().await;
    assert!(
        said.starts_with("stopped no heartbeat"),
        "the guard reports why: {said:?}"
    );
    guard.assert_watching();

    // The console is back: a fresh twist runs while it beats, and the guard leaves it alone.
    console_link.stop().await.expect("stop");
    guard.beat().await;
    let twist = Twist {
        x: -0.02,
        ..Twist::default()
    };
    console_link
        .jog_twist(ReferenceFrame::Base, twist)
        .await
        .expect("twist");
    guard.beat_for(Duration::from_millis(1500)).await;
    assert!(arm_state(&sim).await.0, "a beating console keeps its twist");

    drop(guard.stdin.take());
    wait_moving(&sim, false, Duration::from_secs(2))
        .await
        .expect("stopped when the pipe closes");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_terminated_guard_stops_the_arm_on_its_way_out() {
    let sim = simulator().await;
    let (mut guard, _console_link) = twist_with_guard(&sim).await;
    guard.beat().await;
    let pid = guard.child.id().expect("guard pid");
    assert!(send_signal(pid, "-TERM"));
    wait_moving(&sim, false, Duration::from_secs(2))
        .await
        .expect("the guard stops the twist before it exits");
    let said = guard.said().await;
    assert!(said.starts_with("stopped SIGTERM"), "{said:?}");
    let status = guard.exit_status("the guard exits").await;
    assert!(status.success(), "exit status {status}");
}

fn jog_x() -> ArmCommand {
    ArmCommand::Jog(armjog::console::jog::JogMotion::Cartesian { x: 1, y: 0, z: 0 })
}

fn modbus_driver(sim: &Simulator, guard: GuardPolicy) -> (Driver, UnboundedReceiver<ArmEvent>) {
    let mut config = DriverConfig::new(None, Some(ModbusConfig::new(modbus_addr(sim))));
    config.guard = guard;
    // Slow enough to stay far from any limit for the whole test.
    config.max_jog_speed = 0.04;
    Driver::spawn(config)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_console_refuses_modbus_jogs_when_its_guard_cannot_start() {
    let sim = simulator().await;
    let missing = std::path::PathBuf::from("/nonexistent/armjog-guard");
    let (driver, mut events) = modbus_driver(&sim, GuardPolicy::Spawn(missing));
    let reason = guard_down(&mut events, Duration::from_secs(10)).await;
    assert!(
        reason.contains("cannot start the stop guard /nonexistent/armjog-guard"),
        "names the program: {reason}"
    );

    assert!(driver.send(jog_x()));
    let failed = wait_event(
        &mut events,
        Duration::from_secs(5),
        "the jog refused",
        |e| {
            matches!(
                e,
                ArmEvent::Failed {
                    command: CommandKind::Jog,
                    ..
                }
            )
        },
    )
    .await;
    let ArmEvent::Failed {
        error: error @ ArmError::GuardNotRunning(_),
        ..
    } = failed
    else {
        panic!("refused for want of the guard: {failed:?}")
    };
    let reason = error.to_string();
    assert!(
        reason.starts_with("stop guard not running:"),
        "says why: {reason}"
    );
    tokio::time::sleep(Duration::from_millis(300)).await;
    assert!(!arm_state(&sim).await.0, "nothing moved");
    // Home is motion too.
    assert!(driver.send(ArmCommand::Home));
    wait_event(&mut events, Duration::from_secs(5), "home refused", |e| {
        matches!(e, ArmEvent::Failed { command: CommandKind::Home, error: ArmError::GuardNotRunning(reason) } if reason.to_string().contains("stop guard"))
    })
    .await;
    driver.shutdown().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_killed_guard_stops_the_jog_and_is_restarted() {
    let sim = simulator().await;
    let (driver, mut events) = modbus_driver(&sim, GuardPolicy::Spawn(BIN.into()));
    let pid = guard_ready(&mut events, Duration::from_secs(10), "the guard ready").await;

    // A held key: the jog is re-sent every 100 ms.
    let jogging = {
        let driver = driver.clone();
        tokio::spawn(async move {
            while driver.send(jog_x()) {
                tokio::time::sleep(Duration::from_millis(100)).await;
            }
        })
    };
    assert_moving(&sim, "jogs over Modbus with a guard").await;

    // The jog goes on being re-sent, but the driver refuses it and stopped the arm.
    guard_killed_and_replaced(&sim, &mut events, pid, "the arm stops when its guard dies").await;
    jogging.abort();
    driver.send(ArmCommand::Stop);
    driver.shutdown().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_guard_that_stops_answering_is_replaced() {
    let sim = simulator().await;
    let (driver, mut events) = modbus_driver(&sim, GuardPolicy::Spawn(BIN.into()));
    let pid = guard_ready(&mut events, Duration::from_secs(10), "the guard ready").await;
    // A frozen guard: alive as a process, but it would not stop anything.
    assert!(send_signal(pid, "-STOP"));
    let reason = guard_down(&mut events, Duration::from_secs(15)).await;
    assert!(reason.contains("stopped answering"), "says why: {reason}");
    assert!(driver.send(jog_x()));
    wait_event(&mut events, Duration::from_secs(5), "the jog refused", |e| {
        matches!(e, ArmEvent::Failed { command: CommandKind::Jog, error: ArmError::GuardNotRunning(reason) } if reason.to_string().contains("stop guard not running"))
    })
    .await;
    let again = guard_ready(&mut events, Duration::from_secs(15), "a new guard").await;
    assert_ne!(again, pid, "a fresh guard process");
    let until = Instant::now() + Duration::from_secs(5);
    while std::path::Path::new(&format!("/proc/{pid}")).exists() && Instant::now() < until {
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    assert!(
        !std::path::Path::new(&format!("/proc/{pid}")).exists(),
        "the frozen guard was ended"
    );
    driver.shutdown().await;
}
