//! The speed cap: [`SpeedCap`], made once from `max_jog_speed` (the tool speed at 100 %), says what
//! a percentage of it is for every motion on every link (tool speed, turn rate, a planned move's
//! limits, polar pan and joint jog bounds, the Talos operator's percentage). Nothing else works a
//! cap out.

use crate::kortex::SpeedLimits;
use crate::kortex::commands::MAX_LINEAR_SPEED;
use crate::kortex::gen3::joint_rate_for_tool_speed;

/// Percent of the jog speed in force until the technician (or the operator) changes it.
pub const INITIAL_SPEED: u8 = 50;

/// The tool's turn rate at 100 %, deg/s, scaled like the tool speed (a turn about the tool point
/// does not move it). Bounds orientation jogs and the angular limit of planned moves (holding
/// registers 218-219); never above the arm's configured limit nor the twist's hard limit.
pub const MAX_ANGULAR_JOG_SPEED: f32 = 30.0;

/// Single-joint jog speed at 100 %, deg/s, unless configured otherwise.
pub const JOINT_JOG_SPEED: f32 = 20.0;

/// The Talos operator's speed at its 100 %, m/s (`--operator-full-speed`; the simulator's).
pub const OPERATOR_FULL_SPEED: f64 = 0.25;

/// Whether `percent` (1-100 % of the cap) can be put in force; another leaves the speed as it was.
pub fn is_settable(percent: u8) -> bool {
    (1..=100).contains(&percent)
}

/// `max_jog_speed` at `percent`, in its unit: the one formula of the tool speed cap.
pub fn tool_speed_at(max_jog_speed: f64, percent: u8) -> f64 {
    max_jog_speed * f64::from(percent) / 100.0
}

/// Why a speed cannot be a cap, or an operator's full speed under it.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum SpeedCapError {
    /// Not a tool speed the arm's twist can carry (the words follow the value as typed).
    #[error(
        "must be above 0 and at most {} mm/s (the arm's twist limit)",
        max_tool_speed_mm_s()
    )]
    OutOfRange,
    /// The operator's least speed, 1 % of its full speed, is over the cap.
    #[error("1 % of the operator's full speed is over the cap: its slowest speed would be over it")]
    OperatorTooFast,
}

/// The fastest tool speed a cap or an operator's full speed may be, mm/s: the twist's limit.
fn max_tool_speed_mm_s() -> f64 {
    f64::from(MAX_LINEAR_SPEED) * 1000.0
}

/// Whether `m_s` is a tool speed a cap may be: above 0 and at most the twist's limit.
fn check_tool_speed(m_s: f64) -> Result<f64, SpeedCapError> {
    let in_range = m_s.is_finite() && m_s > 0.0 && m_s <= f64::from(MAX_LINEAR_SPEED);
    in_range.then_some(m_s).ok_or(SpeedCapError::OutOfRange)
}

/// The tool speed cap: `max_jog_speed` m/s at 100 %; percentages of it, 1-100.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpeedCap {
    /// The tool speed at 100 %, m/s: above 0, at most the twist's limit.
    max_jog_speed: f64,
}

impl SpeedCap {
    /// The cap at `max_jog_speed` m/s, above 0 and at most the twist's 0.5 m/s limit.
    pub fn new(max_jog_speed: f64) -> Result<SpeedCap, SpeedCapError> {
        check_tool_speed(max_jog_speed).map(|max_jog_speed| SpeedCap { max_jog_speed })
    }

    /// The cap of a configuration the front ends checked (`cli/values.rs`).
    ///
    /// # Panics
    /// On a value [`SpeedCap::new`] refuses: nothing has connected then, so nothing moves.
    pub fn configured(max_jog_speed: f64) -> SpeedCap {
        match SpeedCap::new(max_jog_speed) {
            Ok(cap) => cap,
            Err(e) => panic!("max_jog_speed {max_jog_speed} m/s: {e}"),
        }
    }

    /// The tool speed at 100 %, mm/s.
    pub fn max_mm_s(&self) -> f64 {
        self.max_jog_speed * 1000.0
    }

    /// The tool speed at `percent`, m/s: the cap every motion keeps.
    pub fn tool_speed(&self, percent: u8) -> f64 {
        tool_speed_at(self.max_jog_speed, percent)
    }

    /// [`Self::tool_speed`] in mm/s, as the technician reads it.
    pub fn tool_speed_mm_s(&self, percent: u8) -> f64 {
        tool_speed_at(self.max_mm_s(), percent)
    }

    /// The speed of a Modbus cartesian twist at `percent`, m/s (diagonals are normalised to it).
    pub fn twist_speed(&self, percent: u8) -> f32 {
        self.tool_speed(percent) as f32
    }

    /// The turn rate at `percent`, deg/s, before the arm's own angular limit.
    pub fn turn_rate(&self, percent: u8) -> f32 {
        MAX_ANGULAR_JOG_SPEED * fraction(percent) as f32
    }

    /// The limits (m/s, deg/s) a move the arm plans itself runs under at `percent`.
    pub fn move_cap(&self, percent: u8) -> SpeedLimits {
        SpeedLimits {
            linear: self.tool_speed(percent) as f32,
            angular: self.turn_rate(percent),
        }
    }

    /// A Modbus polar pan's tool-point bound at `percent`, m/s: `configured`, never above the cap.
    pub fn polar_linear_bound(&self, configured: f32, percent: u8) -> f32 {
        configured.min(self.max_jog_speed as f32) * fraction(percent) as f32
    }

    /// A joint jog's rate, deg/s, keeping the tool under the cap for `horizon` s.
    pub fn joint_rate(
        &self,
        joint_jog_speed: f32,
        positions: &[f32; 7],
        joint: u8,
        percent: u8,
        horizon: f64,
    ) -> f32 {
        let fraction = fraction(percent);
        let by_tool =
            joint_rate_for_tool_speed(positions, joint, self.max_jog_speed * fraction, horizon);
        (f64::from(joint_jog_speed) * fraction).min(by_tool) as f32
    }

    /// This cap on an operator whose 100 % is `operator_full_speed` m/s (its 1 % within the cap).
    pub fn with_operator(self, operator_full_speed: f64) -> Result<OperatorScale, SpeedCapError> {
        let operator_full_speed = check_tool_speed(operator_full_speed)?;
        let scale = OperatorScale {
            cap: self,
            operator_full_speed,
        };
        scale
            .allows_one_percent()
            .then_some(scale)
            .ok_or(SpeedCapError::OperatorTooFast)
    }
}

/// `percent` as a fraction of the cap, 0.01-1 for a speed in force.
pub fn fraction(percent: u8) -> f64 {
    f64::from(percent) / 100.0
}

/// The cap on a Talos operator, whose Set/Get Speed percentage is of its own 100 %, not of the
/// console's cap; only the Talos side converts. Rounding stays under the cap:
/// - to the operator, rounded down, at least 1 % (which [`SpeedCap::with_operator`] keeps under the
///   cap);
/// - from the operator, rounded up; above 100 % of the cap, `None`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OperatorScale {
    cap: SpeedCap,
    /// The operator's tool speed at its own 100 %, m/s.
    operator_full_speed: f64,
}

/// Slack for the floating-point products of whole percentages (20 × 0.2 must be 4, not 3).
const ROUNDING_SLACK: f64 = 1e-9;

impl OperatorScale {
    /// Both speeds in the same unit, unchecked: [`SpeedCap::with_operator`] checks them.
    #[cfg(test)]
    fn new(max_jog_speed: f64, operator_full_speed: f64) -> OperatorScale {
        OperatorScale {
            cap: SpeedCap { max_jog_speed },
            operator_full_speed,
        }
    }

    /// The console's cap.
    pub fn cap(&self) -> SpeedCap {
        self.cap
    }

    /// The console's cap over the operator's full speed.
    fn ratio(&self) -> f64 {
        self.cap.max_jog_speed / self.operator_full_speed
    }

    /// Whether the operator's least speed, 1 %, is within the cap.
    fn allows_one_percent(&self) -> bool {
        self.ratio() >= 0.01 - ROUNDING_SLACK
    }

    /// The operator's tool speed at its own `percent`, mm/s.
    pub fn operator_mm_s(&self, percent: u8) -> f64 {
        tool_speed_at(self.operator_full_speed * 1000.0, percent)
    }

    /// The operator percentage for `percent` of the console's cap: rounded down, 1-100. A
    /// percentage outside 1-100 goes on as it is, for the operator to refuse (it is
    /// OUT_OF_RANGE there too): none is put in force that the operator did not accept.
    pub fn to_operator(&self, percent: u8) -> u8 {
        if !is_settable(percent) {
            return percent;
        }
        let exact = f64::from(percent) * self.ratio();
        (exact + ROUNDING_SLACK).floor().clamp(1.0, 100.0) as u8
    }

    /// The percentage of the console's cap the operator's `percent` gives, rounded up; `None`
    /// when that is over the cap (above 100 %).
    pub fn from_operator(&self, percent: u8) -> Option<u8> {
        let exact = f64::from(percent) / self.ratio();
        let of_cap = (exact - ROUNDING_SLACK).ceil().max(1.0);
        (of_cap <= 100.0).then_some(of_cap as u8)
    }
}

#[cfg(test)]
mod tests;
