//! Numbers as one-shot commands print them: fixed decimals, no `-0.00`, small speeds in mm/s.

/// `value` with `decimals` decimals; a value that rounds to zero prints without a sign (the
/// panels' rule, one home).
pub use crate::console::ui::numbers::fixed;

/// A linear speed: below 1 m/s in mm/s with one decimal (`12.5 mm/s`), else in m/s.
pub fn linear_speed(m_s: f64) -> String {
    if m_s.abs() < 1.0 {
        format!("{} mm/s", fixed(m_s * 1000.0, 1))
    } else {
        format!("{} m/s", fixed(m_s, 3))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_never_has_a_sign() {
        assert_eq!(fixed(-0.0, 2), "0.00");
        assert_eq!(fixed(-0.0004, 3), "0.000");
        assert_eq!(fixed(-0.004, 2), "0.00");
        assert_eq!(fixed(-0.006, 2), "-0.01");
        assert_eq!(fixed(-4.905, 2), "-4.91");
        assert_eq!(fixed(12.0, 0), "12");
    }

    #[test]
    fn speeds_below_one_metre_a_second_are_in_millimetres() {
        assert_eq!(linear_speed(0.5), "500.0 mm/s");
        assert_eq!(linear_speed(0.0125), "12.5 mm/s");
        assert_eq!(linear_speed(-0.0), "0.0 mm/s");
        assert_eq!(linear_speed(-0.25), "-250.0 mm/s");
        assert_eq!(linear_speed(1.5), "1.500 m/s");
    }
}
