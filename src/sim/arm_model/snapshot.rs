//! What the servers read of the arm: one snapshot of everything, at one instant.

use nalgebra::Vector3;

use super::{ActionStatus, Arm, RobotState, SimMotion};
use crate::sim::kinematics::{self, Joints};

/// Everything the servers report, at one instant.
#[derive(Debug, Clone, PartialEq)]
pub struct ArmSnapshot {
    pub time: f64,
    pub robot_state: RobotState,
    pub faults: u32,
    pub warnings: u32,
    /// Degrees as Kinova reports them (0-360), deg/s, N·m, A, °C.
    pub joint_position: Joints,
    pub joint_velocity: Joints,
    pub joint_torque: Joints,
    pub joint_current: Joints,
    pub joint_temperature: Joints,
    /// Metres and degrees (extrinsic XYZ).
    pub tcp_position: [f64; 3],
    pub tcp_orientation: [f64; 3],
    /// m/s and deg/s in the base frame.
    pub tcp_linear_velocity: [f64; 3],
    pub tcp_angular_velocity: [f64; 3],
    /// N and N·m.
    pub tcp_force: [f64; 3],
    pub tcp_torque: [f64; 3],
    pub arm_current: f64,
    pub arm_voltage: f64,
    pub cpu_temperature: f64,
    pub ambient_temperature: f64,
    pub action_status: ActionStatus,
    pub action_id: u16,
    pub move_type: u16,
    pub speed_limit_linear: f64,
    pub speed_limit_angular_deg: f64,
    pub moving: bool,
}

impl Arm {
    pub fn snapshot(&self) -> ArmSnapshot {
        let pose = self.pose();
        let twist = kinematics::jacobian(&self.q) * nalgebra::SVector::<f64, 7>::from(self.qd);
        let total_current: f64 = self.current.iter().sum();
        let gravity = Vector3::new(0.0, 0.0, -0.5 * 9.81);
        // The tool's weight as the wrist sensor sees it, in the tool frame.
        let force = pose.rotation.inverse() * gravity;
        ArmSnapshot {
            time: self.time,
            robot_state: if self.in_fault() {
                RobotState::InFault
            } else if self.motion.is_idle() {
                RobotState::Ready
            } else if matches!(self.motion, SimMotion::ToJoints { .. }) {
                RobotState::ControlledBySequence
            } else {
                RobotState::ControlledManually
            },
            faults: self.faults,
            warnings: self.warnings,
            joint_position: kinematics::reported_deg(&self.q),
            joint_velocity: self.qd.map(f64::to_degrees),
            joint_torque: self.torque,
            joint_current: self.current,
            joint_temperature: self.temperature,
            tcp_position: pose.position.into(),
            tcp_orientation: pose.euler_deg(),
            tcp_linear_velocity: [twist[0], twist[1], twist[2]],
            tcp_angular_velocity: [
                twist[3].to_degrees(),
                twist[4].to_degrees(),
                twist[5].to_degrees(),
            ],
            tcp_force: force.into(),
            tcp_torque: [0.0, 0.0, 0.0],
            arm_current: 0.4 + 0.35 * total_current,
            arm_voltage: 24.0 - 0.05 * total_current,
            cpu_temperature: 45.0 + 0.5 * total_current,
            ambient_temperature: 25.0,
            action_status: self.action_status,
            action_id: self.action_id,
            move_type: self.move_type,
            speed_limit_linear: self.speed_limit_linear,
            speed_limit_angular_deg: self.speed_limit_angular.to_degrees(),
            moving: self.is_moving(),
        }
    }
}
