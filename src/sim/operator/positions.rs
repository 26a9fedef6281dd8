//! Named positions: save, anchor, delete (children freeze), resolve, go to.

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

use super::{MAX_JOG_ANGULAR_DEG, MAX_JOINT_FRACTION, Operator};
use crate::sim::arm_model::{Arm, SimMotion};
use crate::sim::kinematics::{Joints, Pose};
use crate::talos::ReturnCode;

/// Anchors deeper than this are refused (and cycles are impossible by construction).
const MAX_ANCHOR_DEPTH: usize = 32;

#[derive(Debug, Clone, PartialEq)]
pub struct SavedPosition {
    /// Absolute pose, or the pose relative to `parent` when `anchor` is set.
    pub pose: Pose,
    /// Joint angles when saved from the arm unanchored: going there is a joint move, no IK.
    pub joints: Option<Joints>,
    pub anchor: bool,
    pub parent: Option<String>,
}

impl SavedPosition {
    /// At `pose`, moving with nothing; `parent` kept only as a reference.
    pub(super) fn fixed(pose: Pose, parent: Option<String>) -> SavedPosition {
        SavedPosition {
            pose,
            joints: None,
            anchor: false,
            parent,
        }
    }
}

fn iso(pose: &Pose) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::from(pose.position),
        UnitQuaternion::from_rotation_matrix(&pose.rotation),
    )
}

fn pose_of(iso: &Isometry3<f64>) -> Pose {
    Pose {
        position: iso.translation.vector,
        rotation: iso.rotation.to_rotation_matrix(),
    }
}

impl Operator {
    /// A position at `absolute`, anchored to `parent` (held relative to its pose now).
    pub(super) fn anchored(
        &self,
        parent: String,
        absolute: &Pose,
    ) -> Result<SavedPosition, ReturnCode> {
        let parent_pose = self.absolute(&parent, 0)?;
        Ok(SavedPosition {
            pose: pose_of(&(iso(&parent_pose).inverse() * iso(absolute))),
            joints: None,
            anchor: true,
            parent: Some(parent),
        })
    }

    pub(super) fn save(
        &mut self,
        arm: &Arm,
        name: String,
        anchor: bool,
        parent: String,
    ) -> Result<(), ReturnCode> {
        let here = arm.pose();
        let parent = (!parent.is_empty()).then_some(parent);
        let anchored_to = match (&parent, anchor) {
            (Some(p), true) => Some(p.clone()),
            _ => None,
        };
        if let Some(p) = &parent
            && (!self.positions.contains_key(p) || self.depends_on(p, &name))
        {
            return Err(ReturnCode::INVALID_PARENT);
        }
        let position = match anchored_to {
            Some(p) => self.anchored(p, &here)?,
            None => SavedPosition {
                pose: here,
                joints: Some(arm.joints()),
                anchor: false,
                parent,
            },
        };
        self.positions.insert(name, position);
        Ok(())
    }

    /// Whether `name`'s anchor chain passes through `ancestor` (or is it).
    fn depends_on(&self, name: &str, ancestor: &str) -> bool {
        let mut current = Some(name.to_string());
        for _ in 0..=MAX_ANCHOR_DEPTH {
            let Some(n) = current else { return false };
            if n == ancestor {
                return true;
            }
            current = self
                .positions
                .get(&n)
                .filter(|p| p.anchor)
                .and_then(|p| p.parent.clone());
        }
        true
    }

    pub(super) fn delete(&mut self, name: &str) -> Result<(), ReturnCode> {
        if !self.positions.contains_key(name) {
            return Err(ReturnCode::UNKNOWN_POSITION);
        }
        // Freeze anchored children where they are now.
        let children: Vec<String> = self
            .positions
            .iter()
            .filter(|(_, p)| p.anchor && p.parent.as_deref() == Some(name))
            .map(|(n, _)| n.clone())
            .collect();
        for child in children {
            let pose = self.absolute(&child, 0)?;
            if let Some(p) = self.positions.get_mut(&child) {
                *p = SavedPosition::fixed(pose, None);
            }
        }
        self.positions.remove(name);
        Ok(())
    }

    /// The absolute pose of a named position, following anchors.
    pub(super) fn absolute(&self, name: &str, depth: usize) -> Result<Pose, ReturnCode> {
        let position = self
            .positions
            .get(name)
            .ok_or(ReturnCode::UNKNOWN_POSITION)?;
        match (&position.parent, position.anchor) {
            (Some(parent), true) => {
                if depth >= MAX_ANCHOR_DEPTH {
                    return Err(ReturnCode::INVALID_PARENT);
                }
                let parent_pose = self.absolute(parent, depth + 1)?;
                Ok(pose_of(&(iso(&parent_pose) * iso(&position.pose))))
            }
            _ => Ok(position.pose),
        }
    }

    pub(super) fn go_to(&self, name: &str) -> Result<SimMotion, ReturnCode> {
        let position = self
            .positions
            .get(name)
            .ok_or(ReturnCode::UNKNOWN_POSITION)?;
        if let (Some(joints), false) = (position.joints, position.anchor) {
            return Ok(SimMotion::ToJoints {
                target: joints,
                fraction: self.fraction() * MAX_JOINT_FRACTION,
            });
        }
        Ok(SimMotion::ToPose {
            target: self.absolute(name, 0)?,
            linear_speed: self.max_jog_linear * self.fraction(),
            angular_speed: MAX_JOG_ANGULAR_DEG.to_radians() * self.fraction(),
        })
    }

    /// Set Polar / Set Cartesian: the position's absolute place becomes `xyz`, its orientation kept
    /// (a new one takes the tool's). An anchored position stays anchored, its offset recomputed.
    pub(super) fn set_absolute_position(
        &mut self,
        arm: &Arm,
        name: String,
        xyz: Vector3<f64>,
    ) -> Result<(), ReturnCode> {
        let existing = self.positions.get(&name).cloned();
        let rotation = match &existing {
            Some(_) => self.absolute(&name, 0)?.rotation,
            None => arm.pose().rotation,
        };
        let absolute = Pose {
            position: xyz,
            rotation,
        };
        let position = match existing {
            Some(SavedPosition {
                anchor: true,
                parent: Some(parent),
                ..
            }) => self.anchored(parent, &absolute)?,
            other => SavedPosition::fixed(absolute, other.and_then(|p| p.parent)),
        };
        self.positions.insert(name, position);
        Ok(())
    }
}
