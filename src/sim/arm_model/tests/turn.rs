//! Orientation jogs: a twist with only an angular part turns the tool about its point, in the
//! base and the tool frame (stepped exactly, no real time).

use super::*;
use nalgebra::Rotation3;

const RATE_DEG_S: f64 = 15.0;
const SECONDS: f64 = 2.0;

/// Degrees between two orientations.
fn angle_deg(a: &Rotation3<f64>, b: &Rotation3<f64>) -> f64 {
    (a * b.inverse()).angle().to_degrees()
}

/// Turns from home about `axis` (unit, in `frame`) for [`SECONDS`]: the farthest the tool point
/// strayed from where it started (m), and the angle the tool turned (degrees).
fn turn(axis: Vector3<f64>, frame: ReferenceFrame) -> (f64, f64) {
    let mut arm = Arm::default();
    let start = arm.pose();
    arm.command(
        SimMotion::Twist {
            linear: Vector3::zeros(),
            angular: axis * RATE_DEG_S.to_radians(),
            frame,
        },
        0.0,
        false,
    )
    .unwrap();
    let mut strayed: f64 = 0.0;
    for _ in 0..(SECONDS / STEP).round() as u64 {
        arm.step();
        assert!(
            !arm.motion().is_idle(),
            "the turn stopped at {:?}",
            arm.pose()
        );
        strayed = strayed.max((arm.pose().position - start.position).norm());
    }
    let end = arm.pose();
    arm.stop();
    // The turn is about the commanded axis: the tool's rotation relative to the start, seen in
    // the base frame for a base-frame turn and in the start tool frame for a tool-frame turn.
    let relative = match frame {
        ReferenceFrame::Tool => start.rotation.inverse() * end.rotation,
        _ => end.rotation * start.rotation.inverse(),
    };
    if let Some((turned_about, _)) = relative.axis_angle() {
        assert!(
            turned_about.dot(&axis) > 0.99,
            "{frame:?} {axis:?}: turned about {turned_about:?}"
        );
    }
    (strayed, angle_deg(&end.rotation, &start.rotation))
}

#[test]
fn a_two_second_turn_about_each_axis_keeps_the_tool_point_within_3_mm() {
    let expected = RATE_DEG_S * SECONDS;
    for frame in [ReferenceFrame::Base, ReferenceFrame::Tool] {
        for axis in [Vector3::x(), Vector3::y(), Vector3::z(), -Vector3::z()] {
            let (strayed, turned) = turn(axis, frame);
            assert!(
                strayed <= 0.003,
                "{frame:?} {axis:?}: the tool point moved {:.2} mm",
                strayed * 1e3
            );
            assert!(
                (turned - expected).abs() <= expected * 0.1,
                "{frame:?} {axis:?}: turned {turned:.1}° of {expected}°"
            );
        }
    }
}
