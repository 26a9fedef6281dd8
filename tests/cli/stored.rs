//! `armjog modbus action` and `armjog modbus sequence` end to end against the simulator: its
//! factory actions (Home 2, Retract 3, Packaging 4, Zero 5) and sequence 1 (Retract, then
//! Home), an id it does not have, an abort by another client, a fault, `--no-wait`, the speed
//! cap and a profile's cap.

use std::process::{Output, Stdio};
use std::time::{Duration, Instant};

use crate::armjog_run::{Run, armjog, command};
use armjog::sim::arm_model::{Arm, ArmSnapshot};
use armjog::sim::kinematics::to_radians;
use armjog::sim::{SimConfig, Simulator};

const HOME: [f64; 7] = [0.0, 15.0, 180.0, 230.0, 0.0, 55.0, 90.0];
/// Kinova's Retract of a Gen3 7-DoF, as the simulator holds it.
const RETRACT: [f64; 7] = [0.0, -20.0, 180.0, -145.5, 0.0, -50.0, 90.0];

pub(crate) async fn sim(arm: Arm) -> Simulator {
    let mut config = SimConfig::ephemeral();
    config.arm = arm;
    Simulator::start(config).await.expect("simulator")
}

pub(crate) fn addr(sim: &Simulator) -> String {
    sim.modbus_addr.expect("modbus server").to_string()
}

/// `armjog modbus --modbus <the simulator's Modbus server> ARGS`.
pub(crate) async fn modbus(sim: &Simulator, args: &[&str]) -> Run {
    let addr = addr(sim);
    let mut all = vec!["modbus", "--modbus", &addr];
    all.extend_from_slice(args);
    armjog(&all).await
}

pub(crate) async fn snapshot(sim: &Simulator) -> ArmSnapshot {
    sim.arm.snapshot().await.expect("sim")
}

/// The largest difference of the reported joints (0-360) from `want`, degrees.
fn off(s: &ArmSnapshot, want: [f64; 7]) -> f64 {
    s.joint_position
        .iter()
        .zip(want)
        .map(|(at, want)| {
            let d = (at - want).rem_euclid(360.0);
            d.min(360.0 - d)
        })
        .fold(0.0, f64::max)
}

fn spawn(args: &[&str]) -> tokio::process::Child {
    command(args)
        .env_remove("ARMJOG_ARM")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .kill_on_drop(true)
        .spawn()
        .expect("spawn armjog")
}

/// Waits (20 s at most) for a spawned run to end; `what` names the end awaited. Its output,
/// and its stdout and stderr as text.
pub(crate) async fn ended(child: tokio::process::Child, what: &str) -> (Output, String, String) {
    let out = tokio::time::timeout(Duration::from_secs(20), child.wait_with_output())
        .await
        .expect(what)
        .expect("output");
    let (stdout, stderr) = text(&out);
    (out, stdout, stderr)
}

fn text(out: &Output) -> (String, String) {
    (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Waits (at most 10 s) until the simulated arm moves.
async fn until_moving(sim: &Simulator) {
    let until = Instant::now() + Duration::from_secs(10);
    while !snapshot(sim).await.moving {
        assert!(Instant::now() < until, "the arm never started");
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn action_5_takes_every_joint_to_0_and_exits_0() {
    let sim = sim(Arm::at(to_radians(&[
        20.0, 10.0, 20.0, 10.0, 20.0, 10.0, 20.0,
    ])))
    .await;
    let run = modbus(&sim, &["action", "--id", "5"]).await;
    assert_eq!(run.code, 0, "{}{}", run.stdout, run.stderr);
    assert!(
        run.stdout.contains("action 5 completed in"),
        "{}",
        run.stdout
    );
    let s = snapshot(&sim).await;
    assert!(!s.moving, "at rest when it says completed");
    assert!(off(&s, [0.0; 7]) < 0.1, "{:?}", s.joint_position);
    assert!(
        (s.speed_limit_linear - 0.5).abs() < 1e-6,
        "the arm's 0.5 m/s limit is put back: {}",
        s.speed_limit_linear
    );
}

/// From Zero, where the direct way home does not pass Retract. While it runs the tool stays
/// under the 250 mm/s cap and the arm's limit is lowered to it.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn sequence_1_runs_retract_then_home_and_exits_0() {
    let sim = sim(Arm::at([0.0; 7])).await;
    let mut child = spawn(&["modbus", "--modbus", &addr(&sim), "sequence", "--id", "1"]);
    let mut nearest_retract = f64::INFINITY;
    let mut fastest: f64 = 0.0;
    let mut highest_limit: f64 = 0.0;
    let mut moved = false;
    let until = Instant::now() + Duration::from_secs(90);
    let status = loop {
        if let Some(status) = child.try_wait().expect("armjog runs") {
            break status;
        }
        assert!(Instant::now() < until, "no end within 90 s");
        let s = snapshot(&sim).await;
        if s.moving {
            moved = true;
            nearest_retract = nearest_retract.min(off(&s, RETRACT));
            let v = s.tcp_linear_velocity;
            fastest = fastest.max((v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt());
            highest_limit = highest_limit.max(s.speed_limit_linear);
        }
        tokio::time::sleep(Duration::from_millis(20)).await;
    };
    let out = child.wait_with_output().await.expect("output");
    let (stdout, stderr) = text(&out);
    assert_eq!(status.code(), Some(0), "{stdout}{stderr}");
    assert!(stdout.contains("sequence 1 completed in"), "{stdout}");
    assert!(moved);
    assert!(
        nearest_retract < 1.5,
        "passed through Retract: nearest {nearest_retract} deg"
    );
    assert!(fastest <= 0.25 * 1.05, "tool at {fastest} m/s, cap 0.25");
    assert!(highest_limit <= 0.25 + 1e-6, "limit {highest_limit} m/s");
    let s = snapshot(&sim).await;
    assert!(!s.moving);
    assert!(off(&s, HOME) < 0.1, "ends at home: {:?}", s.joint_position);
    assert!((s.speed_limit_linear - 0.5).abs() < 1e-6, "limit put back");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_id_the_arm_does_not_have_exits_1_naming_it_within_about_2_s() {
    let sim = sim(Arm::default()).await;
    let before = snapshot(&sim).await.joint_position;
    for (kind, id) in [("sequence", "9"), ("action", "7")] {
        let started = Instant::now();
        let run = modbus(&sim, &[kind, "--id", id]).await;
        let took = started.elapsed();
        assert_eq!(run.code, 1, "{}{}", run.stdout, run.stderr);
        assert!(
            run.stderr
                .contains(&format!("the arm did not take {kind} {id}")),
            "{}",
            run.stderr
        );
        assert!(run.stderr.contains("Web App"), "{}", run.stderr);
        assert!(!run.stdout.contains("completed"), "{}", run.stdout);
        // 2 s for the arm to take it, and a loaded machine's process start.
        assert!(took < Duration::from_secs(8), "{kind} {id}: {took:?}");
    }
    assert_eq!(snapshot(&sim).await.joint_position, before, "nothing moved");
}

/// The arm's own limit at 50 mm/s: the sequence takes well over 20 s, time enough for a
/// second client to stop it however slowly a process starts.
fn slow_at_zero() -> Arm {
    let mut arm = Arm::at([0.0; 7]);
    arm.set_speed_limits(0.05, 100.0).expect("valid limits");
    arm
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_stop_from_another_client_during_a_sequence_exits_1() {
    let sim = sim(slow_at_zero()).await;
    let child = spawn(&["modbus", "--modbus", &addr(&sim), "sequence", "--id", "1"]);
    until_moving(&sim).await;
    // Its first polls must have seen the sequence running (see the home abort test).
    tokio::time::sleep(Duration::from_secs(2)).await;
    let stop = modbus(&sim, &["stop"]).await;
    assert_eq!(stop.code, 0, "{}", stop.stderr);
    let (out, stdout, stderr) = ended(child, "returns after the stop").await;
    assert_eq!(out.status.code(), Some(1), "{stdout}{stderr}");
    assert!(stderr.contains("sequence 1 aborted"), "{stderr}");
    assert!(!stderr.contains("did not take"), "{stderr}");
    assert!(!stdout.contains("completed"), "{stdout}");
    let s = snapshot(&sim).await;
    assert!(!s.moving, "stopped");
    assert!(off(&s, RETRACT) > 1.0, "stopped short of Retract");
    assert!(
        (s.speed_limit_linear - 0.05).abs() < 1e-6,
        "the arm's own lower limit stays: {}",
        s.speed_limit_linear
    );
}

/// Another client's action replaces ours mid-run: the status names action 4, not our sequence
/// 1. It is not our run's end, nor an id the arm "did not take".
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn another_clients_action_during_a_sequence_exits_1_naming_it() {
    let sim = sim(slow_at_zero()).await;
    let child = spawn(&["modbus", "--modbus", &addr(&sim), "sequence", "--id", "1"]);
    until_moving(&sim).await;
    tokio::time::sleep(Duration::from_secs(2)).await;
    let config = armjog::link::ModbusConfig::new(addr(&sim));
    let (other, _events) = armjog::link::ModbusLink::connect(config)
        .await
        .expect("second client");
    other
        .start_stored(
            armjog::kortex::Stored {
                motion: armjog::kortex::StoredMotion::Action,
                id: 4,
            },
            None,
        )
        .await
        .expect("action 4 started");
    let (out, stdout, stderr) = ended(child, "returns after the other move").await;
    assert_eq!(out.status.code(), Some(1), "{stdout}{stderr}");
    assert!(
        stderr.contains(
            "sequence 1 failed: MOVED BY ANOTHER CLIENT: the arm runs action 4, not our \
             sequence 1"
        ),
        "{stderr}"
    );
    assert!(!stdout.contains("completed"), "{stdout}");
    drop(other);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_fault_during_an_action_exits_1() {
    let sim = sim(slow_at_zero()).await;
    let child = spawn(&["modbus", "--modbus", &addr(&sim), "action", "--id", "3"]);
    until_moving(&sim).await;
    tokio::time::sleep(Duration::from_millis(500)).await;
    sim.arm
        .with(|arm, _| arm.raise_fault(4))
        .await
        .expect("sim");
    let (out, stdout, stderr) = ended(child, "returns after the fault").await;
    assert_eq!(out.status.code(), Some(1), "{stdout}{stderr}");
    assert!(
        stderr.contains("action 3 failed: the arm is in fault: joint_fault"),
        "{stderr}"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_arm_in_fault_starts_nothing() {
    let mut arm = Arm::default();
    arm.raise_fault(4);
    let sim = sim(arm).await;
    let run = modbus(&sim, &["sequence", "--id", "1"]).await;
    assert_eq!(run.code, 1, "{}{}", run.stdout, run.stderr);
    assert!(
        run.stderr
            .contains("sequence 1 failed: the arm is in fault: joint_fault; not started"),
        "{}",
        run.stderr
    );
    assert!(run.stdout.is_empty(), "nothing written: {}", run.stdout);
}

/// Nothing waits to put a lowered limit back, so `--no-wait` leaves the cap written.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn no_wait_returns_at_once_when_the_arms_limit_keeps_the_cap() {
    let mut arm = Arm::default();
    arm.set_speed_limits(0.5, 30.0).expect("valid limits");
    let sim = sim(arm).await;
    // The arm is limited to 0.5 m/s and 30 deg/s: a 500 mm/s cap and its 30 deg/s turn rate
    // are kept without lowering either.
    let run = modbus(
        &sim,
        &[
            "sequence",
            "--id",
            "1",
            "--no-wait",
            "--max-jog-speed",
            "500",
        ],
    )
    .await;
    assert_eq!(run.code, 0, "{}{}", run.stdout, run.stderr);
    assert!(
        run.stdout.starts_with("sequence: started"),
        "{}",
        run.stdout
    );
    let s = snapshot(&sim).await;
    assert!(s.moving, "returned before the end");
    assert_eq!((s.action_id, s.move_type), (1, 1));
    assert!(
        (s.speed_limit_linear - 0.5).abs() < 1e-6,
        "the arm's limit is left as it was: {}",
        s.speed_limit_linear
    );
    assert!((s.speed_limit_angular_deg - 30.0).abs() < 1e-3);
}

#[tokio::test]
async fn no_wait_refuses_a_run_the_arms_limit_would_take_over_the_cap() {
    let sim = sim(Arm::default()).await;
    let run = modbus(
        &sim,
        &[
            "sequence",
            "--id",
            "1",
            "--no-wait",
            "--max-jog-speed",
            "100",
        ],
    )
    .await;
    assert_eq!(run.code, 1, "{}{}", run.stdout, run.stderr);
    assert!(
        run.stderr.contains(
            "sequence 1 not started: the arm's linear limit is 0.5 m/s, over the 0.1 m/s cap"
        ),
        "{}",
        run.stderr
    );
    let s = snapshot(&sim).await;
    assert!(!s.moving, "nothing started");
    assert!(
        (s.speed_limit_linear - 0.5).abs() < 1e-6,
        "the arm's limit is not rewritten: {}",
        s.speed_limit_linear
    );
}

#[tokio::test]
async fn a_cap_over_the_twist_limit_is_refused_before_connecting() {
    // Nothing listens on port 9 of loopback: a connection attempt would fail with exit 3.
    let run = armjog(&[
        "modbus",
        "--modbus",
        "127.0.0.1:9",
        "action",
        "--id",
        "5",
        "--max-jog-speed",
        "501",
    ])
    .await;
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(
        run.stderr.contains("'501' for '--max-jog-speed <MM_S>'")
            && run.stderr.contains("at most 500 mm/s"),
        "{}",
        run.stderr
    );
}

/// Id 0 names no action (`kortex::commands::STORED_IDS`): refused as the console's form refuses
/// it, from the command line and from a profile, before anything connects.
#[tokio::test(flavor = "multi_thread")]
async fn an_id_of_0_is_refused_before_connecting() {
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0")
        .await
        .expect("bind");
    let addr = listener.local_addr().expect("addr").to_string();
    let dir = tempfile::tempdir().expect("temp dir");
    let config = dir.path().join("config.toml");
    std::fs::write(
        &config,
        format!("[arms.cell]\nmodbus = \"{addr}\"\nhome_action_id = 0\n"),
    )
    .expect("write config");
    let config = config.display().to_string();
    let modbus = ["modbus", "--modbus", addr.as_str()];
    for (args, says) in [
        (
            [&modbus[..], &["action", "--id", "0"]].concat(),
            "'0' for '--id <N>': 0 is outside 1 to 65535",
        ),
        (
            [&modbus[..], &["sequence", "--id", "0", "--no-wait"]].concat(),
            "'0' for '--id <N>': 0 is outside 1 to 65535",
        ),
        (
            [&modbus[..], &["home", "--action-id", "0"]].concat(),
            "'0' for '--action-id <N>': 0 is outside 1 to 65535",
        ),
        (
            vec!["--modbus", addr.as_str(), "--home-action-id", "0"],
            "'0' for '--home-action-id <HOME_ACTION_ID>': 0 is outside 1 to 65535",
        ),
        (
            vec!["--config", &config, "modbus", "--arm", "cell", "home"],
            "config.toml:3: home_action_id = 0: 0 is outside 1 to 65535",
        ),
        (
            vec!["--config", &config, "--arm", "cell"],
            "config.toml:3: home_action_id = 0: 0 is outside 1 to 65535",
        ),
    ] {
        let run = armjog(&args).await;
        assert_eq!(run.code, 2, "{args:?}: {}{}", run.stdout, run.stderr);
        assert!(run.stderr.contains(says), "{args:?}: {}", run.stderr);
    }
    let accepted = tokio::time::timeout(Duration::from_millis(200), listener.accept()).await;
    assert!(accepted.is_err(), "something connected");
}

/// A profile's `max_jog_speed` caps the stored motions, and its `home_action_id` still goes to
/// `home --action-id` only.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_profiles_cap_and_home_id_reach_the_commands() {
    let sim = sim(Arm::default()).await;
    let dir = tempfile::tempdir().expect("temp dir");
    let config = dir.path().join("config.toml");
    std::fs::write(
        &config,
        format!(
            "[arms.cell]\nmodbus = \"{}\"\nmax_jog_speed = 80\nhome_action_id = 5\n",
            addr(&sim)
        ),
    )
    .expect("write config");
    let config = config.display().to_string();
    let action_3 = [
        "--config",
        &config,
        "modbus",
        "--arm",
        "cell",
        "action",
        "--id",
        "3",
        "--no-wait",
    ];
    // The arm's 0.5 m/s limit is over the profile's cap: with nothing left to put a lowered
    // limit back, the run is refused, naming the profile's cap.
    let run = armjog(&action_3).await;
    assert_eq!(run.code, 1, "{}{}", run.stdout, run.stderr);
    assert!(
        run.stderr.contains("over the 0.08 m/s cap"),
        "{}",
        run.stderr
    );
    // An arm limited below the cap and its turn rate keeps them: the run starts, and its
    // limits are left as they were.
    let lowered = modbus(
        &sim,
        &["speed-limit", "--linear", "0.05", "--angular", "30"],
    )
    .await;
    assert_eq!(lowered.code, 0, "{}", lowered.stderr);
    let run = armjog(&action_3).await;
    assert_eq!(run.code, 0, "{}{}", run.stdout, run.stderr);
    let s = snapshot(&sim).await;
    assert_eq!(
        (s.action_id, s.move_type),
        (3, 0),
        "action 3, not the home id"
    );
    assert!(
        (s.speed_limit_linear - 0.05).abs() < 1e-6,
        "{}",
        s.speed_limit_linear
    );
    let run = armjog(&[
        "--config",
        &config,
        "modbus",
        "--arm",
        "cell",
        "home",
        "--no-wait",
    ])
    .await;
    assert_eq!(run.code, 0, "{}{}", run.stdout, run.stderr);
    assert_eq!(
        snapshot(&sim).await.action_id,
        5,
        "home took the profile's id"
    );
}
