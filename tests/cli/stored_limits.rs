//! The arm's speed limits around `armjog modbus home|action|sequence`: both lowered for a run
//! to what the one speed rule gives at --max-jog-speed (the linear one to the cap, the angular
//! one to the turn rate) and put back; with `--no-wait`, neither lowered, and a run the arm's
//! angular limit would turn faster than the turn rate refused.

use super::stored::{modbus, sim, snapshot};
use crate::armjog_run::armjog;
use armjog::sim::arm_model::Arm;

/// A run lowers both of the arm's limits for its time, each to what the one speed rule gives
/// at --max-jog-speed (`link::driver::move_cap_at`, at 100 %): the linear one to the cap, the
/// angular one to the turn rate, 30 deg/s; and puts both back. Words by hand (CDAB, low word
/// first): 0.1 = 0x3DCCCCCD, 30.0 = 0x41F00000, 0.5 = 0x3F000000, 100.0 = 0x42C80000.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_run_lowers_the_angular_limit_to_the_turn_rate_as_the_linear_one_and_puts_both_back() {
    use crate::modbus_fake::{FakeArm, Written};
    let arm = FakeArm::start().await;
    arm.with(|s| {
        s.input_registers[0] = 7; // ready
        s.holding_registers[100] = 1; // an earlier action completed
        s.holding_registers[101] = 2;
        s.set_holding_f32(104, 0.5);
        s.set_holding_f32(106, 100.0);
    });
    // The fake never runs action 3: the wait ends at its timeout, and the run is stopped.
    let run = armjog(&[
        "modbus",
        "--modbus",
        &arm.addr(),
        "action",
        "--id",
        "3",
        "--max-jog-speed",
        "100",
        "--wait-timeout",
        "0.5",
    ])
    .await;
    assert_eq!(run.code, 1, "{}{}", run.stdout, run.stderr);
    let limits: Vec<Written> = arm
        .writes()
        .into_iter()
        .filter(|w| matches!(w, Written::Registers(216, _)))
        .collect();
    assert_eq!(
        limits,
        [
            Written::Registers(216, vec![0xCCCD, 0x3DCC, 0x0000, 0x41F0]),
            Written::Registers(216, vec![0x0000, 0x3F00, 0x0000, 0x42C8]),
        ]
    );
}

/// The simulator's arm turns at up to 100 deg/s: over the 30 deg/s turn rate of any cap, so
/// with nothing left to lower its angular limit for the run, `--no-wait` refuses.
#[tokio::test]
async fn no_wait_refuses_a_run_the_arms_angular_limit_would_turn_over_the_turn_rate() {
    let sim = sim(Arm::default()).await;
    let run = modbus(
        &sim,
        &["action", "--id", "5", "--no-wait", "--max-jog-speed", "500"],
    )
    .await;
    assert_eq!(run.code, 1, "{}{}", run.stdout, run.stderr);
    assert!(
        run.stderr.contains(
            "action 5 not started: the arm's angular limit is 100 deg/s, over the 30 deg/s \
             turn rate"
        ),
        "{}",
        run.stderr
    );
    let s = snapshot(&sim).await;
    assert!(!s.moving, "nothing started");
    assert!(
        (s.speed_limit_angular_deg - 100.0).abs() < 1e-3,
        "the arm's limit is not rewritten: {}",
        s.speed_limit_angular_deg
    );
}
