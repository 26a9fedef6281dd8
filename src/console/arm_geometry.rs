//! The arm view's geometry, pure: joint and tool positions from the reported angles (forward
//! kinematics of [`crate::kortex::gen3`], as the simulator uses), the reach envelope, the panel's
//! two projections, and which way a jog moves the tool point.

use nalgebra::{Matrix4, Vector3};

use crate::kortex::{ReferenceFrame, gen3};
use crate::link::interface::JogMotion;

/// The arm's points and the tool's axes, base frame, metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArmPose {
    /// The base, each joint's origin (J1-J7; some coincide in the DH table), then the tool.
    pub points: [Vector3<f64>; 9],
    /// The tool interface's X, Y and Z axes (unit vectors).
    pub tool_axes: [Vector3<f64>; 3],
}

impl ArmPose {
    /// The tool point (tool interface origin).
    pub fn tool(&self) -> Vector3<f64> {
        self.points[8]
    }

    /// The tool frame's rotation (columns: its axes in the base frame).
    fn tool_rotation(&self) -> nalgebra::Matrix3<f64> {
        nalgebra::Matrix3::from_columns(&self.tool_axes)
    }
}

fn origin(t: &Matrix4<f64>) -> Vector3<f64> {
    Vector3::new(t[(0, 3)], t[(1, 3)], t[(2, 3)])
}

fn axis(t: &Matrix4<f64>, c: usize) -> Vector3<f64> {
    Vector3::new(t[(0, c)], t[(1, c)], t[(2, c)])
}

/// The arm at the reported joint angles (deg, 0-360), converted as the simulator does.
pub fn arm_pose(position_deg: &[f32; 7]) -> ArmPose {
    let q = position_deg.map(|d| f64::from(d).to_radians());
    let (joints, tool) = gen3::frames(&q);
    let mut points = [Vector3::zeros(); 9];
    for (point, frame) in points[1..8].iter_mut().zip(&joints) {
        *point = origin(frame);
    }
    points[8] = origin(&tool);
    ArmPose {
        points,
        tool_axes: [axis(&tool, 0), axis(&tool, 1), axis(&tool, 2)],
    }
}

/// The shoulder: the origin of the frame J2 turns in, on the base Z axis whatever J1.
pub fn shoulder() -> Vector3<f64> {
    origin(&gen3::frames(&[0.0; 7]).0[1])
}

/// The maximum reach, m: the tool's distance from the shoulder with every joint at 0.
pub fn reach() -> f64 {
    (gen3::tool_position(&[0.0; 7]) - shoulder()).norm()
}

/// The two drawings of the arm view.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Projection {
    /// Seen from above: X to the right, Y up.
    Top,
    /// Seen from the side (from -Y): X to the right, Z up.
    Side,
}

impl Projection {
    /// A base-frame point on this drawing's plane.
    pub fn project(self, p: &Vector3<f64>) -> (f64, f64) {
        match self {
            Projection::Top => (p.x, p.y),
            Projection::Side => (p.x, p.z),
        }
    }

    /// The world window drawn ([left, right], [bottom, top], m): reach plus margin, and the table.
    pub fn bounds(self) -> ([f64; 2], [f64; 2]) {
        let r = reach() + MARGIN;
        match self {
            Projection::Top => ([-r, r], [-r, r]),
            Projection::Side => {
                let z = shoulder().z;
                ([-r, r], [-TABLE_MARGIN, z + r])
            }
        }
    }

    /// Width over height of the world window (a terminal cell is about twice as tall as wide).
    pub fn aspect(self) -> f64 {
        let ([l, r], [b, t]) = self.bounds();
        (r - l) / (t - b)
    }
}

/// Room around the reach envelope, m.
const MARGIN: f64 = 0.05;
/// Room below the table in the side view, m: the table line shows above the panel's border.
const TABLE_MARGIN: f64 = 0.08;

/// The unit vector (base frame) a jog moves the tool point along at this pose; `None` when it does
/// not move it (J7) or cannot be told. `frame`: the cartesian jog frame (`None`: base).
pub fn jog_direction(
    motion: JogMotion,
    frame: Option<ReferenceFrame>,
    position_deg: &[f32; 7],
) -> Option<Vector3<f64>> {
    let pose = arm_pose(position_deg);
    let tool = pose.tool();
    let mut v = Vector3::zeros();
    if let JogMotion::Cartesian { x, y, z } = motion {
        let d = Vector3::new(f64::from(x), f64::from(y), f64::from(z));
        // Mixed: translation in the base frame, rotation in the tool frame.
        v = match frame {
            Some(ReferenceFrame::Tool) => pose.tool_rotation() * d,
            _ => d,
        };
    }
    if let JogMotion::Polar { azimuth, altitude } = motion {
        // As the polar pan turns the tool (see `kortex::polar`).
        v = f64::from(azimuth) * Vector3::z().cross(&tool);
        let across = Vector3::new(tool.y, -tool.x, 0.0);
        if altitude != 0 && across.norm() > f64::from(crate::kortex::polar::MIN_RADIUS) {
            v += f64::from(altitude) * across.normalize().cross(&tool);
        }
    }
    if let JogMotion::Joint { joint, direction } = motion {
        let q = position_deg.map(|d| f64::from(d).to_radians());
        let (joints, _) = gen3::frames(&q);
        let index = usize::from(joint.clamp(1, 7) - 1);
        let f = &joints[index];
        v = f64::from(direction) * axis(f, 2).cross(&(tool - origin(f)));
    }
    let norm = v.norm();
    (norm > 1e-6 && norm.is_finite()).then(|| v / norm)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_reach_is_the_straight_arm_from_the_shoulder() {
        // The Gen3 7-DOF's published reach is 902 mm; the DH table gives the same.
        assert!((reach() - 0.902).abs() < 0.002, "{}", reach());
        assert!((shoulder() - Vector3::new(0.0, 0.0, 0.2848)).norm() < 1e-3);
    }

    #[test]
    fn the_home_pose_ends_at_the_forward_kinematics_tool_point() {
        let pose = arm_pose(&gen3::HOME_DEG.map(|d| d as f32));
        let expected = gen3::tool_position(&gen3::HOME_DEG.map(f64::to_radians));
        assert!((pose.tool() - expected).norm() < 1e-6);
        assert_eq!(pose.points[0], Vector3::zeros());
        // Every point within reach of the shoulder.
        for p in pose.points {
            assert!((p - shoulder()).norm() <= reach() + 0.3, "{p:?}");
        }
        for a in pose.tool_axes {
            assert!((a.norm() - 1.0).abs() < 1e-9);
        }
    }

    #[test]
    fn jog_directions_follow_the_command() {
        let home = gen3::HOME_DEG.map(|d| d as f32);
        let plus_x = JogMotion::Cartesian { x: 1, y: 0, z: 0 };
        let d = jog_direction(plus_x, None, &home).expect("moves");
        assert!((d - Vector3::x()).norm() < 1e-9);
        // At home the tool's X axis is the base's Y axis... whatever it is, the tool frame
        // turns the direction onto the tool's own X axis.
        let pose = arm_pose(&home);
        let d = jog_direction(plus_x, Some(ReferenceFrame::Tool), &home).expect("moves");
        assert!((d - pose.tool_axes[0]).norm() < 1e-9);
        // Azimuth + turns the tool (in front of the base, +X) towards +Y.
        let az = JogMotion::Polar {
            azimuth: 1,
            altitude: 0,
        };
        assert!(jog_direction(az, None, &home).expect("moves").y > 0.9);
        let alt = JogMotion::Polar {
            azimuth: 0,
            altitude: 1,
        };
        assert!(jog_direction(alt, None, &home).expect("moves").z > 0.5);
        // A joint jog moves the tool point the way turning that joint alone does.
        let j2 = JogMotion::Joint {
            joint: 2,
            direction: 1,
        };
        let q = gen3::HOME_DEG.map(f64::to_radians);
        let mut turned = q;
        turned[1] += 1e-6;
        let moved = (gen3::tool_position(&turned) - gen3::tool_position(&q)).normalize();
        let d = jog_direction(j2, None, &home).expect("moves");
        assert!((d - moved).norm() < 1e-4, "{d:?} vs {moved:?}");
        let j7 = JogMotion::Joint {
            joint: 7,
            direction: 1,
        };
        assert_eq!(jog_direction(j7, None, &home), None);
    }
}
