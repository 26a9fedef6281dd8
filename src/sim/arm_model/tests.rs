//! The simulated arm's motions, limits and efforts, stepped exactly.

#![allow(clippy::needless_range_loop)] // parallel per-joint arrays read clearest by index

use super::*;
use crate::sim::kinematics::MAX_JOINT_TORQUE;
use nalgebra::Vector3;

/// Straight jogs and steps.
mod path;
/// Orientation jogs.
mod turn;

#[test]
fn starts_at_home_at_rest() {
    let arm = Arm::default();
    let s = arm.snapshot();
    assert!((s.tcp_position[0] - 0.4566).abs() < 1e-3);
    assert_eq!(s.robot_state, RobotState::Ready);
    assert!(!s.moving);
}

#[test]
fn a_base_twist_moves_the_tcp_along_x_at_the_commanded_speed() {
    let mut arm = Arm::default();
    let x0 = arm.pose().position;
    let twist = SimMotion::Twist {
        linear: Vector3::new(0.1, 0.0, 0.0),
        angular: Vector3::zeros(),
        frame: ReferenceFrame::Base,
    };
    arm.command(twist, 0.0, false).unwrap();
    arm.advance(0.5);
    let d = arm.pose().position - x0;
    assert!((d.x - 0.05).abs() < 0.005, "{d:?}");
    assert!(d.y.abs() < 0.003 && d.z.abs() < 0.003, "{d:?}");
}

#[test]
fn the_watchdog_stops_an_unrefreshed_continuous_motion() {
    let mut arm = Arm::default();
    let m = SimMotion::Polar {
        azimuth: 0.2,
        altitude: 0.0,
    };
    arm.command(m, 0.0, true).unwrap();
    arm.advance(0.3);
    arm.refresh_watchdog();
    arm.advance(0.45);
    assert!(
        !arm.motion().is_idle(),
        "refreshed at 0.3 s, still moving at 0.75 s"
    );
    arm.advance(0.051 + STEP);
    assert!(arm.motion().is_idle());
    assert!(!arm.is_moving());
}

#[test]
fn polar_azimuth_orbits_about_z_at_constant_radius_and_height() {
    let mut arm = Arm::default();
    let p0 = arm.pose().position;
    let m = SimMotion::Polar {
        azimuth: 10f64.to_radians(),
        altitude: 0.0,
    };
    arm.command(m, 0.0, false).unwrap();
    arm.advance(1.0);
    let p = arm.pose().position;
    let r0 = (p0.x.powi(2) + p0.y.powi(2)).sqrt();
    let r = (p.x.powi(2) + p.y.powi(2)).sqrt();
    assert!((r - r0).abs() < 0.003 && (p.z - p0.z).abs() < 0.003);
    let turned = p.y.atan2(p.x) - p0.y.atan2(p0.x);
    assert!(
        (turned.to_degrees() - 10.0).abs() < 0.5,
        "{}",
        turned.to_degrees()
    );
}

#[test]
fn polar_altitude_raises_the_elevation() {
    let mut arm = Arm::default();
    let elevation = |p: Vector3<f64>| p.z.atan2((p.x.powi(2) + p.y.powi(2)).sqrt());
    let e0 = elevation(arm.pose().position);
    arm.command(
        SimMotion::Polar {
            azimuth: 0.0,
            altitude: 0.1,
        },
        0.0,
        false,
    )
    .unwrap();
    arm.advance(0.5);
    assert!(elevation(arm.pose().position) > e0 + 0.04);
}

#[test]
fn to_pose_reaches_a_reachable_target_and_refuses_an_unreachable_one() {
    let mut arm = Arm::default();
    let mut target = arm.pose();
    target.position += Vector3::new(-0.05, 0.05, 0.05);
    let m = SimMotion::ToPose {
        target,
        linear_speed: 0.1,
        angular_speed: 0.5,
    };
    arm.command(m, 0.0, false).unwrap();
    arm.advance(3.0);
    assert!((arm.pose().position - target.position).norm() < 1e-3);
    assert!(arm.motion().is_idle());
    assert_eq!(arm.snapshot().action_status, ActionStatus::Completed);

    let mut far = arm.pose();
    far.position = Vector3::new(1.5, 0.0, 0.4);
    let m = SimMotion::ToPose {
        target: far,
        linear_speed: 0.1,
        angular_speed: 0.5,
    };
    assert_eq!(arm.command(m, 0.0, false), Err(Refusal::Unreachable));
}

#[test]
fn home_returns_every_joint() {
    let mut arm = Arm::at(kinematics::to_radians(&[
        20.0, 30.0, 170.0, 240.0, 10.0, 40.0, 80.0,
    ]));
    let home = kinematics::to_radians(&HOME_DEG);
    arm.command(
        SimMotion::ToJoints {
            target: home,
            fraction: 0.5,
        },
        0.0,
        false,
    )
    .unwrap();
    arm.advance(3.0);
    for i in 0..JOINTS {
        assert!(
            kinematics::wrap_pi(arm.joints()[i] - home[i]).abs() < 1e-3,
            "joint {i}"
        );
    }
}

#[test]
fn a_joint_limit_stops_the_motion_and_warns() {
    // J2 starts near +128.9 deg and is driven outwards.
    let mut arm = Arm::at(kinematics::to_radians(&[
        0.0, 127.0, 180.0, 230.0, 0.0, 55.0, 90.0,
    ]));
    let m = SimMotion::JointVelocity {
        joint: 1,
        velocity: 20f64.to_radians(),
    };
    arm.command(m, 0.0, false).unwrap();
    arm.advance(0.5);
    assert!(arm.motion().is_idle());
    assert!(arm.joints()[1].to_degrees() <= 128.9 + 1e-6);
    assert_ne!(arm.snapshot().warnings & (Flag::JointFault.bit()), 0);
}

#[test]
fn quick_stop_faults_the_arm_until_reset() {
    let mut arm = Arm::default();
    arm.quick_stop();
    assert_eq!(arm.snapshot().robot_state, RobotState::InFault);
    let m = SimMotion::Polar {
        azimuth: 0.1,
        altitude: 0.0,
    };
    assert_eq!(arm.command(m.clone(), 0.0, false), Err(Refusal::InFault));
    arm.fault_reset();
    assert!(arm.command(m, 0.0, false).is_ok());
}

#[test]
fn a_delayed_motion_waits() {
    let mut arm = Arm::default();
    let m = SimMotion::Polar {
        azimuth: 0.1,
        altitude: 0.0,
    };
    arm.command(m, 0.2, false).unwrap();
    arm.advance(0.1);
    assert!(arm.motion().is_idle());
    arm.advance(0.15);
    assert!(!arm.motion().is_idle());
}

#[test]
fn efforts_are_plausible_and_deterministic() {
    let mut a = Arm::default();
    let mut b = Arm::default();
    let m = SimMotion::Polar {
        azimuth: 0.2,
        altitude: 0.05,
    };
    a.command(m.clone(), 0.0, false).unwrap();
    b.command(m, 0.0, false).unwrap();
    a.advance(1.0);
    b.advance(1.0);
    assert_eq!(a.snapshot(), b.snapshot());
    let s = a.snapshot();
    for i in 0..JOINTS {
        assert!(s.joint_torque[i].abs() <= MAX_JOINT_TORQUE[i]);
        assert!(s.joint_current[i] > 0.0 && s.joint_current[i] < 10.0);
        assert!(s.joint_temperature[i] >= 30.0 && s.joint_temperature[i] < 80.0);
    }
    assert!(s.arm_voltage > 20.0 && s.arm_voltage < 25.0);
}

#[test]
fn a_non_finite_motion_is_refused_and_nothing_moves() {
    let mut arm = Arm::default();
    let before = arm.joints();
    let m = SimMotion::JointVelocity {
        joint: 0,
        velocity: f64::NAN,
    };
    assert_eq!(arm.command(m, 0.0, false), Err(Refusal::NotFinite));
    arm.advance(0.3);
    assert_eq!(arm.joints(), before);
}

/// The wrench is the tool's weight as a wrist sensor measures it: in the tool frame (the
/// console labels it so). At home the tool's Y axis points down, so gravity shows in Fy; in
/// any pose it is the base frame's gravity turned by the reported orientation.
#[test]
fn the_wrench_is_the_tools_weight_in_the_tool_frame() {
    let arm = Arm::default();
    let s = arm.snapshot();
    let [fx, fy, fz] = s.tcp_force;
    assert!((fy - -0.5 * 9.81).abs() < 1e-3, "{:?}", s.tcp_force);
    assert!(fx.abs() < 1e-3 && fz.abs() < 1e-3, "{:?}", s.tcp_force);

    let mut arm = Arm::default();
    let twist = SimMotion::Twist {
        linear: Vector3::zeros(),
        angular: Vector3::new(20.0, 10.0, 0.0),
        frame: ReferenceFrame::Base,
    };
    arm.command(twist, 0.0, false).unwrap();
    arm.advance(0.5);
    let s = arm.snapshot();
    let orientation =
        kinematics::Pose::from_position_euler_deg(s.tcp_position, s.tcp_orientation).rotation;
    let in_tool = orientation.inverse() * Vector3::new(0.0, 0.0, -0.5 * 9.81);
    let force = Vector3::from(s.tcp_force);
    assert!((force - in_tool).norm() < 1e-3, "{force:?} vs {in_tool:?}");
    // Turned: no longer all in Fy.
    assert!(force.x.abs() > 0.1 || force.z.abs() > 0.1, "{force:?}");
}
