//! The speed in force, percent of the cap: one value per driver, shared by the Talos side and
//! the Modbus worker, so a speed set through either bounds the motion both command.

use std::sync::Arc;
use std::sync::atomic::{AtomicU8, Ordering};

/// Percent of the jog speed in force until the technician (or the operator) changes it.
pub const INITIAL_SPEED: u8 = 50;

/// The angular speed of an orientation jog at 100 %, deg/s: the speed in force scales it as it
/// scales the tool speed cap (a turn about the tool point moves the point itself not at all).
/// Never above the arm's configured angular limit (holding registers 218-219) nor the twist's
/// hard limit (100 deg/s).
pub const MAX_ANGULAR_JOG_SPEED: f32 = 30.0;

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

#[cfg(test)]
mod tests {
    use super::*;

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
