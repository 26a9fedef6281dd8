//! Straight jogs stay straight and steps reach their target, stepped exactly (no real time).

use super::*;
use nalgebra::Rotation3;

/// Degrees between two orientations.
fn angle_deg(a: &Rotation3<f64>, b: &Rotation3<f64>) -> f64 {
    (a * b.inverse()).angle().to_degrees()
}

/// The worst straying of a base-frame jog from its line.
struct Straying {
    /// Largest distance from the commanded line, m.
    off_line: f64,
    /// Largest turn of the tool from its starting orientation, degrees.
    turn_deg: f64,
    /// Distance travelled along the line, m.
    along: f64,
}

/// Jogs at `velocity` (m/s, base frame) for `seconds`, checking the tool every millisecond.
fn jog(arm: &mut Arm, velocity: Vector3<f64>, seconds: f64) -> Straying {
    let start = arm.pose();
    let direction = velocity.normalize();
    arm.command(
        SimMotion::Twist {
            linear: velocity,
            angular: Vector3::zeros(),
            frame: ReferenceFrame::Base,
        },
        0.0,
        false,
    )
    .unwrap();
    let mut straying = Straying {
        off_line: 0.0,
        turn_deg: 0.0,
        along: 0.0,
    };
    for _ in 0..(seconds / STEP).round() as u64 {
        arm.step();
        assert!(
            !arm.motion().is_idle(),
            "the jog stopped at {:?}",
            arm.pose()
        );
        let pose = arm.pose();
        let moved = pose.position - start.position;
        let along = moved.dot(&direction);
        straying.off_line = straying.off_line.max((moved - direction * along).norm());
        straying.turn_deg = straying
            .turn_deg
            .max(angle_deg(&pose.rotation, &start.rotation));
        straying.along = along;
    }
    arm.stop();
    straying
}

#[test]
fn a_250_mm_plus_x_jog_from_home_stays_on_its_line() {
    let mut arm = Arm::default();
    let start = arm.pose().position;
    let s = jog(&mut arm, Vector3::new(0.25, 0.0, 0.0), 1.0);
    let d = arm.pose().position - start;
    assert!((s.along - 0.25).abs() < 0.002, "travelled {} m", s.along);
    assert!(d.y.abs() <= 0.0005 && d.z.abs() <= 0.0005, "{d:?}");
    assert!(s.off_line <= 0.0005, "{} mm off the line", s.off_line * 1e3);
    assert!(s.turn_deg <= 0.1, "turned {}°", s.turn_deg);
}

#[test]
fn an_x_z_diagonal_does_not_wander_in_y() {
    let mut arm = Arm::default();
    let start = arm.pose().position;
    let v = Vector3::new(1.0, 0.0, 1.0).normalize() * 0.25;
    let s = jog(&mut arm, v, 1.0);
    let d = arm.pose().position - start;
    assert!(d.y.abs() <= 0.0005, "{d:?}");
    assert!(s.off_line <= 0.0005, "{} mm off the line", s.off_line * 1e3);
    assert!(s.turn_deg <= 0.1, "turned {}°", s.turn_deg);
}

#[test]
fn plus_y_and_minus_z_jogs_stay_on_their_lines() {
    for v in [Vector3::new(0.0, 0.25, 0.0), Vector3::new(0.0, 0.0, -0.25)] {
        let mut arm = Arm::default();
        let s = jog(&mut arm, v, 1.0);
        assert!(
            (s.along - 0.25).abs() < 0.002,
            "{v:?}: travelled {}",
            s.along
        );
        assert!(
            s.off_line <= 0.0005,
            "{v:?}: {} mm off the line",
            s.off_line * 1e3
        );
        assert!(s.turn_deg <= 0.1, "{v:?}: turned {}°", s.turn_deg);
    }
}

#[test]
fn a_slow_jog_stays_on_its_line_too() {
    let mut arm = Arm::default();
    let s = jog(&mut arm, Vector3::new(0.01, 0.0, 0.0), 5.0);
    assert!((s.along - 0.05).abs() < 0.001, "travelled {}", s.along);
    assert!(s.off_line <= 0.0005 && s.turn_deg <= 0.1);
}

#[test]
fn a_tool_frame_jog_keeps_the_tool_orientation() {
    let mut arm = Arm::default();
    let start = arm.pose();
    arm.command(
        SimMotion::Twist {
            linear: Vector3::new(0.0, 0.0, 0.1),
            angular: Vector3::zeros(),
            frame: ReferenceFrame::Tool,
        },
        0.0,
        false,
    )
    .unwrap();
    arm.advance(1.0);
    let pose = arm.pose();
    let expected = start.position + start.rotation * Vector3::new(0.0, 0.0, 0.1);
    assert!((pose.position - expected).norm() < 0.0005, "{pose:?}");
    assert!(angle_deg(&pose.rotation, &start.rotation) <= 0.1);
}

#[test]
fn a_jog_out_of_reach_holds_little_error_and_never_outruns_its_cap() {
    // +X at 0.25 m/s for 3 s asks for 750 mm: the arm stretches out and cannot follow.
    let mut arm = Arm::default();
    let cap = 0.25;
    arm.command_capped(
        SimMotion::Twist {
            linear: Vector3::new(0.5, 0.0, 0.0),
            angular: Vector3::zeros(),
            frame: ReferenceFrame::Base,
        },
        0.0,
        false,
        Some(cap),
    )
    .unwrap();
    for _ in 0..3000 {
        arm.step();
        let speed = Vector3::from(arm.snapshot().tcp_linear_velocity).norm();
        assert!(speed <= cap * 1.0001, "{speed} m/s");
        if let Some(reference) = &arm.reference {
            let err = kinematics::pose_error(&arm.pose(), &reference.pose);
            // The held error, plus one step of motion.
            assert!(err.fixed_rows::<3>(0).norm() <= 0.002 + cap * STEP + 1e-9);
            assert!(err.fixed_rows::<3>(3).norm().to_degrees() <= 0.5 + 1e-6);
        }
        if arm.motion().is_idle() {
            break;
        }
    }
}

#[test]
fn a_new_motion_starts_from_where_the_tool_is() {
    let mut arm = Arm::default();
    jog(&mut arm, Vector3::new(0.1, 0.0, 0.0), 0.3);
    // The same jog again after a stop: nothing of the first one's reference is left.
    let s = jog(&mut arm, Vector3::new(0.1, 0.0, 0.0), 0.3);
    assert!((s.along - 0.03).abs() < 0.001, "travelled {}", s.along);
    assert!(s.off_line <= 0.0005);
}

#[test]
fn a_polar_pan_keeps_its_radius_and_height() {
    let mut arm = Arm::default();
    let p0 = arm.pose().position;
    arm.command(
        SimMotion::Polar {
            azimuth: 30f64.to_radians(),
            altitude: 0.0,
        },
        0.0,
        false,
    )
    .unwrap();
    let radius = |p: Vector3<f64>| p.x.hypot(p.y);
    for _ in 0..2000 {
        arm.step();
        let p = arm.pose().position;
        assert!((radius(p) - radius(p0)).abs() <= 0.0005, "{p:?}");
        assert!((p.z - p0.z).abs() <= 0.0005, "{p:?}");
    }
    let turned = arm.pose().position.y.atan2(arm.pose().position.x) - p0.y.atan2(p0.x);
    assert!(
        (turned.to_degrees() - 60.0).abs() < 0.5,
        "{}",
        turned.to_degrees()
    );
}

/// Runs a discrete move to `target` until it finishes (at most 5 s).
fn move_to(arm: &mut Arm, target: Pose, linear_speed: f64) -> f64 {
    arm.command(
        SimMotion::ToPose {
            target,
            linear_speed,
            angular_speed: 30f64.to_radians(),
        },
        0.0,
        false,
    )
    .unwrap();
    let start = arm.time();
    while !arm.motion().is_idle() {
        assert!(arm.time() - start < 5.0, "the move never finished");
        arm.step();
    }
    assert_eq!(
        arm.snapshot().action_status,
        ActionStatus::Completed,
        "to {target:?}: warnings {:x}, at {:?}",
        arm.snapshot().warnings,
        arm.pose()
    );
    arm.time() - start
}

#[test]
fn steps_of_a_tenth_one_and_ten_millimetres_end_on_target() {
    for axis in 0..3 {
        for mm in [0.1, 1.0, 10.0, -1.0] {
            let mut arm = Arm::default();
            let start = arm.pose();
            let mut target = start;
            target.position[axis] += mm / 1000.0;
            let took = move_to(&mut arm, target, 0.125);
            let pose = arm.pose();
            let moved = (pose.position[axis] - start.position[axis]) * 1000.0;
            assert!(
                (moved - mm).abs() <= 0.05,
                "axis {axis}: a {mm} mm step moved {moved} mm"
            );
            assert!(
                (pose.position - target.position).norm() <= 0.05e-3,
                "axis {axis}, {mm} mm: {:?} off",
                pose.position - target.position
            );
            assert!(angle_deg(&pose.rotation, &target.rotation) <= 0.1);
            assert!(took < 1.0, "a {mm} mm step took {took} s");
        }
    }
}

#[test]
fn a_step_that_also_turns_ends_within_a_tenth_of_a_degree() {
    let mut arm = Arm::default();
    let mut target = arm.pose();
    target.position.z += 0.002;
    target.rotation =
        Rotation3::from_axis_angle(&Vector3::z_axis(), 0.5f64.to_radians()) * target.rotation;
    move_to(&mut arm, target, 0.125);
    let pose = arm.pose();
    assert!((pose.position - target.position).norm() <= 0.05e-3);
    assert!(angle_deg(&pose.rotation, &target.rotation) <= 0.1);
}
