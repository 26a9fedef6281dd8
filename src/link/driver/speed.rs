//! The speed in force, percent of the cap, and the fence's share of it: one per driver, shared by
//! both sides.

use std::sync::Arc;
use std::sync::atomic::{AtomicU8, AtomicU16, Ordering};

use crate::link::fence::WHOLE;
use crate::link::speed::INITIAL_SPEED;
#[cfg(test)]
use crate::link::speed::fraction;

/// See the module docs. Clones share the values.
#[derive(Debug, Clone)]
pub struct SpeedInForce(Arc<(AtomicU8, AtomicU16)>);

impl Default for SpeedInForce {
    fn default() -> SpeedInForce {
        SpeedInForce(Arc::new((
            AtomicU8::new(INITIAL_SPEED),
            AtomicU16::new(WHOLE),
        )))
    }
}

impl SpeedInForce {
    /// The technician's speed (or the operator's), percent of the cap.
    pub fn percent(&self) -> u8 {
        self.0.0.load(Ordering::Acquire)
    }

    /// Puts `percent` in force; callers have checked it (1-100) or the operator reported it.
    pub fn set(&self, percent: u8) {
        self.0.0.store(percent, Ordering::Release);
    }

    /// The fence's share of the speed, per mille ([`WHOLE`]: none taken).
    pub fn fence_permille(&self) -> u16 {
        self.0.1.load(Ordering::Acquire)
    }

    /// The fence's share as a fraction, 0 to 1: what every jog's rate is multiplied by.
    pub fn fence_share(&self) -> f32 {
        f32::from(self.fence_permille().min(WHOLE)) / f32::from(WHOLE)
    }

    /// Puts the fence's share in force (at most [`WHOLE`]).
    pub fn set_fence(&self, permille: u16) {
        self.0.1.store(permille.min(WHOLE), Ordering::Release);
    }

    /// `percent` with the fence's share taken, whole percent, at least 1: what a link that has
    /// only a percentage (the Talos operator) is told.
    pub fn fenced(&self, percent: u8) -> u8 {
        let share = u32::from(percent) * u32::from(self.fence_permille().min(WHOLE)) / 1000;
        u8::try_from(share).unwrap_or(percent).max(1).min(percent)
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

    #[test]
    fn the_fence_takes_a_share_without_changing_the_speed_asked_for() {
        let speed = SpeedInForce::default();
        speed.set(50);
        assert_eq!((speed.fence_permille(), speed.fenced(50)), (WHOLE, 50));
        speed.clone().set_fence(550);
        assert_eq!(speed.percent(), 50);
        // 50 % x 0.55 = 27.5 %: 27 % to a link that takes whole percents.
        assert_eq!(speed.fenced(50), 27);
        assert!((speed.fence_share() - 0.55).abs() < 1e-6);
        // Never under 1 %, never over what was asked.
        speed.set_fence(10);
        assert_eq!(speed.fenced(5), 1);
        speed.set_fence(5000);
        assert_eq!((speed.fence_permille(), speed.fenced(80)), (WHOLE, 80));
    }
}
