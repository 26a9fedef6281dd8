//! The stop guard over Talos: `armjog guard --talos` (the real binary, fed through a pipe the
//! test holds as a console would) stops a Home, which no operator watchdog covers, once the
//! console is gone; against an operator that serves one client at a time (the deployed one:
//! `--one-client`, ack dialect, XOR checksum) too. A frozen console still holds its connection:
//! such an operator does not answer the guard, which says so and leaves the move alone; one
//! that takes several clients is stopped. `guard_kill.rs` kills the real console.

use crate::guard_support;

use std::time::Duration;

use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;

use armjog::link::driver::{Driver, DriverConfig};
use armjog::link::guard::GuardPolicy;
use armjog::link::interface::{ArmCommand, ArmError, ArmEvent, GuardStatus, LinkStatus};
use armjog::link::{Dialect, TalosConfig};
use armjog::sim::arm_model::Arm;
use armjog::sim::kinematics::to_radians;
use armjog::sim::stored::RETRACT_DEG;
use armjog::sim::{SimConfig, Simulator};
use armjog::talos::{Checksum, Request};
use guard_support::{
    BIN, Guard, arm_state, assert_moving, assert_still, guard_killed_and_replaced, send_signal,
    wait_event, wait_moving,
};

/// The simulated arm at Retract: Home from there runs for many seconds.
async fn sim_at_retract(dialect: Dialect, checksum: Checksum, one_client: bool) -> Simulator {
    let mut config = SimConfig::ephemeral();
    config.arm = Arm::at(to_radians(&RETRACT_DEG));
    config.talos.dialect = dialect;
    config.talos.checksum = checksum;
    config.talos.one_client = one_client;
    Simulator::start(config).await.expect("simulator")
}

/// The console's connection (the test's stand-in: a bare socket, which closing sends nothing,
/// as a killed console's does not), with Home sent, answered, and the arm seen moving.
async fn console_homing(sim: &Simulator, checksum: Checksum) -> TcpStream {
    let mut stream = TcpStream::connect(sim.talos_addr)
        .await
        .expect("the console connects");
    let home = Request::Home { delay_ms: 0 }
        .to_frame(0)
        .expect("home frame")
        .to_bytes(checksum)
        .expect("home bytes");
    stream.write_all(&home).await.expect("home sent");
    let mut answer = [0u8; 4];
    tokio::time::timeout(Duration::from_secs(5), stream.read_exact(&mut answer))
        .await
        .expect("home answered")
        .expect("home answered");
    assert_moving(sim, "Home runs").await;
    stream
}

/// The simulated arm at Retract, `armjog guard --talos` for it, beaten once, and the console
/// homing the arm.
async fn homing_with_guard(
    dialect: Dialect,
    checksum: Checksum,
    one_client: bool,
) -> (Simulator, Guard, TcpStream) {
    let sim = sim_at_retract(dialect, checksum, one_client).await;
    let talos = sim.talos_addr.to_string();
    let args = [
        "--talos",
        &talos,
        "--dialect",
        dialect.as_str(),
        "--checksum",
        checksum.as_str(),
    ];
    let mut guard = Guard::start(&args).await;
    guard.beat().await;
    let console = console_homing(&sim, checksum).await;
    (sim, guard, console)
}

/// The console dies: the kernel closes its connection and its end of the pipe. Asserts the
/// guard stops Home within 2 s and the stop holds (`stopped` says what stopped, in the log);
/// returns what the guard says.
async fn console_dies(
    sim: &Simulator,
    guard: &mut Guard,
    console: TcpStream,
    stopped: &str,
) -> String {
    drop(console);
    drop(guard.stdin.take());
    let took = wait_moving(sim, false, Duration::from_secs(2))
        .await
        .expect("the guard stops Home within 2 s of the console's death");
    eprintln!("{stopped} in {:.1} ms", took.as_secs_f64() * 1000.0);
    assert_still(sim).await;
    guard.said().await
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_guard_stops_a_talos_home_when_the_console_is_gone() {
    let (sim, mut guard, console) = homing_with_guard(Dialect::Icd, Checksum::Crc16, false).await;
    guard.beat_for(Duration::from_millis(500)).await;
    assert!(
        arm_state(&sim).await.0,
        "Home runs on beside a beating console"
    );

    let said = console_dies(
        &sim,
        &mut guard,
        console,
        "pipe closed -> Home stopped over Talos",
    )
    .await;
    assert!(
        said.starts_with("stopped the console is gone") && said.contains("talos: stop set of 3"),
        "the guard reports the ICD stop set: {said:?}"
    );
    let status = guard.exit_status("the guard exits after the stop").await;
    assert!(status.success(), "exit status {status}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_silent_console_gets_its_talos_home_stopped_by_an_operator_that_takes_several_clients() {
    let (sim, mut guard, _console) = homing_with_guard(Dialect::Icd, Checksum::Crc16, false).await;

    // The pipe stays open, the console's connection too, and no heartbeat comes.
    wait_moving(&sim, false, Duration::from_secs(4))
        .await
        .expect("the guard stops Home after the heartbeat timeout (1 s)");
    let said = guard.said().await;
    assert!(
        said.starts_with("stopped no heartbeat") && said.contains("talos: stop set"),
        "{said:?}"
    );
    guard.assert_watching();
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn over_an_operator_that_serves_one_client_the_guard_stops_home_once_the_console_is_gone() {
    let (sim, mut guard, console) = homing_with_guard(Dialect::Ack, Checksum::Xor8, true).await;

    // Frozen: the console holds the operator's one connection, so the guard's is not answered.
    // It says so, leaves no stop queued, and Home runs on.
    let said = guard.said().await;
    assert!(
        said.starts_with("stop-failed no heartbeat")
            && said.contains("one client at a time")
            && said.contains("the console holds its own"),
        "the guard says it cannot reach the operator: {said:?}"
    );
    assert!(
        arm_state(&sim).await.0,
        "Home runs on: nothing reaches an operator busy with the frozen console"
    );
    guard.assert_watching();

    // Now the console dies: its connection closes, the operator takes the guard's.
    let said = console_dies(
        &sim,
        &mut guard,
        console,
        "one-client operator: pipe closed -> Home stopped",
    )
    .await;
    assert!(
        said.starts_with("stopped the console is gone") && said.contains("talos: stop set of 1"),
        "the ack dialect's stop set (Polar Pan STOP): {said:?}"
    );
}

/// The console's driver on the simulator's operator alone, with `guard`; once the link is up.
/// The driver over Talos with its link up and, when `want_guard`, its guard ready (its pid).
/// Over Talos alone the guard is ready as soon as it runs, so its report may come before the
/// link's: both are waited for in one pass, whichever comes first.
async fn talos_driver(
    sim: &Simulator,
    guard: GuardPolicy,
    want_guard: bool,
) -> (
    Driver,
    tokio::sync::mpsc::UnboundedReceiver<ArmEvent>,
    Option<u32>,
) {
    let mut config = DriverConfig::new(Some(TalosConfig::new(sim.talos_addr.to_string())), None);
    config.guard = guard;
    let (driver, mut events) = Driver::spawn(config);
    let (mut up, mut ready) = (false, None);
    while !up || (want_guard && ready.is_none()) {
        let event = wait_event(
            &mut events,
            Duration::from_secs(10),
            "the link up and the guard ready",
            |e| {
                matches!(
                    e,
                    ArmEvent::Status(LinkStatus::Up { .. })
                        | ArmEvent::Guard(GuardStatus::Ready { .. })
                )
            },
        )
        .await;
        match event {
            ArmEvent::Guard(GuardStatus::Ready { pid }) => ready = Some(pid),
            _ => up = true,
        }
    }
    (driver, events, ready)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn talos_motion_waits_for_a_ready_guard_as_modbus_motion_does() {
    let sim = sim_at_retract(Dialect::Icd, Checksum::Crc16, false).await;
    let missing = std::path::PathBuf::from("/nonexistent/armjog-guard");
    let (driver, mut events, _) = talos_driver(&sim, GuardPolicy::Spawn(missing), false).await;
    for command in [
        ArmCommand::Home,
        ArmCommand::GoToPosition {
            name: "bench".into(),
        },
    ] {
        let kind = command.kind();
        assert!(driver.send(command));
        wait_event(&mut events, Duration::from_secs(5), "the refusal", |e| {
            matches!(e, ArmEvent::Failed { command, error: ArmError::GuardNotRunning(reason) }
                if *command == kind && reason.to_string().starts_with("stop guard not running"))
        })
        .await;
    }
    tokio::time::sleep(Duration::from_millis(300)).await;
    assert!(!arm_state(&sim).await.0, "nothing moved");
    driver.shutdown().await;

    // With the guard ready (over Talos alone it connects to nothing), Home runs.
    let (driver, _events, _) = talos_driver(&sim, GuardPolicy::Spawn(BIN.into()), true).await;
    assert!(driver.send(ArmCommand::Home));
    assert_moving(&sim, "Home runs with the guard ready").await;
    driver.send(ArmCommand::Stop);
    driver.shutdown().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_killed_guard_stops_a_talos_home_and_is_restarted() {
    let sim = sim_at_retract(Dialect::Icd, Checksum::Crc16, false).await;
    let (driver, mut events, ready) =
        talos_driver(&sim, GuardPolicy::Spawn(BIN.into()), true).await;
    let pid = ready.expect("the guard ready");
    assert!(driver.send(ArmCommand::Home));
    assert_moving(&sim, "Home runs").await;

    // Nothing would stop Home if the console died now: the driver stops it.
    guard_killed_and_replaced(&sim, &mut events, pid, "Home stops when the guard dies").await;
    driver.shutdown().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_terminated_guard_leaves_no_stop_queued_behind_a_live_console() {
    let (sim, mut guard, console) = homing_with_guard(Dialect::Ack, Checksum::Xor8, true).await;

    // SIGTERM while the console lives and holds the operator's one connection: the guard
    // cannot be served, says so, and exits.
    let pid = guard.child.id().expect("guard pid");
    assert!(send_signal(pid, "-TERM"));
    let said = guard.said().await;
    assert!(
        said.starts_with("stop-failed SIGTERM") && said.contains("one client at a time"),
        "{said:?}"
    );
    guard.exit_status("the guard exits").await;

    // Its connection, served once the console's closes, carried no stop: Home runs on (the
    // console, alive, would have stopped it itself on seeing its guard die).
    drop(console);
    tokio::time::sleep(Duration::from_millis(500)).await;
    assert!(
        arm_state(&sim).await.0,
        "no stop left queued in the operator lands later"
    );
}
