//! The arm's efforts: torques, currents and temperatures from a simple, deterministic model.

use super::Arm;
use super::STEP;
use super::kinematics::{MAX_JOINT_TORQUE, Pose};

impl Arm {
    /// Torques from gravity and viscous friction, currents via the torque constant, first-order
    /// heat.
    pub(super) fn update_effort(&mut self) {
        let reach = self.reach();
        for (i, max_torque) in MAX_JOINT_TORQUE.iter().enumerate() {
            let lever = match i {
                1 => 18.0 * reach,
                3 => 9.0 * reach,
                5 => 1.5 * reach,
                _ => 0.3 * (self.q[i]).sin(),
            };
            let friction = 0.8 * self.qd[i];
            let torque = (lever + friction).clamp(-max_torque, *max_torque);
            let k_t = if i < 4 { 11.0 } else { 7.6 };
            let current = 0.15 + torque.abs() / k_t;
            self.torque[i] = torque;
            self.current[i] = current;
            let target = 30.0 + 12.0 * current * current;
            self.temperature[i] += (target - self.temperature[i]) * STEP / 120.0;
        }
    }

    /// The tool's horizontal distance from the base axis, from the cache while the joints stay.
    fn reach(&mut self) -> f64 {
        if let Some((q, reach)) = self.reach_at
            && q == self.q
        {
            return reach;
        }
        let reach = horizontal_reach(&self.pose());
        self.reach_at = Some((self.q, reach));
        reach
    }
}

/// The tool's horizontal distance from the base axis, m (the shoulder's and elbow's lever).
pub(super) fn horizontal_reach(pose: &Pose) -> f64 {
    pose.position.x.hypot(pose.position.y)
}
