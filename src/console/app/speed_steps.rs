//! The speed keys' steps, fine where a technician creeps up on a part, coarse for travel.

/// The speeds the speed keys walk, percent.
pub const SPEED_STEPS: [u8; 7] = [1, 5, 10, 25, 50, 75, 100];

/// The next step up or down from `current` (percent), staying at either end.
pub fn next_speed(current: u8, up: bool) -> u8 {
    let first = SPEED_STEPS[0];
    let last = SPEED_STEPS[SPEED_STEPS.len() - 1];
    if up {
        SPEED_STEPS
            .into_iter()
            .find(|&s| s > current)
            .unwrap_or(last)
    } else {
        SPEED_STEPS
            .into_iter()
            .rev()
            .find(|&s| s < current)
            .unwrap_or(first)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn up_walks_every_step_to_100_and_stays() {
        let mut speed = 1;
        let mut walked = vec![speed];
        for _ in 0..8 {
            speed = next_speed(speed, true);
            walked.push(speed);
        }
        assert_eq!(walked, [1, 5, 10, 25, 50, 75, 100, 100, 100]);
    }

    #[test]
    fn down_walks_every_step_to_1_and_stays() {
        let mut speed = 100;
        let mut walked = vec![speed];
        for _ in 0..8 {
            speed = next_speed(speed, false);
            walked.push(speed);
        }
        assert_eq!(walked, [100, 75, 50, 25, 10, 5, 1, 1, 1]);
    }

    #[test]
    fn a_speed_between_steps_goes_to_the_next_step_in_the_pressed_direction() {
        assert_eq!(next_speed(42, true), 50);
        assert_eq!(next_speed(42, false), 25);
        assert_eq!(next_speed(3, false), 1);
        assert_eq!(next_speed(99, true), 100);
        assert_eq!(next_speed(0, true), 1, "below the range: the first step");
        assert_eq!(next_speed(0, false), 1, "never below 1 %");
        assert_eq!(
            next_speed(200, false),
            100,
            "above the range: the last step"
        );
    }
}
