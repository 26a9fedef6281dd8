//! The simulated operator's semantics, driven directly (no sockets).

use super::{MAX_JOG_LINEAR, Operator, VERSION};
use crate::sim::arm_model::{Arm, SimMotion};
use crate::talos::hardware::{self, ActuatorCommand, HwReply, HwRequest};
use crate::talos::{Reply, Request, ReturnCode};

/// Saving, going to, anchoring and deleting named positions.
mod positions;

fn rc(reply: &Reply) -> ReturnCode {
    reply.return_code()
}

fn cart(op: &mut Operator, arm: &mut Arm, name: &str) -> (i32, i32, i32) {
    match op.handle(arm, Request::GetCartesianPosition { name: name.into() }) {
        Reply::GetCartesianPosition {
            return_code,
            x,
            y,
            z,
        } if return_code.is_ok() => (x, y, z),
        other => panic!("get_cart {name}: {other:?}"),
    }
}

fn save(op: &mut Operator, arm: &mut Arm, name: &str, anchor: bool, parent: &str) -> ReturnCode {
    let reply = op.handle(
        arm,
        Request::SavePosition {
            name: name.into(),
            anchor,
            parent: parent.into(),
        },
    );
    rc(&reply)
}

#[test]
fn handshake_reports_the_version() {
    let reply =
        Operator::default().handle(&mut Arm::default(), Request::Handshake { oid: Some(3) });
    assert_eq!(
        reply,
        Reply::Handshake {
            return_code: ReturnCode::OK,
            major_version: VERSION.0,
            minor_version: VERSION.1
        }
    );
}

#[test]
fn speed_is_a_percentage_and_0_or_over_100_is_refused() {
    let (mut op, mut arm) = (Operator::default(), Arm::default());
    assert_eq!(
        rc(&op.handle(&mut arm, Request::SetSpeed { speed: 80 })),
        ReturnCode::OK
    );
    assert_eq!(
        op.handle(&mut arm, Request::GetSpeed),
        Reply::GetSpeed {
            return_code: ReturnCode::OK,
            speed: 80
        }
    );
    for bad in [0, 101, 255] {
        assert_eq!(
            rc(&op.handle(&mut arm, Request::SetSpeed { speed: bad })),
            ReturnCode::OUT_OF_RANGE
        );
    }
    assert_eq!(op.speed(), 80);
}

#[test]
fn cartesian_start_moves_along_x_at_the_speed_setting_until_the_watchdog() {
    let (mut op, mut arm) = (Operator::default(), Arm::default());
    op.handle(&mut arm, Request::SetSpeed { speed: 40 });
    let x0 = arm.pose().position;
    let start = Request::CartesianMoveStart {
        moving_x: 1,
        moving_y: 0,
        moving_z: 0,
    };
    assert!(rc(&op.handle(&mut arm, start.clone())).is_ok());
    arm.advance(0.3);
    op.handle(&mut arm, start);
    arm.advance(0.3);
    let moved = arm.pose().position - x0;
    let expected = MAX_JOG_LINEAR * 0.4 * 0.6;
    assert!(
        (moved.x - expected).abs() < 0.01,
        "moved {moved:?}, expected {expected}"
    );
    assert!(arm.is_moving());
    arm.advance(0.25);
    assert!(
        !arm.is_moving(),
        "the watchdog stops 500 ms after the last START"
    );
}

#[test]
fn a_stop_stops_either_kind_of_continuous_motion() {
    let (mut op, mut arm) = (Operator::default(), Arm::default());
    op.handle(
        &mut arm,
        Request::PolarPanStart {
            moving_azimuth: 1,
            moving_altitude: 0,
        },
    );
    arm.advance(0.05);
    op.handle(&mut arm, Request::CartesianMoveStop);
    assert!(arm.motion().is_idle());
    op.handle(
        &mut arm,
        Request::CartesianMoveStart {
            moving_x: 0,
            moving_y: 0,
            moving_z: 1,
        },
    );
    op.handle(&mut arm, Request::PolarPanStop);
    assert!(arm.motion().is_idle());
}

#[test]
fn discrete_cartesian_move_arrives_and_honours_delay() {
    let (mut op, mut arm) = (Operator::default(), Arm::default());
    let p0 = arm.pose().position;
    let reply = op.handle(
        &mut arm,
        Request::CartesianMove {
            delta_x: 0,
            delta_y: 500,
            delta_z: -300,
            delay_ms: 200,
            time_ms: 1000,
        },
    );
    assert!(rc(&reply).is_ok());
    arm.advance(0.15);
    assert!(
        (arm.pose().position - p0).norm() < 1e-6,
        "still waiting for the delay"
    );
    arm.advance(2.5);
    let d = arm.pose().position - p0;
    assert!(
        (d.y - 0.05).abs() < 1e-3 && (d.z + 0.03).abs() < 1e-3,
        "{d:?}"
    );
}

#[test]
fn cartesian_steps_of_a_tenth_and_one_millimetre_move_that_far() {
    // Tenths of a millimetre: 1 is the 0.1 mm step, 10 the 1 mm one.
    for (tenths, axis) in [(1, 0), (10, 0), (-1, 1), (10, 2), (-10, 2)] {
        let (mut op, mut arm) = (Operator::default(), Arm::default());
        let p0 = arm.pose().position;
        let mut delta = [0; 3];
        delta[axis] = tenths;
        let reply = op.handle(
            &mut arm,
            Request::CartesianMove {
                delta_x: delta[0],
                delta_y: delta[1],
                delta_z: delta[2],
                delay_ms: 0,
                time_ms: 0,
            },
        );
        assert!(rc(&reply).is_ok());
        arm.advance(1.0);
        assert!(
            arm.motion().is_idle(),
            "{tenths} on axis {axis} still moving"
        );
        let moved_mm = (arm.pose().position - p0) * 1000.0;
        let wanted = f64::from(tenths) / 10.0;
        for k in 0..3 {
            let expected = if k == axis { wanted } else { 0.0 };
            assert!(
                (moved_mm[k] - expected).abs() <= 0.05,
                "{tenths} tenths on axis {axis}: moved {moved_mm:?} mm"
            );
        }
    }
}

#[test]
fn a_continuous_plus_x_start_moves_along_x_only() {
    let (mut op, mut arm) = (Operator::default(), Arm::default());
    assert!(rc(&op.handle(&mut arm, Request::SetSpeed { speed: 100 })).is_ok());
    let p0 = arm.pose();
    let start = Request::CartesianMoveStart {
        moving_x: 1,
        moving_y: 0,
        moving_z: 0,
    };
    // START refreshed every 250 ms (inside the watchdog) for 1 s at 250 mm/s.
    for _ in 0..4 {
        assert!(rc(&op.handle(&mut arm, start.clone())).is_ok());
        arm.advance(0.25);
    }
    op.handle(&mut arm, Request::CartesianMoveStop);
    let d = arm.pose().position - p0.position;
    // At the cap the tool runs a few per cent slow (damped IK), never fast.
    assert!(d.x > 0.23 && d.x <= 0.25, "{d:?}");
    assert!(d.y.abs() <= 5e-4 && d.z.abs() <= 5e-4, "{d:?}");
    let turned = (arm.pose().rotation * p0.rotation.inverse()).angle();
    assert!(
        turned.to_degrees() <= 0.1,
        "turned {}°",
        turned.to_degrees()
    );
}

#[test]
fn polar_pan_discrete_turns_the_azimuth_by_whole_degrees() {
    let (mut op, mut arm) = (Operator::default(), Arm::default());
    let p0 = arm.pose().position;
    let reply = op.handle(
        &mut arm,
        Request::PolarPan {
            delta_azimuth: 10,
            delta_altitude: 0,
            delay_ms: 0,
            time_ms: 0,
        },
    );
    assert!(rc(&reply).is_ok());
    arm.advance(3.0);
    let p = arm.pose().position;
    let turned = (p.y.atan2(p.x) - p0.y.atan2(p0.x)).to_degrees();
    assert!((turned - 10.0).abs() < 0.2, "{turned}");
}

#[test]
fn an_unreachable_move_is_refused_and_nothing_moves() {
    let (mut op, mut arm) = (Operator::default(), Arm::default());
    let reply = op.handle(
        &mut arm,
        Request::CartesianMove {
            delta_x: 20_000,
            delta_y: 0,
            delta_z: 0,
            delay_ms: 0,
            time_ms: 0,
        },
    );
    assert_eq!(rc(&reply), ReturnCode::UNREACHABLE);
    assert!(arm.motion().is_idle());
}

#[test]
fn motion_is_refused_while_the_arm_is_in_fault() {
    let (mut op, mut arm) = (Operator::default(), Arm::default());
    arm.quick_stop();
    let reply = op.handle(&mut arm, Request::Home { delay_ms: 0 });
    assert_eq!(rc(&reply), ReturnCode::ARM_FAULT);
}

#[test]
fn hardware_operations_read_feedback_and_jog_one_joint() {
    let (mut op, mut arm) = (Operator::default(), Arm::default());
    let hw = |request: HwRequest| Request::HardwareOperation {
        subcommand: request.subcommand(),
        reserved: 0,
        payload: request.encode_payload().unwrap(),
    };
    let reply = op.handle(&mut arm, hw(HwRequest::GetActuatorFeedback { selector: 0 }));
    let Reply::HardwareOperation {
        return_code,
        subcommand,
        payload,
    } = reply
    else {
        panic!()
    };
    assert!(return_code.is_ok());
    let HwReply::GetActuatorFeedback { actuators } = HwReply::decode(subcommand, &payload).unwrap()
    else {
        panic!()
    };
    assert_eq!(actuators.len(), 7);
    assert!((actuators[3].position_deg - 230.0).abs() < 0.01);

    let jog = HwRequest::SendActuatorCommand {
        joint: 1,
        command: ActuatorCommand::jog(0.0, 10.0),
    };
    assert!(rc(&op.handle(&mut arm, hw(jog))).is_ok());
    assert!(matches!(
        arm.motion(),
        SimMotion::JointVelocity { joint: 0, .. }
    ));
    arm.advance(0.4);
    assert!((arm.joints()[0].to_degrees() - 4.0).abs() < 0.1);
    arm.advance(0.2);
    assert!(
        arm.motion().is_idle(),
        "jog stops without a refresh within 500 ms"
    );

    let unknown = Request::HardwareOperation {
        subcommand: 0x0042,
        reserved: 0,
        payload: vec![],
    };
    assert_eq!(
        rc(&op.handle(&mut arm, unknown)),
        ReturnCode::UNSUPPORTED_SUBCOMMAND
    );
    let short = Request::HardwareOperation {
        subcommand: hardware::subcommand::SEND_ACTUATOR_COMMAND,
        reserved: 0,
        payload: vec![1, 2],
    };
    assert_eq!(
        rc(&op.handle(&mut arm, short)),
        ReturnCode::MALFORMED_PAYLOAD
    );
}

#[test]
fn the_jog_speed_cap_is_the_operators_100_percent() {
    let (mut op, mut arm) = (Operator::with_max_jog_linear(0.1), Arm::default());
    op.handle(&mut arm, Request::SetSpeed { speed: 100 });
    let x0 = arm.pose().position.x;
    let start = Request::CartesianMoveStart {
        moving_x: 1,
        moving_y: 0,
        moving_z: 0,
    };
    op.handle(&mut arm, start);
    arm.advance(0.4);
    let moved = arm.pose().position.x - x0;
    assert!(
        (moved - 0.04).abs() < 0.004,
        "0.1 m/s for 0.4 s: moved {moved}"
    );
}
