//! Whether a go-to's end is ours: the action status names our move and the arm is at rest where
//! sent, within [`ARRIVED_MM`] and [`ARRIVED_DEG`]. Anything else is another client's move.

use std::time::Instant;

use super::{ACTION_GRACE, ActionKind, TrackedAction};
use crate::console::positions::BookEntry;
use crate::kortex::arm_state::stored_started_in;
use crate::kortex::{ActionStatus, Coded, Pose, Telemetry};

/// Over a Gen3's 0.1 mm repeatability, under the distance between two saved positions.
pub const ARRIVED_MM: f32 = 5.0;
/// The same for the tool's orientation, deg.
pub const ARRIVED_DEG: f32 = 2.0;

/// Where a go-to must end.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GoToTarget {
    /// The pose sent; its orientation is compared only when `turn` is set.
    pose: Pose,
    turn: bool,
}

impl GoToTarget {
    /// A move to `pose` (over Modbus): point and orientation.
    pub fn pose(pose: Pose) -> GoToTarget {
        GoToTarget { pose, turn: true }
    }

    /// A Go To's target: the book's point for the name, when absolute (an anchored position moves
    /// with its parent). The orientation is the operator's.
    pub fn book(entry: &BookEntry) -> Option<GoToTarget> {
        if entry.anchor {
            return None;
        }
        let [x, y, z] = entry.cartesian?.map(|tenths| tenths as f32 / 10_000.0);
        Some(GoToTarget {
            pose: Pose {
                x,
                y,
                z,
                ..Pose::default()
            },
            turn: false,
        })
    }

    /// How the arm at `at` misses the target, or `None` there (a non-number pose is not there).
    pub fn missed_by(&self, at: &Pose) -> Option<String> {
        let mm = at.distance_to(&self.pose) * 1000.0;
        let deg = if self.turn {
            at.turn_to(&self.pose)
        } else {
            0.0
        };
        if !(mm.is_finite() && deg.is_finite()) {
            return Some("the arm's reported pose is not a number".into());
        }
        if mm > ARRIVED_MM {
            return Some(format!(
                "the arm is at rest {mm:.0} mm from where it was sent"
            ));
        }
        (deg > ARRIVED_DEG)
            .then(|| format!("the arm is at rest turned {deg:.0} deg from where it was sent"))
    }
}

/// The arm runs another move than ours ([`crate::kortex::OurMove::other_in`]), read after ours was
/// seen started or [`ACTION_GRACE`] after sending. A Talos Go To (unnamed in the status) is
/// another's once a stored action starts that was not running when sent ([`stored_started_in`]);
/// not Talos Home, which may be the arm's own.
pub(super) fn foreign_move(
    action: &mut TrackedAction,
    accepted: Instant,
    t: &Telemetry,
    now: Instant,
) -> Option<String> {
    let Some(ours) = action.move_type else {
        if !matches!(action.kind, ActionKind::GoTo(_)) {
            return None;
        }
        let before = *action.status_before.get_or_insert(t.action);
        return stored_started_in(&before, &t.action);
    };
    let Some(other) = ours.other_in(&t.action) else {
        action.seen_ours |= t.action.move_type == Coded::Known(ours.move_type)
            && t.action.status == Coded::Known(ActionStatus::Started);
        return None;
    };
    (action.seen_ours || now >= accepted + ACTION_GRACE).then_some(other)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bench() -> Pose {
        Pose::from_array([0.4, 0.1, 0.3, 90.0, 0.0, 90.0])
    }

    #[test]
    fn a_target_is_missed_past_the_tolerance_and_by_a_pose_that_is_not_a_number() {
        let target = GoToTarget::pose(bench());
        assert_eq!(target.missed_by(&bench()), None);
        let near = Pose {
            x: 0.404,
            theta_z: 91.5,
            ..bench()
        };
        assert_eq!(target.missed_by(&near), None);
        let far = Pose { x: 0.41, ..bench() };
        assert_eq!(
            target.missed_by(&far).as_deref(),
            Some("the arm is at rest 10 mm from where it was sent")
        );
        let turned = Pose {
            theta_z: 93.0,
            ..bench()
        };
        assert!(target.missed_by(&turned).is_some());
        let nan = Pose {
            y: f32::NAN,
            ..bench()
        };
        assert_eq!(
            target.missed_by(&nan).as_deref(),
            Some("the arm's reported pose is not a number")
        );
    }

    #[test]
    fn a_book_target_is_the_point_alone_and_none_for_an_anchored_position() {
        let mut entry = BookEntry {
            cartesian: Some([4000, 1000, 3000]),
            orientation: Some([0.0, 0.0, 0.0]),
            ..BookEntry::default()
        };
        let target = GoToTarget::book(&entry).expect("a target");
        // The operator's orientation is not the book's to judge.
        assert_eq!(target.missed_by(&bench()), None);
        entry.anchor = true;
        assert_eq!(GoToTarget::book(&entry), None);
        entry.anchor = false;
        entry.cartesian = None;
        assert_eq!(GoToTarget::book(&entry), None);
    }
}
