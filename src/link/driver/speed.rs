//! The speed in force, percent of the cap: one per driver, shared by both sides.

use std::sync::Arc;
use std::sync::atomic::{AtomicU8, Ordering};

use crate::link::speed::INITIAL_SPEED;
#[cfg(test)]
use crate::link::speed::fraction;

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
        assert!((fraction(other.percent()) - 0.2).abs() < 1e-12);
    }
}
