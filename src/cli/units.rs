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

/// A snapshot's `arm` line: current A, voltage V, CPU and ambient temperatures C.
pub fn arm_line([current, voltage, cpu, ambient]: [f32; 4]) -> String {
    let [current, voltage] = [current, voltage].map(|v| fixed(f64::from(v), 3));
    let [cpu, ambient] = [cpu, ambient].map(|v| fixed(f64::from(v), 1));
    format!(
        "arm           current {current} A   voltage {voltage} V   cpu {cpu} C   ambient {ambient} C"
    )
}

/// A snapshot's tool lines: pose (position mm, orientation deg), twist (m/s, deg/s) and wrench
/// (N, N m), each six floats: x, y, z then about x, y, z.
pub fn tool_lines(
    position_mm: [f64; 3],
    orientation_deg: [f32; 3],
    twist: &[f32],
    wrench: &[f32],
) -> [String; 3] {
    let f = |v: f32, decimals: usize| fixed(f64::from(v), decimals);
    let [x, y, z] = position_mm.map(|mm| fixed(mm, 1));
    let [rx, ry, rz] = orientation_deg.map(|deg| f(deg, 2));
    let [vx, vy, vz] = [0, 1, 2].map(|i| linear_speed(f64::from(twist[i])));
    let [wx, wy, wz] = [3, 4, 5].map(|i| f(twist[i], 2));
    let [fx, fy, fz] = [0, 1, 2].map(|i| f(wrench[i], 2));
    let [tx, ty, tz] = [3, 4, 5].map(|i| f(wrench[i], 3));
    [
        format!(
            "tcp pose      x {x} mm   y {y} mm   z {z} mm   theta x {rx}   y {ry}   z {rz} deg"
        ),
        format!("tcp twist     x {vx}   y {vy}   z {vz}   theta x {wx}   y {wy}   z {wz} deg/s"),
        format!(
            "tcp wrench    force x {fx}   y {fy}   z {fz} N   torque x {tx}   y {ty}   z {tz} N m"
        ),
    ]
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
