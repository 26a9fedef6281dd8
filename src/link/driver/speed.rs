//! The speed in force, percent of the cap: one value per driver, shared by the Talos side and
//! the Modbus worker, so a speed set through either bounds the motion both command. And the
//! conversion between it and a Talos operator's own percentage ([`OperatorScale`]).

use std::sync::Arc;
use std::sync::atomic::{AtomicU8, Ordering};

use crate::kortex::SpeedLimits;

/// Percent of the jog speed in force until the technician (or the operator) changes it.
pub const INITIAL_SPEED: u8 = 50;

/// The tool's turn rate at 100 %, deg/s: the speed in force scales it as it scales the tool
/// speed cap (a turn about the tool point moves the point itself not at all). One rate for
/// every motion that turns the tool: an orientation jog, and a move the arm plans itself (a
/// go-to, a step, home, a stored action), whose angular limit (holding registers 218-219) is
/// lowered to it. Never above the arm's configured angular limit nor the twist's hard limit
/// (100 deg/s).
pub const MAX_ANGULAR_JOG_SPEED: f32 = 30.0;

/// Single-joint jog speed at 100 %, deg/s, unless configured otherwise.
pub const JOINT_JOG_SPEED: f32 = 20.0;

/// The Talos operator's tool speed at its own 100 %, m/s, unless the technician says otherwise
/// (`--operator-full-speed`): the simulator's default.
pub const OPERATOR_FULL_SPEED: f64 = 0.25;

/// Whether `percent` can be put in force: 1-100 % of the cap. Another is refused (by the Modbus
/// worker, or by the operator it is passed on to) and leaves the speed in force as it was.
pub fn is_settable(percent: u8) -> bool {
    (1..=100).contains(&percent)
}

/// The tool speed cap at `percent` of `max_jog_speed`, in its unit: the one cap every motion
/// keeps (what a cartesian jog moves at, what a move is capped at).
pub fn tool_speed_at(max_jog_speed: f64, percent: u8) -> f64 {
    max_jog_speed * f64::from(percent) / 100.0
}

/// The tool's turn rate at `percent`, deg/s: [`MAX_ANGULAR_JOG_SPEED`] scaled by it, before
/// the arm's own configured angular limit (which only the link's telemetry knows). What an
/// orientation jog turns at, and what a capped move may turn at ([`move_cap_at`]).
pub fn turn_rate_at(percent: u8) -> f32 {
    MAX_ANGULAR_JOG_SPEED * (f64::from(percent) / 100.0) as f32
}

/// The limits a move the arm plans itself (a go-to, a step, home, a stored action) runs under
/// at `percent`: the tool speed cap ([`tool_speed_at`], `max_jog_speed` in m/s) and the turn
/// rate ([`turn_rate_at`]), as the arm's speed limits (m/s, deg/s) for the move.
pub fn move_cap_at(max_jog_speed: f64, percent: u8) -> SpeedLimits {
    SpeedLimits {
        linear: tool_speed_at(max_jog_speed, percent) as f32,
        angular: turn_rate_at(percent),
    }
}

/// See the module docs. Clones share the value.
#[derive(Debug, Clone)]
pub struct SpeedInForce(Arc<AtomicU8>);

impl Default for SpeedInForce {
    fn default() -> SpeedInForce {
        SpeedInForce(Arc::new(AtomicU8::new(INITIAL_SPEED)))
    }
}

impl SpeedInForce {
    pub fn percent(&self) -> u8 {
        self.0.load(Ordering::Acquire)
    }

    /// The speed in force as a fraction of the cap, 0.01-1.
    pub fn fraction(&self) -> f64 {
        f64::from(self.percent()) / 100.0
    }

    /// Puts `percent` in force; callers have checked it (1-100) or the operator reported it.
    pub fn set(&self, percent: u8) {
        self.0.store(percent, Ordering::Release);
    }
}

/// A Talos operator's Set Speed / Get Speed percentage is of its own 100 % speed, not of the
/// console's cap: this converts between the two, so the speed in force stays a percentage of
/// the console's cap on both link sides and only the Talos side converts.
///
/// Edge cases, all on the side of the cap:
/// - To the operator, the percentage rounds down and is at least 1 %: it never gives more than
///   the console's percentage of the cap, except that 1 % of the operator's speed is the least
///   it can be asked for, which [`OperatorScale::allows_one_percent`] keeps under the cap (the
///   console refuses to start otherwise).
/// - From the operator, the percentage of the cap rounds up (the speed shown is never less than
///   the speed it runs at); above 100 % the operator runs over the cap, and `None` says so.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OperatorScale {
    /// The console's cap over the operator's full speed.
    ratio: f64,
}

/// Slack for the floating-point products of whole percentages (20 × 0.2 must be 4, not 3).
const ROUNDING_SLACK: f64 = 1e-9;

impl OperatorScale {
    /// Both speeds in the same unit; callers have checked both are finite and above 0.
    pub fn new(max_jog_speed: f64, operator_full_speed: f64) -> OperatorScale {
        OperatorScale {
            ratio: max_jog_speed / operator_full_speed,
        }
    }

    /// Whether the operator's least speed, 1 %, is within the cap.
    pub fn allows_one_percent(&self) -> bool {
        self.ratio >= 0.01 - ROUNDING_SLACK
    }

    /// The operator percentage for `percent` of the console's cap: rounded down, 1-100. A
    /// percentage outside 1-100 goes on as it is, for the operator to refuse (it is
    /// OUT_OF_RANGE there too): none is put in force that the operator did not accept.
    pub fn to_operator(&self, percent: u8) -> u8 {
        if !(1..=100).contains(&percent) {
            return percent;
        }
        let exact = f64::from(percent) * self.ratio;
        (exact + ROUNDING_SLACK).floor().clamp(1.0, 100.0) as u8
    }

    /// The percentage of the console's cap the operator's `percent` gives, rounded up; `None`
    /// when that is over the cap (above 100 %).
    pub fn from_operator(&self, percent: u8) -> Option<u8> {
        let exact = f64::from(percent) / self.ratio;
        let of_cap = (exact - ROUNDING_SLACK).ceil().max(1.0);
        (of_cap <= 100.0).then_some(of_cap as u8)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_percentage_scales_the_cap_and_the_turn_rate_and_only_1_to_100_is_settable() {
        assert!((tool_speed_at(0.25, 20) - 0.05).abs() < 1e-12);
        assert!((tool_speed_at(250.0, 100) - 250.0).abs() < 1e-12);
        assert!((turn_rate_at(20) - 6.0).abs() < 1e-5);
        assert!((turn_rate_at(100) - 30.0).abs() < 1e-5);
        assert!(!is_settable(0) && is_settable(1) && is_settable(100) && !is_settable(101));
    }

    #[test]
    fn a_move_is_capped_at_the_tool_speed_and_the_turn_rate_of_its_percentage() {
        // 50 % of 250 mm/s: 125 mm/s, and half of the 30 deg/s turn rate.
        let cap = move_cap_at(0.25, 50);
        assert!((cap.linear - 0.125).abs() < 1e-7, "{cap:?}");
        assert!((cap.angular - 15.0).abs() < 1e-5, "{cap:?}");
        // The same rate an orientation jog turns at, at every percentage.
        for percent in 1..=100 {
            assert_eq!(move_cap_at(0.05, percent).angular, turn_rate_at(percent));
        }
        let cap = move_cap_at(0.05, 10);
        assert!((cap.linear - 0.005).abs() < 1e-7 && (cap.angular - 3.0).abs() < 1e-5);
    }

    #[test]
    fn the_same_full_speed_is_one_to_one() {
        let scale = OperatorScale::new(0.25, 0.25);
        for percent in 1..=100 {
            assert_eq!(scale.to_operator(percent), percent);
            assert_eq!(scale.from_operator(percent), Some(percent));
        }
    }

    #[test]
    fn a_faster_operator_gets_a_smaller_percentage_rounded_down() {
        // The case: a 50 mm/s cap on a 250 mm/s operator.
        let scale = OperatorScale::new(0.05, 0.25);
        assert_eq!(scale.to_operator(100), 20);
        assert_eq!(scale.to_operator(50), 10);
        assert_eq!(scale.to_operator(24), 4, "4.8 % rounds down");
        assert_eq!(scale.to_operator(1), 1, "0.2 % is asked as the least, 1 %");
        assert_eq!(
            scale.to_operator(0),
            0,
            "out of range: the operator refuses it"
        );
        assert_eq!(scale.to_operator(101), 101);
        // A cap that does not divide evenly: 50 of 300 mm/s.
        let scale = OperatorScale::new(50.0, 300.0);
        assert_eq!(scale.to_operator(100), 16, "16.7 % rounds down");
        assert_eq!(scale.to_operator(75), 12);
    }

    #[test]
    fn no_console_percentage_asks_for_more_than_its_share_of_the_cap() {
        for (cap, full) in [(50.0, 250.0), (50.0, 300.0), (50.0, 500.0), (7.0, 500.0)] {
            let scale = OperatorScale::new(cap, full);
            for percent in 1..=100u8 {
                let operator_mm_s = f64::from(scale.to_operator(percent)) * full / 100.0;
                let wanted = cap * f64::from(percent) / 100.0;
                // Over the console's share only at the operator's floor of 1 %; never over the cap.
                assert!(
                    operator_mm_s <= wanted + 1e-9 || scale.to_operator(percent) == 1,
                    "{cap}/{full} at {percent} %: {operator_mm_s} mm/s"
                );
                assert!(operator_mm_s <= cap + 1e-9);
            }
        }
    }

    #[test]
    fn an_operator_speed_reads_back_rounded_up_and_over_the_cap_as_none() {
        let scale = OperatorScale::new(0.05, 0.25);
        assert_eq!(scale.from_operator(20), Some(100));
        assert_eq!(scale.from_operator(10), Some(50));
        assert_eq!(scale.from_operator(21), None, "105 % of the cap");
        assert_eq!(scale.from_operator(100), None);
        let scale = OperatorScale::new(50.0, 300.0);
        assert_eq!(scale.from_operator(12), Some(72));
        assert_eq!(scale.from_operator(13), Some(78), "78.000 exactly, not 79");
        assert_eq!(scale.from_operator(17), None, "102 % of the cap");
        // A console cap above the operator's full speed: its 100 % is well under the cap.
        let scale = OperatorScale::new(0.25, 0.1);
        assert_eq!(scale.to_operator(100), 100);
        assert_eq!(scale.from_operator(100), Some(40));
    }

    #[test]
    fn one_percent_of_the_operator_must_fit_under_the_cap() {
        assert!(OperatorScale::new(5.0, 500.0).allows_one_percent());
        assert!(!OperatorScale::new(4.9, 500.0).allows_one_percent());
        assert!(OperatorScale::new(0.0025, 0.25).allows_one_percent());
    }

    #[test]
    fn clones_share_one_speed() {
        let speed = SpeedInForce::default();
        let other = speed.clone();
        assert_eq!(other.percent(), INITIAL_SPEED);
        speed.set(20);
        assert_eq!(other.percent(), 20);
        assert!((other.fraction() - 0.2).abs() < 1e-12);
    }
}
