//! The simulator's stored actions and sequences: the Gen3's four factory actions and one sequence
//! (a real arm's ids are in its Web App). Each action is a joint-space move at [`ACTION_FRACTION`]
//! of the joints' top speed, under the configured linear limit. Pure.

use super::arm_model::SimMotion;
use super::kinematics::{self, HOME_DEG};
use crate::kortex::{CodeName, MoveType};

/// The Home action's id (armjog's default `--action-id`).
pub const HOME_ACTION_ID: u16 = 2;

/// The share of each joint's top speed a stored action runs at.
pub const ACTION_FRACTION: f64 = 0.3;

/// A stored action: an id, its Web App name and the joint angles it goes to (degrees).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StoredAction {
    pub id: u16,
    pub name: &'static str,
    pub joints_deg: [f64; 7],
}

/// Retract: Kinova's own pose (the `retract` group state in Kinovarobotics/ros_kortex
/// `gen3_move_it_config/config/7dof/gen3.srdf`: 0, -0.35, 3.14, -2.54, 0, -0.87, 1.57 rad), in
/// degrees rounded to the half degree.
pub const RETRACT_DEG: [f64; 7] = [0.0, -20.0, 180.0, -145.5, 0.0, -50.0, 90.0];

/// Packaging: Kinova publishes no angles; a plausible pose folded tighter than Retract, every
/// limited joint at least 2 degrees inside its limit (J4 147.8, J6 120.3).
pub const PACKAGING_DEG: [f64; 7] = [0.0, -30.0, 180.0, -140.0, 0.0, -110.0, 90.0];

/// Zero: every joint at 0 (the arm straight up).
pub const ZERO_DEG: [f64; 7] = [0.0; 7];

/// The factory actions, by id.
pub const ACTIONS: [StoredAction; 4] = {
    const fn stored(id: u16, name: &'static str, joints_deg: [f64; 7]) -> StoredAction {
        StoredAction {
            id,
            name,
            joints_deg,
        }
    }
    [
        stored(HOME_ACTION_ID, "Home", HOME_DEG),
        stored(3, "Retract", RETRACT_DEG),
        stored(4, "Packaging", PACKAGING_DEG),
        stored(5, "Zero", ZERO_DEG),
    ]
};

/// A stored sequence: the actions it runs, in order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StoredSequence {
    pub id: u16,
    pub name: &'static str,
    pub actions: &'static [u16],
}

/// The sequences, by id.
pub const SEQUENCES: [StoredSequence; 1] = [StoredSequence {
    id: 1,
    name: "Retract, then Home",
    actions: &[3, HOME_ACTION_ID],
}];

pub fn action(id: u16) -> Option<&'static StoredAction> {
    ACTIONS.iter().find(|a| a.id == id)
}

pub fn sequence(id: u16) -> Option<&'static StoredSequence> {
    SEQUENCES.iter().find(|s| s.id == id)
}

fn to_motion(action: &StoredAction) -> SimMotion {
    SimMotion::ToJoints {
        target: kinematics::to_radians(&action.joints_deg),
        fraction: ACTION_FRACTION,
    }
}

/// The moves that start `id` as `move_type` (0 action, 1 sequence); `None` if none.
pub fn steps(id: u16, move_type: u16) -> Option<Vec<SimMotion>> {
    match MoveType::from_code(move_type)? {
        MoveType::Action => action(id).map(|a| vec![to_motion(a)]),
        MoveType::Sequence => sequence(id).map(|s| {
            s.actions
                .iter()
                .filter_map(|step| action(*step))
                .map(to_motion)
                .collect()
        }),
        _ => None,
    }
}

#[cfg(test)]
mod tests;
