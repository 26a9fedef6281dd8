//! The simulated arm: joint state, the running motion, a fixed-step integrator and deterministic
//! efforts and temperatures. Protocol-neutral ([`SimMotion`] in, [`ArmSnapshot`] out); time moves
//! only through [`Arm::step`], so tests drive it exactly.

use crate::kortex::Flag;
pub use crate::kortex::{ActionStatus, ReferenceFrame, RobotState};

use super::kinematics::{self, HOME_DEG, JOINTS, Joints, Pose};

/// The geometric Jacobian (rows vx, vy, vz, wx, wy, wz; a column per joint).
type Jacobian = nalgebra::SMatrix<f64, 6, JOINTS>;

/// Integrator step, seconds (1 kHz).
pub const STEP: f64 = 0.001;

/// Kinova twist hard limits.
pub const MAX_TWIST_LINEAR: f64 = 0.5;
pub const MAX_TWIST_ANGULAR_DEG: f64 = 100.0;

/// The operator's continuous-START watchdog, seconds.
pub const WATCHDOG: f64 = 0.5;

/// A discrete move has arrived this close (m, rad): well inside a 0.1 mm step, so steps are exact.
pub const ARRIVED_POSITION: f64 = 5e-6;
pub const ARRIVED_ROTATION: f64 = 0.01 * std::f64::consts::PI / 180.0;

#[derive(Debug, Clone)]
pub struct Arm {
    time: f64,
    q: Joints,
    qd: Joints,
    motion: SimMotion,
    /// A motion waiting for its start time (Talos Delay), with its tool speed cap.
    delayed: Option<(f64, SimMotion, Option<f64>)>,
    /// The running motion's tool speed cap, m/s, if set (the operator's); the linear limit on top.
    tcp_cap: Option<f64>,
    /// When set, the current motion stops at this time unless refreshed (Talos continuous).
    watchdog: Option<f64>,
    /// How long a continuous motion runs without a refresh, seconds ([`WATCHDOG`]).
    watchdog_period: f64,
    faults: u32,
    warnings: u32,
    action_status: ActionStatus,
    action_id: u16,
    move_type: u16,
    speed_limit_linear: f64,
    speed_limit_angular: f64,
    temperature: Joints,
    torque: Joints,
    current: Joints,
    /// Kinematics cache of the effort model: at rest the 1 kHz integrator skips them.
    reach_at: Option<(Joints, f64)>,
    /// Where a running twist or polar pan should have the tool (see [`tracking`]).
    reference: Option<tracking::Reference>,
    /// The moves of a running stored sequence still to come, in order.
    queued: std::collections::VecDeque<SimMotion>,
}

impl Default for Arm {
    fn default() -> Self {
        Arm::at(kinematics::to_radians(&HOME_DEG))
    }
}

impl Arm {
    /// An arm at rest at joint angles `q` (radians).
    pub fn at(q: Joints) -> Arm {
        let mut arm = Arm {
            time: 0.0,
            q,
            qd: [0.0; JOINTS],
            motion: SimMotion::Idle,
            delayed: None,
            tcp_cap: None,
            watchdog: None,
            watchdog_period: WATCHDOG,
            faults: 0,
            warnings: 0,
            action_status: ActionStatus::Completed,
            action_id: 0,
            move_type: 0,
            speed_limit_linear: MAX_TWIST_LINEAR,
            speed_limit_angular: MAX_TWIST_ANGULAR_DEG.to_radians(),
            temperature: [30.0; JOINTS],
            torque: [0.0; JOINTS],
            current: [0.0; JOINTS],
            reach_at: None,
            reference: None,
            queued: std::collections::VecDeque::new(),
        };
        arm.update_effort();
        arm
    }

    pub fn time(&self) -> f64 {
        self.time
    }

    pub fn joints(&self) -> Joints {
        self.q
    }

    pub fn pose(&self) -> Pose {
        kinematics::forward(&self.q)
    }

    pub fn motion(&self) -> &SimMotion {
        &self.motion
    }

    pub fn is_moving(&self) -> bool {
        !self.motion.is_idle() || self.qd.iter().any(|v| v.abs() > 1e-9)
    }

    pub fn in_fault(&self) -> bool {
        self.faults != 0
    }

    /// Starts `motion` after `delay` s; `watchdog`: stops unless refreshed within [`WATCHDOG`].
    pub fn command(
        &mut self,
        motion: SimMotion,
        delay: f64,
        watchdog: bool,
    ) -> Result<(), Refusal> {
        self.command_capped(motion, delay, watchdog, None)
    }

    /// [`Arm::command`] with the tool point at or under `max_tcp_speed` m/s (and the configured
    /// linear limit): joint velocities scale down together, so the path stays the same.
    pub fn command_capped(
        &mut self,
        motion: SimMotion,
        delay: f64,
        watchdog: bool,
        max_tcp_speed: Option<f64>,
    ) -> Result<(), Refusal> {
        if !motion.is_finite()
            || !delay.is_finite()
            || max_tcp_speed.is_some_and(|cap| !cap.is_finite())
        {
            return Err(Refusal::NotFinite);
        }
        if self.in_fault() && !motion.is_idle() {
            return Err(Refusal::InFault);
        }
        self.check_reachable(&motion)?;
        // Any new motion replaces a running sequence.
        self.queued.clear();
        self.watchdog = watchdog.then_some(self.time + self.watchdog_period);
        self.move_type = match motion {
            SimMotion::ToPose { .. } => 2,
            SimMotion::Twist { .. } | SimMotion::Polar { .. } => 3,
            _ => self.move_type,
        };
        if delay > 0.0 {
            self.delayed = Some((self.time + delay, motion, max_tcp_speed));
        } else {
            self.delayed = None;
            self.tcp_cap = max_tcp_speed;
            self.start(motion);
        }
        Ok(())
    }

    /// Changes the tool speed cap of the running motion (a repeated START at a new speed).
    pub fn set_tcp_cap(&mut self, max_tcp_speed: Option<f64>) {
        self.tcp_cap = max_tcp_speed;
    }

    /// Refreshes the watchdog of a continuous motion (a repeated START).
    pub fn refresh_watchdog(&mut self) {
        if self.watchdog.is_some() {
            self.watchdog = Some(self.time + self.watchdog_period);
        }
    }

    /// When the continuous motion stops unrefreshed (arm time, s); a change means it was re-armed.
    pub fn watchdog_deadline(&self) -> Option<f64> {
        self.watchdog
    }

    /// The continuous motions' watchdog period (tests lengthen it); bad values ignored.
    pub fn set_watchdog_period(&mut self, seconds: f64) {
        if seconds.is_finite() && seconds > 0.0 {
            self.watchdog_period = seconds;
        }
    }

    fn start(&mut self, motion: SimMotion) {
        if !motion.is_idle() {
            self.action_status = ActionStatus::Started;
        }
        self.motion = motion;
    }

    /// Stops any motion at once (the integrator has no deceleration ramp).
    pub fn stop(&mut self) {
        if !self.motion.is_idle() {
            self.action_status = ActionStatus::Aborted;
        }
        self.motion = SimMotion::Idle;
        self.delayed = None;
        self.watchdog = None;
        self.qd = [0.0; JOINTS];
        self.reference = None;
        self.queued.clear();
    }

    /// Coil 0: stop and go into fault, as Kinova's quick stop does.
    pub fn quick_stop(&mut self) {
        self.stop();
        self.faults |= Flag::EmergencyStop.bit();
    }

    /// Coil 2 / clear-faults hardware operation.
    pub fn fault_reset(&mut self) {
        self.faults = 0;
    }

    /// Fault injection: raise one fault bit (stops motion).
    pub fn raise_fault(&mut self, bit: u32) {
        self.stop();
        self.faults |= 1 << (bit & 31);
    }

    /// A start the arm could not carry out.
    pub fn mark_aborted(&mut self) {
        self.action_status = ActionStatus::Aborted;
    }

    /// Names the stored action (move type 0) or sequence (1) the status registers report.
    pub fn set_action(&mut self, id: u16, move_type: u16) {
        self.action_id = id;
        self.move_type = move_type;
    }

    /// Starts stored action or sequence `id` as its `steps`, one after the other; the status names
    /// `id` and `move_type` until the last arrives. Every step is checked before the first moves.
    pub fn command_stored(
        &mut self,
        id: u16,
        move_type: u16,
        steps: Vec<SimMotion>,
    ) -> Result<(), Refusal> {
        self.set_action(id, move_type);
        let mut steps = std::collections::VecDeque::from(steps);
        for step in &steps {
            if !step.is_finite() {
                return Err(Refusal::NotFinite);
            }
            self.check_reachable(step)?;
        }
        let Some(first) = steps.pop_front() else {
            return Err(Refusal::OutOfRange);
        };
        self.command(first, 0.0, false)?;
        self.queued = steps;
        Ok(())
    }

    /// Desired speed limits (m/s, deg/s), clamped to the hard limits.
    pub fn set_speed_limits(&mut self, linear: f64, angular_deg: f64) -> Result<(), Refusal> {
        if !(linear.is_finite() && angular_deg.is_finite()) || linear <= 0.0 || angular_deg <= 0.0 {
            return Err(Refusal::OutOfRange);
        }
        self.speed_limit_linear = linear.min(MAX_TWIST_LINEAR);
        self.speed_limit_angular = angular_deg.min(MAX_TWIST_ANGULAR_DEG).to_radians();
        Ok(())
    }

    pub fn speed_limits(&self) -> (f64, f64) {
        (
            self.speed_limit_linear,
            self.speed_limit_angular.to_degrees(),
        )
    }

    fn check_reachable(&self, motion: &SimMotion) -> Result<(), Refusal> {
        match motion {
            SimMotion::ToPose { target, .. } => kinematics::inverse(&self.q, target)
                .map(|_| ())
                .map_err(|e| match e {
                    kinematics::IkError::JointLimit { joint } => Refusal::JointLimit(joint),
                    kinematics::IkError::Unreachable { .. } => Refusal::Unreachable,
                }),
            SimMotion::ToJoints { target, .. } => {
                match (0..JOINTS).find(|&i| !kinematics::within_limit(i, target[i])) {
                    Some(i) => Err(Refusal::JointLimit(i + 1)),
                    None => Ok(()),
                }
            }
            SimMotion::JointVelocity { joint, .. } if *joint >= JOINTS => Err(Refusal::OutOfRange),
            _ => Ok(()),
        }
    }

    /// Advances the simulation by `seconds` in fixed steps.
    pub fn advance(&mut self, seconds: f64) {
        let steps = (seconds / STEP).round() as u64;
        for _ in 0..steps {
            self.step();
        }
    }

    /// One integrator step of [`STEP`] seconds.
    pub fn step(&mut self) {
        self.time += STEP;
        if let Some((at, _, _)) = &self.delayed
            && self.time >= *at
            && let Some((_, motion, cap)) = self.delayed.take()
        {
            self.tcp_cap = cap;
            self.start(motion);
        }
        if self.watchdog.is_some_and(|deadline| self.time >= deadline) {
            tracing::info!(
                "sim: continuous motion stopped by the {} ms watchdog",
                (self.watchdog_period * 1000.0).round()
            );
            self.stop();
        }
        // The tool's horizontal reach for the effort model, from this step's kinematics.
        let mut reach = None;
        self.qd = if self.motion.is_idle() {
            [0.0; JOINTS]
        } else {
            let (pose, j) = kinematics::pose_and_jacobian(&self.q);
            reach = Some(horizontal_reach(&pose));
            let desired = self.desired_velocity(&pose, &j);
            let (qd, twist) = self.limit_tcp_speed(limit_joint_speeds(desired), &j);
            if let Some(reference) = &mut self.reference {
                reference.advance(&pose, twist);
            }
            qd
        };
        let next: Joints = std::array::from_fn(|i| self.q[i] + self.qd[i] * STEP);
        if let Some(joint) = (0..JOINTS).find(|&i| !kinematics::within_limit(i, next[i])) {
            // A real arm stops at a joint limit; the warning says which kind of stop it was.
            tracing::info!("sim: joint {} reached its limit", joint + 1);
            self.stop();
            self.warnings |= Flag::JointFault.bit();
        } else {
            if self.qd.iter().any(|v| *v != 0.0) {
                self.warnings &= !(Flag::JointFault.bit());
            }
            self.q = next;
            // Reach from this step's kinematics: a step old, cheaper.
            if let Some(reach) = reach {
                self.reach_at = Some((self.q, reach));
            }
        }
        self.update_effort();
    }
}

/// How far joint `i` turns from `from` to `to` (rad): a continuous joint the short way, a limited
/// joint straight across its range, never through its limit.
pub fn joint_delta(i: usize, from: f64, to: f64) -> f64 {
    match kinematics::JOINT_LIMITS_DEG[i] {
        Some(_) => kinematics::wrap_pi(to) - kinematics::wrap_pi(from),
        None => kinematics::wrap_pi(to - from),
    }
}

mod effort;
mod motion;
mod polar;
mod snapshot;
mod tracking;
mod velocity;

pub use motion::{Refusal, SimMotion};
pub use polar::{polar_target, polar_twist};
pub use snapshot::ArmSnapshot;

use effort::horizontal_reach;
use velocity::limit_joint_speeds;

#[cfg(test)]
mod tests;
