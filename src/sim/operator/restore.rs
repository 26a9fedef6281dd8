//! Positions remembered from earlier runs, put back into a fresh operator before it serves, so none
//! reads "unknown to operator". Plain numbers in, so the simulator needs nothing of the console.

use std::collections::BTreeMap;

use super::{Operator, SavedPosition};
use crate::sim::arm_model::Arm;
use crate::sim::kinematics::{self, JOINTS, Joints, Pose};
use crate::talos::PositionName;
use crate::talos::name::NameError;
use crate::text;

/// Kept joint angles must put the tool this close to the place (m), else taken at another time.
const JOINTS_AGREE_WITHIN: f64 = 0.005;

/// A named position from an earlier run, as remembered.
#[derive(Debug, Clone, PartialEq)]
pub struct RememberedPosition {
    pub name: String,
    /// Absolute tool position in the base frame, metres.
    pub position_m: [f64; 3],
    /// θx, θy, θz in degrees (extrinsic XYZ); `None`: the arm's orientation at start.
    pub orientation_deg: Option<[f64; 3]>,
    /// J1-J7 in degrees as reported (0-360), when the pose was saved from the arm.
    pub joints_deg: Option<[f64; JOINTS]>,
    pub parent: Option<String>,
    pub anchor: bool,
}

impl Operator {
    /// Saves each remembered position, parents first; one that cannot be taken is skipped with a
    /// warning, a child of an unknown parent dropped. Returns how many were restored.
    pub fn restore(&mut self, arm: &Arm, remembered: Vec<RememberedPosition>) -> usize {
        let mut waiting: BTreeMap<String, RememberedPosition> = BTreeMap::new();
        for position in remembered {
            match usable(&position) {
                Ok(()) => {
                    waiting.insert(position.name.clone(), position);
                }
                // A name from a file: escaped and capped, one log line whatever it holds.
                Err(why) => tracing::warn!(
                    "position '{}' not restored: {why}",
                    text::logged(&position.name)
                ),
            }
        }
        let mut restored = 0;
        while !waiting.is_empty() {
            let ready: Vec<String> = waiting
                .values()
                .filter(|p| {
                    p.parent
                        .as_ref()
                        .is_none_or(|parent| !waiting.contains_key(parent))
                })
                .map(|p| p.name.clone())
                .collect();
            // A cycle of parents: break it by taking the rest without their parents.
            let cycle = ready.is_empty();
            let names = if cycle {
                waiting.keys().cloned().collect()
            } else {
                ready
            };
            for name in names {
                let Some(mut position) = waiting.remove(&name) else {
                    continue;
                };
                if cycle {
                    tracing::warn!(
                        "position '{}': its parents form a cycle: restored alone",
                        text::logged(&name)
                    );
                    position.parent = None;
                }
                self.restore_one(arm, position);
                restored += 1;
            }
        }
        restored
    }

    fn restore_one(&mut self, arm: &Arm, remembered: RememberedPosition) {
        let absolute = Pose::from_position_euler_deg(
            remembered.position_m,
            remembered
                .orientation_deg
                .unwrap_or_else(|| arm.pose().euler_deg()),
        );
        let parent = remembered
            .parent
            .filter(|p| self.positions.contains_key(p) && *p != remembered.name);
        let saved = match (&parent, remembered.anchor) {
            (Some(p), true) => self
                .anchored(p.clone(), &absolute)
                .unwrap_or_else(|_| SavedPosition::fixed(absolute, None)),
            _ => SavedPosition {
                pose: absolute,
                joints: remembered
                    .joints_deg
                    .and_then(|deg| joints_near(arm.joints(), deg, &absolute)),
                anchor: false,
                parent,
            },
        };
        self.positions.insert(remembered.name, saved);
    }
}

/// Why a remembered position cannot be restored.
#[derive(Debug, thiserror::Error)]
enum Unusable {
    #[error("name {0}")]
    Name(#[from] NameError),
    #[error("a coordinate is not a finite number")]
    NotFinite,
}

fn usable(position: &RememberedPosition) -> Result<(), Unusable> {
    PositionName::new(position.name.as_str())?;
    let finite = position.position_m.iter().all(|v| v.is_finite())
        && position
            .orientation_deg
            .is_none_or(|o| o.iter().all(|v| v.is_finite()));
    finite.then_some(()).ok_or(Unusable::NotFinite)
}

/// The reported angles (0-360) as angles reachable from `from`, each the turn nearest the joint (a
/// continuous joint never spins round). `None` past a limit or off the tool's `at`.
fn joints_near(from: Joints, reported_deg: [f64; JOINTS], at: &Pose) -> Option<Joints> {
    if !reported_deg.iter().all(|v| v.is_finite()) {
        return None;
    }
    let target: Joints = std::array::from_fn(|i| {
        let wanted = reported_deg[i].to_radians();
        from[i] + kinematics::wrap_pi(wanted - from[i])
    });
    let within = (0..JOINTS).all(|i| kinematics::within_limit(i, target[i]));
    let agrees =
        (kinematics::forward(&target).position - at.position).norm() <= JOINTS_AGREE_WITHIN;
    (within && agrees).then_some(target)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::kinematics::{HOME_DEG, reported_deg, to_radians};
    use crate::talos::{Reply, Request, ReturnCode};

    fn remembered(name: &str, position_m: [f64; 3]) -> RememberedPosition {
        RememberedPosition {
            name: name.into(),
            position_m,
            orientation_deg: Some([90.0, 0.0, 90.0]),
            joints_deg: None,
            parent: None,
            anchor: false,
        }
    }

    #[test]
    fn remembered_positions_are_known_with_their_coordinates_and_parents_first() {
        let mut arm = Arm::default();
        let mut operator = Operator::default();
        let mut pick = remembered("pick", [0.5, 0.1, 0.3]);
        pick.parent = Some("table".into());
        pick.anchor = true;
        let mut bad = remembered("bad", [f64::NAN, 0.0, 0.0]);
        bad.parent = None;
        let count = operator.restore(&arm, vec![pick, remembered("table", [0.6, 0.0, 0.1]), bad]);
        assert_eq!(count, 2);
        let reply = operator.handle(
            &mut arm,
            Request::GetCartesianPosition {
                name: "pick".into(),
            },
        );
        assert_eq!(
            reply,
            Reply::GetCartesianPosition {
                return_code: ReturnCode::OK,
                x: 5000,
                y: 1000,
                z: 3000
            }
        );
        let pick = &operator.positions()["pick"];
        assert!(pick.anchor, "anchored to its parent");
        assert!(!operator.positions().contains_key("bad"));
    }

    #[test]
    fn joint_angles_are_kept_on_the_nearest_turn_and_only_if_they_agree() {
        let arm = Arm::default();
        let home = to_radians(&HOME_DEG);
        let pose = kinematics::forward(&home);
        let p = pose.position;
        let mut at_home = remembered("home", [p.x, p.y, p.z]);
        // J1 at -0.5 deg reads 359.5: restored as -0.5, not a turn away.
        let mut q = home;
        q[0] = (-0.5f64).to_radians();
        let reported = reported_deg(&q);
        let p = kinematics::forward(&q).position;
        at_home.position_m = [p.x, p.y, p.z];
        at_home.joints_deg = Some(reported);
        let mut elsewhere = remembered("elsewhere", [0.3, 0.3, 0.3]);
        elsewhere.joints_deg = Some(reported);
        let mut operator = Operator::default();
        operator.restore(&arm, vec![at_home, elsewhere]);
        let joints = operator.positions()["home"].joints.expect("joints kept");
        for i in 0..JOINTS {
            assert!(
                (joints[i] - q[i]).abs() < 1e-6,
                "J{} {joints:?} vs {q:?}",
                i + 1
            );
        }
        assert_eq!(
            operator.positions()["elsewhere"].joints,
            None,
            "angles that do not reach the place are dropped"
        );
    }
}
