//! Numbers as the one-shot commands print them: fixed decimals without `-0.00`, small linear
//! speeds in mm/s, and the RFC 3339 UTC timestamps of `--watch` lines.

use std::time::{SystemTime, UNIX_EPOCH};

/// `value` with `decimals` decimals; a value that rounds to zero prints without a sign.
pub fn fixed(value: f64, decimals: usize) -> String {
    let text = format!("{value:.decimals$}");
    match text.strip_prefix('-') {
        Some(unsigned) if unsigned.bytes().all(|b| b == b'0' || b == b'.') => unsigned.to_string(),
        _ => text,
    }
}

/// A linear speed: below 1 m/s in mm/s with one decimal (`12.5 mm/s`), else in m/s.
pub fn linear_speed(m_s: f64) -> String {
    if m_s.abs() < 1.0 {
        format!("{} mm/s", fixed(m_s * 1000.0, 1))
    } else {
        format!("{} m/s", fixed(m_s, 3))
    }
}

/// `at` as RFC 3339 in UTC with milliseconds: `2026-11-30T22:51:05.123Z`. Times before 1970
/// print as the epoch.
pub fn rfc3339_utc(at: SystemTime) -> String {
    let since = at.duration_since(UNIX_EPOCH).unwrap_or_default();
    let secs = since.as_secs();
    let (days, of_day) = (secs / 86_400, secs % 86_400);
    let (year, month, day) = civil_from_days(days);
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}.{:03}Z",
        of_day / 3600,
        of_day / 60 % 60,
        of_day % 60,
        since.subsec_millis()
    )
}

/// The proleptic Gregorian date `days` after 1970-01-01 (Howard Hinnant's `civil_from_days`).
fn civil_from_days(days: u64) -> (u64, u64, u64) {
    let z = days + 719_468;
    let era = z / 146_097;
    let doe = z % 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + u64::from(month <= 2);
    (year, month, day)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

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

    #[test]
    fn timestamps_are_rfc3339_utc_with_milliseconds() {
        assert_eq!(rfc3339_utc(UNIX_EPOCH), "1970-01-01T00:00:00.000Z");
        let at = UNIX_EPOCH + Duration::from_millis(1_796_078_665_123);
        assert_eq!(rfc3339_utc(at), "2026-11-30T22:44:25.123Z");
        // A leap day.
        let leap = UNIX_EPOCH + Duration::from_secs(951_782_400);
        assert_eq!(rfc3339_utc(leap), "2000-02-29T00:00:00.000Z");
    }
}
