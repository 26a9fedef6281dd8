//! The stored actions and sequences: the table, and how the arm runs and reports them when
//! started through the command registers.

use super::*;

#[test]
fn the_factory_actions_are_home_retract_packaging_zero() {
    let names: Vec<(u16, &str)> = ACTIONS.iter().map(|a| (a.id, a.name)).collect();
    assert_eq!(
        names,
        [(2, "Home"), (3, "Retract"), (4, "Packaging"), (5, "Zero")]
    );
    assert_eq!(
        action(2).map(|a| a.joints_deg),
        Some([0.0, 15.0, 180.0, 230.0, 0.0, 55.0, 90.0])
    );
    assert_eq!(action(5).map(|a| a.joints_deg), Some([0.0; 7]));
    assert!(action(1).is_none() && action(6).is_none());
}

#[test]
fn every_action_is_inside_the_joint_limits_with_a_margin() {
    for a in ACTIONS {
        let q = kinematics::to_radians(&a.joints_deg);
        for (i, angle) in q.iter().enumerate() {
            // 2 degrees further out is still inside.
            let out = angle + angle.signum() * 2f64.to_radians();
            assert!(kinematics::within_limit(i, out), "{} J{}", a.name, i + 1);
        }
    }
}

#[test]
fn sequence_1_is_retract_then_home_and_unknown_ids_have_no_steps() {
    let retract = SimMotion::ToJoints {
        target: kinematics::to_radians(&[0.0, -20.0, 180.0, -145.5, 0.0, -50.0, 90.0]),
        fraction: 0.3,
    };
    let home = SimMotion::ToJoints {
        target: kinematics::to_radians(&[0.0, 15.0, 180.0, 230.0, 0.0, 55.0, 90.0]),
        fraction: 0.3,
    };
    assert_eq!(steps(1, 1), Some(vec![retract, home]));
    assert_eq!(steps(9, 1), None);
    assert_eq!(steps(1, 0), None, "no action 1");
    assert_eq!(steps(2, 2), None, "a cartesian move is not stored");
}

// ---- started through holding registers 200-202, as a Modbus client does ----

use crate::kortex::ActionStatus;
use crate::sim::arm_model::{Arm, ArmSnapshot};
use crate::sim::modbus_registers::write_registers;
use crate::sim::world::World;

const HOME: [f64; 7] = [0.0, 15.0, 180.0, 230.0, 0.0, 55.0, 90.0];
const RETRACT: [f64; 7] = [0.0, -20.0, 180.0, -145.5, 0.0, -50.0, 90.0];

/// The largest difference of reported joint angles (0-360) from `want` (any sign), degrees.
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

/// FC16 200-202 <- [1 (start), id, move type].
fn start(world: &mut World, id: u16, move_type: u16) {
    write_registers(world, 200, &[1, id, move_type]).expect("the write is accepted");
}

/// Steps the arm 10 ms at a time until it rests (at most 60 s), calling `each` on every
/// snapshot while it moves.
fn run_to_rest(world: &mut World, mut each: impl FnMut(&ArmSnapshot)) -> ArmSnapshot {
    for _ in 0..6000 {
        world.arm.advance(0.01);
        let s = world.arm.snapshot();
        if !s.moving {
            return s;
        }
        each(&s);
    }
    panic!("still moving after 60 s");
}

#[test]
fn action_5_takes_every_joint_to_0_and_completes() {
    let mut world = World::default();
    start(&mut world, 5, 0);
    let s = world.arm.snapshot();
    assert_eq!(
        (s.action_status, s.action_id, s.move_type),
        (ActionStatus::Started, 5, 0)
    );
    let s = run_to_rest(&mut world, |_| {});
    assert!(off(&s, [0.0; 7]) < 0.01, "{:?}", s.joint_position);
    assert_eq!(
        (s.action_status, s.action_id, s.move_type),
        (ActionStatus::Completed, 5, 0)
    );
}

#[test]
fn actions_3_and_4_reach_their_poses() {
    for (id, want) in [
        (3, RETRACT),
        (4, [0.0, -30.0, 180.0, -140.0, 0.0, -110.0, 90.0]),
    ] {
        let mut world = World::default();
        start(&mut world, id, 0);
        let s = run_to_rest(&mut world, |_| {});
        assert!(off(&s, want) < 0.01, "action {id}: {:?}", s.joint_position);
        assert_eq!(s.action_status, ActionStatus::Completed, "action {id}");
    }
}

#[test]
fn sequence_1_runs_retract_then_home_reporting_itself_started_until_the_end() {
    // From Zero, so the direct way home never passes near Retract.
    let mut world = World {
        arm: Arm::at([0.0; 7]),
        ..World::default()
    };
    start(&mut world, 1, 1);
    let mut nearest_retract = f64::INFINITY;
    let s = run_to_rest(&mut world, |s| {
        nearest_retract = nearest_retract.min(off(s, RETRACT));
        assert_eq!(
            (s.action_status, s.action_id, s.move_type),
            (ActionStatus::Started, 1, 1),
            "between and during the steps the sequence is what runs"
        );
    });
    assert!(
        nearest_retract < 0.5,
        "passed Retract within {nearest_retract} deg"
    );
    assert!(off(&s, HOME) < 0.01, "ends at home: {:?}", s.joint_position);
    assert_eq!(
        (s.action_status, s.action_id, s.move_type),
        (ActionStatus::Completed, 1, 1)
    );
}

#[test]
fn a_stop_during_a_sequence_aborts_it_and_the_next_step_never_starts() {
    let mut world = World::default();
    start(&mut world, 1, 1);
    world.arm.advance(1.0);
    write_registers(&mut world, 200, &[2]).expect("stop accepted");
    let stopped = world.arm.snapshot();
    assert_eq!(stopped.action_status, ActionStatus::Aborted);
    assert!(
        off(&stopped, RETRACT) > 1.0,
        "stopped on the way to Retract"
    );
    world.arm.advance(10.0);
    let later = world.arm.snapshot();
    assert!(!later.moving);
    assert_eq!(
        later.joint_position, stopped.joint_position,
        "Home never ran"
    );
    assert_eq!(later.action_status, ActionStatus::Aborted);
}

#[test]
fn an_unknown_action_or_sequence_is_aborted_naming_it_and_nothing_moves() {
    for (id, move_type) in [(7, 0), (9, 1), (1, 0)] {
        let mut world = World::default();
        let before = world.arm.joints();
        start(&mut world, id, move_type);
        world.arm.advance(0.5);
        let s = world.arm.snapshot();
        assert_eq!(
            (s.action_status, s.action_id, s.move_type),
            (ActionStatus::Aborted, id, move_type)
        );
        assert_eq!(world.arm.joints(), before, "{id}/{move_type} moved");
    }
}

#[test]
fn a_sequence_on_an_arm_in_fault_is_aborted_and_nothing_moves() {
    let mut world = World::default();
    world.arm.raise_fault(4);
    let before = world.arm.joints();
    start(&mut world, 1, 1);
    world.arm.advance(0.5);
    assert_eq!(world.arm.snapshot().action_status, ActionStatus::Aborted);
    assert_eq!(world.arm.joints(), before);
}
