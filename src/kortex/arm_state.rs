//! What telemetry says about the arm, for the console, its audit and `armjog modbus home`: at
//! rest or not, why an action aborted, whether the arm is in fault, whether its action status
//! names another move than ours. Pure.

use super::gen3::limit_margin;
use super::telemetry::ActionState;
use super::{ActionStatus, CodeName, Coded, Flag, MoveType, RobotState, Telemetry};

/// Below these the arm is at rest.
pub const REST_JOINT_DEG_S: f32 = 0.5;
pub const REST_LINEAR_M_S: f32 = 0.002;
pub const REST_ANGULAR_DEG_S: f32 = 0.5;
/// A joint this close to its limit may be the one an abort stopped at.
const NEAR_LIMIT_DEG: f32 = 3.0;
/// A joint this close to its limit is at it.
const AT_LIMIT_DEG: f32 = 0.5;

/// Whether telemetry shows the arm at rest (NaN counts as moving).
pub fn at_rest(t: &Telemetry) -> bool {
    let v = t.tcp.twist;
    t.joints.iter().all(|j| j.velocity.abs() < REST_JOINT_DEG_S)
        && [v.x, v.y, v.z].iter().all(|c| c.abs() < REST_LINEAR_M_S)
        && [v.theta_x, v.theta_y, v.theta_z]
            .iter()
            .all(|c| c.abs() < REST_ANGULAR_DEG_S)
}

/// Why an action aborted, naming the joint at its limit if one is.
pub fn abort_reason(t: &Telemetry) -> String {
    let nearest = t
        .joints
        .iter()
        .enumerate()
        .filter_map(|(i, j)| limit_margin(i, j.position).map(|m| (i, m)))
        .filter(|(_, m)| *m <= NEAR_LIMIT_DEG)
        .min_by(|a, b| a.1.total_cmp(&b.1));
    // A joint is the cause if it faulted or is at its limit, not merely near it.
    let warned = t.warnings.contains(Flag::JointFault);
    match nearest {
        Some((i, m)) if warned || m <= AT_LIMIT_DEG => format!("aborted, J{} at its limit", i + 1),
        Some((i, _)) => format!("aborted, J{} near its limit", i + 1),
        None if warned => "aborted (joint fault warning)".into(),
        None => "aborted".into(),
    }
}

/// What the arm's fault is, if it is in fault.
pub fn fault_reason(t: &Telemetry) -> Option<String> {
    let state_fault = matches!(t.robot_state, Coded::Known(RobotState::InFault));
    if t.faults.is_empty() && !state_fault {
        return None;
    }
    let names = t.faults.names();
    Some(if names.is_empty() {
        "the arm is in fault".into()
    } else {
        format!("the arm is in fault: {}", names.join(", "))
    })
}

/// Our move, as the action status (holding registers 100-102) names it: its move type and, for a
/// stored action or sequence, its id (a cartesian trajectory or a twist carries none).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OurMove {
    pub move_type: MoveType,
    pub id: Option<u16>,
}

impl OurMove {
    /// What the action status names when it is not our move (another client's), in words: `the arm
    /// runs action 5, not our action 2`; `None` while it names ours or a type the ICD does not
    /// list. The one reading of "not ours"; whether a read may predate our move is the caller's.
    pub fn other_in(&self, status: &ActionState) -> Option<String> {
        let Coded::Known(theirs) = status.move_type else {
            return None;
        };
        let ours = theirs == self.move_type && self.id.is_none_or(|id| id == status.id);
        (!ours).then(|| {
            format!(
                "the arm runs {}, not our {}",
                move_words(theirs, Some(status.id)),
                move_words(self.move_type, self.id)
            )
        })
    }
}

/// A stored action or sequence started under a move of ours the status does not name (a Talos Go
/// To), in words. `before` is what the status named when ours was sent: a move named then is not
/// told from ours; any other started since is another client's.
pub fn stored_started_in(before: &ActionState, status: &ActionState) -> Option<String> {
    let Coded::Known(theirs @ (MoveType::Action | MoveType::Sequence)) = status.move_type else {
        return None;
    };
    if status.status != Coded::Known(ActionStatus::Started) {
        return None;
    }
    if let Coded::Known(move_type) = before.move_type {
        let named_before = OurMove {
            move_type,
            id: Some(before.id),
        };
        named_before.other_in(status)?;
    }
    Some(format!(
        "the arm runs {}",
        move_words(theirs, Some(status.id))
    ))
}

/// `action 5`, `sequence 1`, `cartesian trajectory`, `twist`.
fn move_words(move_type: MoveType, id: Option<u16>) -> String {
    match (move_type, id) {
        (MoveType::Action | MoveType::Sequence, Some(id)) => format!("{} {id}", move_type.key()),
        (other, _) => other.key().replace('_', " "),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn status(move_type: MoveType, id: u16) -> ActionState {
        ActionState {
            status: Coded::Known(ActionStatus::Started),
            id,
            move_type: Coded::Known(move_type),
        }
    }

    #[test]
    fn another_move_is_named_by_its_type_and_a_stored_ones_id() {
        let action_2 = OurMove {
            move_type: MoveType::Action,
            id: Some(2),
        };
        assert_eq!(action_2.other_in(&status(MoveType::Action, 2)), None);
        assert_eq!(
            action_2.other_in(&status(MoveType::Action, 5)).as_deref(),
            Some("the arm runs action 5, not our action 2")
        );
        // A sequence of the same id is another move.
        assert_eq!(
            action_2.other_in(&status(MoveType::Sequence, 2)).as_deref(),
            Some("the arm runs sequence 2, not our action 2")
        );
        assert_eq!(
            action_2.other_in(&status(MoveType::Twist, 0)).as_deref(),
            Some("the arm runs twist, not our action 2")
        );
        let go_to = OurMove {
            move_type: MoveType::CartesianTrajectory,
            id: None,
        };
        // A trajectory carries no id: any id is ours.
        assert_eq!(
            go_to.other_in(&status(MoveType::CartesianTrajectory, 9)),
            None
        );
        assert_eq!(
            go_to.other_in(&status(MoveType::Action, 5)).as_deref(),
            Some("the arm runs action 5, not our cartesian trajectory")
        );
        // A move type the ICD does not list names nothing.
        let unknown = ActionState {
            move_type: Coded::Unknown(9),
            ..status(MoveType::Action, 5)
        };
        assert_eq!(action_2.other_in(&unknown), None);
    }

    #[test]
    fn a_stored_move_started_under_an_unnamed_move_is_named_unless_the_status_named_it_before() {
        let before = ActionState {
            status: Coded::Known(ActionStatus::Completed),
            ..status(MoveType::Action, 2)
        };
        // The operator's Go To: the last move's type and id left, or a trajectory.
        assert_eq!(
            stored_started_in(&before, &status(MoveType::Action, 2)),
            None
        );
        let trajectory = status(MoveType::CartesianTrajectory, 2);
        assert_eq!(stored_started_in(&before, &trajectory), None);
        assert_eq!(
            stored_started_in(&before, &status(MoveType::Action, 5)).as_deref(),
            Some("the arm runs action 5")
        );
        assert_eq!(
            stored_started_in(&before, &status(MoveType::Sequence, 2)).as_deref(),
            Some("the arm runs sequence 2")
        );
        assert_eq!(
            stored_started_in(&trajectory, &status(MoveType::Action, 2)).as_deref(),
            Some("the arm runs action 2")
        );
        // Only a start: a stored move's end, or its abort, is not one.
        let completed = ActionState {
            status: Coded::Known(ActionStatus::Completed),
            ..status(MoveType::Action, 5)
        };
        assert_eq!(stored_started_in(&before, &completed), None);
        // Without a status (Talos hardware telemetry) nothing is named.
        let unknown = ActionState {
            status: Coded::Unknown(u16::MAX),
            id: 0,
            move_type: Coded::Unknown(u16::MAX),
        };
        assert_eq!(stored_started_in(&unknown, &unknown), None);
        assert_eq!(
            stored_started_in(&unknown, &status(MoveType::Action, 5)).as_deref(),
            Some("the arm runs action 5")
        );
    }
}
