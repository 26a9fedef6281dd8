//! One speed cap for every motion of the simulated operator, measured on the simulated arm (no
//! sockets, simulated time): the tool point never moves faster than the cap times the speed,
//! whatever the motion. And the simulator's Home is a joint-space move that never passes a
//! joint limit, over Talos and over Modbus.

use armjog::kortex::Flag;
use armjog::sim::arm_model::{ActionStatus, Arm, STEP, SimMotion};
use armjog::sim::kinematics::{self, HOME_DEG, JOINTS};
use armjog::sim::modbus_registers::{HOME_ACTION_ID, write_registers};
use armjog::sim::operator::Operator;
use armjog::sim::world::World;
use armjog::talos::hardware::{ActuatorCommand, HwRequest};
use armjog::talos::{Reply, Request};

/// The cap of these tests, m/s.
const CAP: f64 = 0.05;
/// Integration and finite-difference slack over the cap.
const TOLERANCE: f64 = 1.02;

fn operator(speed: u8) -> Operator {
    let mut op = Operator::with_max_jog_linear(CAP);
    let reply = op.handle(&mut Arm::default(), Request::SetSpeed { speed });
    assert!(reply.return_code().is_ok());
    op
}

fn ok(op: &mut Operator, arm: &mut Arm, request: Request) {
    let reply: Reply = op.handle(arm, request.clone());
    assert!(reply.return_code().is_ok(), "{request:?}: {reply:?}");
}

fn hw(request: HwRequest) -> Request {
    Request::HardwareOperation {
        subcommand: request.subcommand(),
        reserved: 0,
        payload: request.encode_payload().expect("payload"),
    }
}

/// Runs the arm for `seconds` (calling `refresh` every 100 ms, as a held key re-sends its
/// START) and returns the highest tool speed seen over any 10 ms and the distance covered.
fn measure(arm: &mut Arm, seconds: f64, mut refresh: impl FnMut(&mut Arm)) -> (f64, f64) {
    let window = 10;
    let steps = (seconds / STEP).round() as usize;
    let mut positions = vec![arm.pose().position];
    let mut top = 0.0f64;
    for i in 1..=steps {
        if i % 100 == 0 {
            refresh(arm);
        }
        arm.step();
        positions.push(arm.pose().position);
        if i >= window {
            let d = (positions[i] - positions[i - window]).norm();
            top = top.max(d / (window as f64 * STEP));
        }
    }
    let travelled = positions
        .windows(2)
        .map(|w| (w[1] - w[0]).norm())
        .sum::<f64>();
    (top, travelled)
}

fn assert_capped(what: &str, (top, travelled): (f64, f64), cap: f64, seconds: f64) {
    assert!(
        top <= cap * TOLERANCE,
        "{what}: {:.1} mm/s over the {:.1} mm/s cap",
        top * 1000.0,
        cap * 1000.0
    );
    // It did move, near the cap (not a motion that was simply refused or crawling).
    assert!(
        travelled > 0.5 * cap * seconds,
        "{what}: only {:.1} mm in {seconds} s",
        travelled * 1000.0
    );
}

#[test]
fn continuous_polar_pans_stay_under_the_cap() {
    for (azimuth, altitude) in [(1, 0), (0, 1), (1, 1), (-1, -1)] {
        let (mut op, mut arm) = (operator(100), Arm::default());
        let start = Request::PolarPanStart {
            moving_azimuth: azimuth,
            moving_altitude: altitude,
        };
        ok(&mut op, &mut arm, start.clone());
        let measured = measure(&mut arm, 1.0, |arm| ok(&mut op.clone(), arm, start.clone()));
        assert_capped(&format!("polar {azimuth} {altitude}"), measured, CAP, 1.0);
    }
}

#[test]
fn the_cap_scales_with_the_speed() {
    let (mut op, mut arm) = (operator(40), Arm::default());
    let start = Request::PolarPanStart {
        moving_azimuth: 1,
        moving_altitude: 1,
    };
    ok(&mut op, &mut arm, start.clone());
    let measured = measure(&mut arm, 1.0, |arm| ok(&mut op.clone(), arm, start.clone()));
    assert_capped("polar at 40 %", measured, 0.4 * CAP, 1.0);
}

#[test]
fn discrete_polar_and_cartesian_moves_stay_under_the_cap() {
    let pan = Request::PolarPan {
        delta_azimuth: 20,
        delta_altitude: 10,
        delay_ms: 0,
        time_ms: 0,
    };
    let cartesian = Request::CartesianMove {
        delta_x: -500,
        delta_y: 800,
        delta_z: 500,
        delay_ms: 0,
        time_ms: 0,
    };
    // Timed: asks for 100 mm in 0.5 s, the cap holds it to 50 mm/s.
    let timed = Request::CartesianMove {
        delta_x: 1000,
        delta_y: 0,
        delta_z: 0,
        delay_ms: 0,
        time_ms: 500,
    };
    for request in [pan, cartesian, timed] {
        let (mut op, mut arm) = (operator(100), Arm::default());
        ok(&mut op, &mut arm, request.clone());
        let measured = measure(&mut arm, 1.0, |_| {});
        assert_capped(&format!("{request:?}"), measured, CAP, 1.0);
    }
}

#[test]
fn continuous_cartesian_jogs_stay_under_the_cap() {
    let (mut op, mut arm) = (operator(100), Arm::default());
    let start = Request::CartesianMoveStart {
        moving_x: 1,
        moving_y: -1,
        moving_z: 1,
    };
    ok(&mut op, &mut arm, start.clone());
    let measured = measure(&mut arm, 1.0, |arm| ok(&mut op.clone(), arm, start.clone()));
    assert_capped("cartesian diagonal", measured, CAP, 1.0);
}

#[test]
fn joint_jogs_stay_under_the_cap_whatever_rate_is_asked() {
    // 60 deg/s of J1, J2 or J4 would move the tool at several hundred mm/s.
    for joint in [1u8, 2, 4, 6] {
        let (mut op, mut arm) = (operator(100), Arm::default());
        let jog = hw(HwRequest::SendActuatorCommand {
            joint,
            command: ActuatorCommand::jog(0.0, -60.0),
        });
        ok(&mut op, &mut arm, jog.clone());
        let measured = measure(&mut arm, 1.0, |arm| ok(&mut op.clone(), arm, jog.clone()));
        assert_capped(&format!("joint {joint}"), measured, CAP, 1.0);
    }
}

#[test]
fn go_to_and_home_stay_under_the_cap() {
    let away = kinematics::to_radians(&[40.0, 40.0, 150.0, 250.0, 30.0, 80.0, 60.0]);
    // A position saved with joints (a joint move) and one set by coordinates (a cartesian move).
    let (mut op, mut arm) = (operator(100), Arm::at(away));
    ok(
        &mut op,
        &mut arm,
        Request::SavePosition {
            name: "away".into(),
            anchor: false,
            parent: String::new(),
        },
    );
    ok(
        &mut op,
        &mut arm,
        Request::SetCartesianPosition {
            name: "over".into(),
            x: 4000,
            y: 1500,
            z: 3500,
        },
    );
    let mut arm = Arm::default();
    for name in ["away", "over"] {
        ok(
            &mut op,
            &mut arm,
            Request::GoToPosition { name: name.into() },
        );
        let measured = measure(&mut arm, 1.0, |_| {});
        assert_capped(&format!("go to {name}"), measured, CAP, 1.0);
        arm.stop();
    }
    let mut arm = Arm::at(away);
    ok(&mut op, &mut arm, Request::Home { delay_ms: 0 });
    let measured = measure(&mut arm, 1.0, |_| {});
    assert_capped("home", measured, CAP, 1.0);
}

/// Poses to home from, near every limit and with the continuous joints wound past a turn.
fn start_poses() -> Vec<[f64; JOINTS]> {
    vec![
        // J4 near +147.8: the short way to 230 (-130) would cross 180, through the limit.
        [0.0, 15.0, 180.0, 140.0, 0.0, 55.0, 90.0],
        [0.0, 15.0, 180.0, 146.0, 0.0, 55.0, 90.0],
        // J2 near both ends.
        [0.0, 127.0, 180.0, 230.0, 0.0, 55.0, 90.0],
        [0.0, -127.0, 180.0, 230.0, 0.0, 55.0, 90.0],
        // J6 near both ends: 55 -> -119 and 119.
        [0.0, 15.0, 180.0, 230.0, 0.0, -119.0, 90.0],
        [0.0, 15.0, 180.0, 230.0, 0.0, 119.0, 90.0],
        // J4 near -147.8 (212.2 as reported).
        [0.0, 15.0, 180.0, 213.0, 0.0, 55.0, 90.0],
        // Continuous joints wound round: the short way is back through 0.
        [350.0, 15.0, -170.0, 230.0, 720.0 + 10.0, 55.0, -270.0],
        [170.0, 60.0, 10.0, 100.0, 200.0, -100.0, 300.0],
    ]
}

fn assert_home(arm: &Arm, from: &[f64; JOINTS]) {
    let home = kinematics::to_radians(&HOME_DEG);
    for (i, (q, h)) in arm.joints().iter().zip(home).enumerate() {
        let off = kinematics::wrap_pi(q - h).to_degrees();
        assert!(
            off.abs() < 0.01,
            "from {from:?}: joint {} off by {off}",
            i + 1
        );
    }
    let s = arm.snapshot();
    assert_eq!(s.action_status, ActionStatus::Completed, "from {from:?}");
    assert_eq!(s.warnings & Flag::JointFault.bit(), 0, "from {from:?}");
}

/// Steps until the motion ends (at most `seconds`), checking no joint ever leaves its range
/// and no continuous joint turns further than half a turn.
fn run_home(arm: &mut Arm, from: &[f64; JOINTS], seconds: f64) {
    let start = arm.joints();
    for _ in 0..(seconds / STEP) as usize {
        arm.step();
        for (i, q) in arm.joints().iter().enumerate() {
            assert!(kinematics::within_limit(i, *q), "from {from:?}: J{}", i + 1);
            let turned = (q - start[i]).abs().to_degrees();
            let continuous = kinematics::JOINT_LIMITS_DEG[i].is_none();
            assert!(
                !continuous || turned <= 180.0 + 1e-6,
                "from {from:?}: J{} turned {turned}",
                i + 1
            );
        }
        if arm.motion().is_idle() {
            return;
        }
    }
    panic!("home from {from:?} did not end within {seconds} s");
}

#[test]
fn talos_home_is_a_joint_move_within_the_limits_from_any_pose() {
    for from in start_poses() {
        let mut op = Operator::default();
        let mut arm = Arm::at(kinematics::to_radians(&from));
        ok(&mut op, &mut arm, Request::SetSpeed { speed: 100 });
        ok(&mut op, &mut arm, Request::Home { delay_ms: 0 });
        assert!(matches!(arm.motion(), SimMotion::ToJoints { .. }));
        run_home(&mut arm, &from, 60.0);
        assert_home(&arm, &from);
    }
}

#[test]
fn modbus_home_action_is_a_joint_move_within_the_limits_from_any_pose() {
    for from in start_poses() {
        let mut world = World {
            arm: Arm::at(kinematics::to_radians(&from)),
            ..World::default()
        };
        // 200 <- 1 (start), 201 <- the Home action's id, 202 <- 0 (an action).
        write_registers(&mut world, 200, &[1, HOME_ACTION_ID, 0]).expect("accepted");
        assert!(matches!(world.arm.motion(), SimMotion::ToJoints { .. }));
        run_home(&mut world.arm, &from, 60.0);
        assert_home(&world.arm, &from);
    }
}
