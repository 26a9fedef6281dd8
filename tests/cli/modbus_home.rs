//! `armjog modbus home`: it waits for the action's end and says how it ended. Against the
//! simulator: completed at rest, an arm in fault, an action id the arm does not have, an abort
//! by another client, the wait's timeout, `--no-wait`; against the fake arm, a home aborted at
//! a joint limit.

use crate::armjog_run::command;
use crate::modbus_fake::{self, FakeArm, Written};
use crate::stored::{addr, ended, modbus, sim};

use std::process::Stdio;
use std::time::{Duration, Instant};

use armjog::sim::arm_model::Arm;
use armjog::sim::kinematics::to_radians;

/// Polls the fake arm until `done` holds; panics after 10 s.
async fn fake_until(arm: &FakeArm, what: &str, done: impl Fn(&modbus_fake::ArmState) -> bool) {
    let until = Instant::now() + Duration::from_secs(10);
    while !arm.with(|s| done(s)) {
        assert!(Instant::now() < until, "not within 10 s: {what}");
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
}

/// The simulator's home is a joint-space move that never passes a limit, so an arm whose home
/// stops at a joint limit is played by the fake: it takes the home, reports it started and
/// moving, then aborted with J4 at its limit and a joint-fault warning.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn home_aborted_at_a_joint_limit_names_the_joint_and_exits_1() {
    let arm = FakeArm::start().await;
    arm.with(|s| {
        s.input_registers[0] = 7; // ready
        for (j, deg) in [0.0, 15.0, 180.0, 230.0, 0.0, 55.0, 90.0]
            .iter()
            .enumerate()
        {
            s.set_input_f32(34 + 2 * j, *deg);
        }
        s.holding_registers[100] = 1; // an earlier action completed
        // Limits the capped home can lower for its run.
        s.set_holding_f32(104, 0.5);
        s.set_holding_f32(106, 100.0);
    });
    let home = command(&["modbus", "--modbus", &arm.addr(), "home"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .kill_on_drop(true)
        .spawn()
        .expect("spawn armjog modbus home");
    let start = Written::Registers(200, vec![1]);
    fake_until(&arm, "home started", |s| s.writes().contains(&start)).await;
    let reads_before = arm.with(|s| {
        s.holding_registers[100] = 0; // started
        s.holding_registers[101] = 2; // the home action
        s.set_input_f32(48 + 2 * 3, -20.0); // J4 turning
        s.reads().len()
    });
    // Once the waiting command has read the action status as started, the arm stops at the
    // limit.
    fake_until(&arm, "action status read while started", |s| {
        s.reads()[reads_before..]
            .iter()
            .any(|&(fc, at, n)| fc == 3 && at <= 100 && 100 < at + n)
    })
    .await;
    arm.with(|s| {
        s.set_input_f32(34 + 2 * 3, 147.8);
        s.set_input_f32(48 + 2 * 3, 0.0);
        s.input_registers[4] = 1 << 4; // warning: joint_fault
        s.holding_registers[100] = 3; // aborted
    });
    let (out, stdout, stderr) = ended(home, "armjog modbus home returns after the abort").await;
    assert_eq!(out.status.code(), Some(1), "{stdout}{stderr}");
    assert!(
        stderr.contains("home failed: aborted, J4 at its limit"),
        "{stderr}"
    );
    assert!(!stderr.contains("at once"), "{stderr}");
    assert!(!stdout.contains("completed"), "{stdout}");
}

/// A simulated arm away from home.
fn away() -> Arm {
    Arm::at(to_radians(&[10.0, 30.0, 170.0, 240.0, 10.0, 40.0, 80.0]))
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn home_on_a_healthy_arm_waits_for_the_end_and_exits_0() {
    let sim = sim(away()).await;
    let run = modbus(&sim, &["home"]).await;
    assert_eq!(run.code, 0, "{}{}", run.stdout, run.stderr);
    assert!(run.stdout.contains("home: completed in"), "{}", run.stdout);
    let s = sim.arm.snapshot().await.expect("sim");
    assert!(!s.moving, "at rest when it says completed");
    let home = [0.0, 15.0, 180.0, 230.0, 0.0, 55.0, 90.0];
    for (j, (at, want)) in s.joint_position.iter().zip(home).enumerate() {
        // Reported 0-360: 360 is 0.
        let off = (at - want).rem_euclid(360.0);
        assert!(off.min(360.0 - off) < 0.1, "J{}: {at} vs {want}", j + 1);
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn home_on_an_arm_in_fault_exits_1_and_starts_nothing() {
    let mut arm = away();
    arm.raise_fault(4);
    let sim = sim(arm).await;
    let before = sim.arm.snapshot().await.expect("sim").joint_position;
    let run = modbus(&sim, &["home"]).await;
    assert_eq!(run.code, 1, "{}{}", run.stdout, run.stderr);
    assert!(
        run.stderr
            .contains("home failed: the arm is in fault: joint_fault"),
        "{}",
        run.stderr
    );
    tokio::time::sleep(Duration::from_millis(200)).await;
    let after = sim.arm.snapshot().await.expect("sim").joint_position;
    assert_eq!(before, after, "nothing moved");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn home_with_an_action_id_the_arm_does_not_have_exits_1() {
    let sim = sim(away()).await;
    let run = modbus(&sim, &["home", "--action-id", "99"]).await;
    assert_eq!(run.code, 1, "{}{}", run.stdout, run.stderr);
    assert!(run.stderr.contains("action 99"), "{}", run.stderr);
    assert!(!run.stdout.contains("completed"), "{}", run.stdout);
}

/// J1 170 degrees from home and the tool limited to 50 mm/s: the home takes over 20 s,
/// time enough to abort it however slowly a second process starts.
fn far_from_home() -> Arm {
    let mut arm = Arm::at(to_radians(&[170.0, 30.0, 170.0, 240.0, 10.0, 40.0, 80.0]));
    arm.set_speed_limits(0.05, 100.0).expect("valid limits");
    arm
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn home_aborted_by_another_client_while_waiting_exits_1() {
    let sim = sim(far_from_home()).await;
    let home = command(&["modbus", "--modbus", &addr(&sim), "home"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .kill_on_drop(true)
        .spawn()
        .expect("spawn armjog modbus home");
    // Abort only once the home runs, from a second client, as a technician would.
    let until = Instant::now() + Duration::from_secs(10);
    while !sim.arm.snapshot().await.expect("sim").moving {
        assert!(Instant::now() < until, "the home never started");
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    // The home process must also have read the action running before the abort, or it
    // rightly takes an action that ends at once for one the arm does not have. On a loaded
    // machine its first poll can come late; the home still has well over 15 s to go.
    tokio::time::sleep(Duration::from_secs(2)).await;
    let abort = modbus(&sim, &["abort"]).await;
    assert_eq!(abort.code, 0, "{}", abort.stderr);
    let (out, stdout, stderr) = ended(home, "armjog modbus home returns after the abort").await;
    assert_eq!(out.status.code(), Some(1), "{stdout}{stderr}");
    assert!(stderr.contains("home failed: aborted"), "{stderr}");
    // It had seen the home start: the abort is not mistaken for a missing action.
    assert!(!stderr.contains("at once"), "{stderr}");
    assert!(!stdout.contains("completed"), "{stdout}");
    let s = sim.arm.snapshot().await.expect("sim");
    assert!(!s.moving, "the abort stopped the arm");
    let j1 = s.joint_position[0];
    assert!(
        (1.0..=170.0).contains(&j1),
        "stopped short of home: J1 at {j1}"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_home_past_its_wait_timeout_is_stopped_and_exits_1() {
    let sim = sim(away()).await;
    let run = modbus(&sim, &["home", "--wait-timeout", "0.2"]).await;
    assert_eq!(run.code, 1, "{}{}", run.stdout, run.stderr);
    assert!(
        run.stderr.contains("no end within 0.2 s; stopped"),
        "{}",
        run.stderr
    );
    assert!(!sim.arm.snapshot().await.expect("sim").moving, "stopped");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn home_no_wait_returns_while_the_arm_still_moves() {
    let mut arm = away();
    arm.set_speed_limits(0.5, 30.0).expect("valid limits");
    let sim = sim(arm).await;
    let started = Instant::now();
    // Limits of 0.5 m/s and 30 deg/s keep a 500 mm/s cap and its turn rate: nothing needs
    // lowering.
    let run = modbus(&sim, &["home", "--no-wait", "--max-jog-speed", "500"]).await;
    assert_eq!(run.code, 0, "{}{}", run.stdout, run.stderr);
    assert!(run.stdout.starts_with("home: started"), "{}", run.stdout);
    assert!(
        sim.arm.snapshot().await.expect("sim").moving,
        "returned before the end ({:?})",
        started.elapsed()
    );
}
