//! UTC calendar dates and RFC 3339 timestamps from a `SystemTime`, without a date crate.

use std::time::{SystemTime, UNIX_EPOCH};

/// Year, month and day of a count of days since 1970-01-01 (proleptic Gregorian; Howard
/// Hinnant's `civil_from_days`).
fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let month = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let year = yoe + era * 400 + i64::from(month <= 2);
    (year, month, day)
}

/// Milliseconds since the epoch; a clock set before 1970 counts as the epoch.
fn epoch_ms(at: SystemTime) -> i64 {
    at.duration_since(UNIX_EPOCH)
        .map(|d| i64::try_from(d.as_millis()).unwrap_or(i64::MAX))
        .unwrap_or(0)
}

/// `YYYY-MM-DD` in UTC.
pub fn date(at: SystemTime) -> String {
    let (y, m, d) = civil_from_days(epoch_ms(at).div_euclid(86_400_000));
    format!("{y:04}-{m:02}-{d:02}")
}

/// `YYYY-MM-DDTHH:MM:SS.mmmZ`.
pub fn rfc3339_ms(at: SystemTime) -> String {
    let ms = epoch_ms(at);
    let of_day = ms.rem_euclid(86_400_000);
    let (h, min, s, milli) = (
        of_day / 3_600_000,
        of_day / 60_000 % 60,
        of_day / 1000 % 60,
        of_day % 1000,
    );
    format!("{}T{h:02}:{min:02}:{s:02}.{milli:03}Z", date(at))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    fn at(secs: u64, ms: u64) -> SystemTime {
        UNIX_EPOCH + Duration::from_secs(secs) + Duration::from_millis(ms)
    }

    #[test]
    fn known_instants_format_as_rfc3339() {
        assert_eq!(rfc3339_ms(at(0, 0)), "1970-01-01T00:00:00.000Z");
        // `date -u -d @1796077651`: Mon Nov 30 22:27:31 UTC 2026.
        assert_eq!(
            rfc3339_ms(at(1_796_077_651, 853)),
            "2026-11-30T22:27:31.853Z"
        );
        // A leap day, and the last millisecond of a year.
        assert_eq!(rfc3339_ms(at(951_782_400, 0)), "2000-02-29T00:00:00.000Z");
        assert_eq!(
            rfc3339_ms(at(1_704_067_199, 999)),
            "2023-12-31T23:59:59.999Z"
        );
    }

    #[test]
    fn the_date_turns_at_utc_midnight() {
        assert_eq!(date(at(1_796_083_199, 999)), "2026-11-30");
        assert_eq!(date(at(1_796_083_200, 0)), "2026-12-01");
    }

    #[test]
    fn a_clock_before_1970_reads_as_the_epoch() {
        assert_eq!(date(UNIX_EPOCH - Duration::from_secs(10)), "1970-01-01");
    }
}
