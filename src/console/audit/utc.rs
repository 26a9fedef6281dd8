//! UTC dates and RFC 3339 stamps: audit file names and lines, `armjog status --watch`.

use std::time::{SystemTime, UNIX_EPOCH};

use time::OffsetDateTime;
use time::format_description::BorrowedFormatItem;
use time::macros::format_description;

const DATE: &[BorrowedFormatItem<'_>] = format_description!("[year]-[month]-[day]");
const RFC3339_MS: &[BorrowedFormatItem<'_>] =
    format_description!("[year]-[month]-[day]T[hour]:[minute]:[second].[subsecond digits:3]Z");

/// `at` in UTC; before 1970 or past 9999 counts as the epoch.
fn utc(at: SystemTime) -> OffsetDateTime {
    let since = at.duration_since(UNIX_EPOCH).unwrap_or_default();
    OffsetDateTime::from_unix_timestamp_nanos(since.as_nanos().try_into().unwrap_or(i128::MAX))
        .unwrap_or(OffsetDateTime::UNIX_EPOCH)
}

fn format(at: SystemTime, format: &[BorrowedFormatItem<'_>]) -> String {
    utc(at)
        .format(format)
        // Only a component missing from the value fails, and a UTC date and time has them all.
        .expect("a UTC date and time formats")
}

/// `YYYY-MM-DD` in UTC.
pub fn date(at: SystemTime) -> String {
    format(at, DATE)
}

/// `YYYY-MM-DDTHH:MM:SS.mmmZ`: RFC 3339 in UTC with milliseconds (truncated, not rounded).
pub fn rfc3339_ms(at: SystemTime) -> String {
    format(at, RFC3339_MS)
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
    fn timestamps_are_rfc3339_utc_with_milliseconds() {
        // The `--watch` lines' cases (formerly `cli::units`).
        assert_eq!(rfc3339_ms(UNIX_EPOCH), "1970-01-01T00:00:00.000Z");
        let at = UNIX_EPOCH + Duration::from_millis(1_796_078_665_123);
        assert_eq!(rfc3339_ms(at), "2026-11-30T22:44:25.123Z");
        // A leap day.
        let leap = UNIX_EPOCH + Duration::from_secs(951_782_400);
        assert_eq!(rfc3339_ms(leap), "2000-02-29T00:00:00.000Z");
        // Milliseconds are cut, never rounded up into the next second.
        assert_eq!(
            rfc3339_ms(UNIX_EPOCH + Duration::from_nanos(1_999_999_999)),
            "1970-01-01T00:00:01.999Z"
        );
    }

    #[test]
    fn a_clock_before_1970_reads_as_the_epoch() {
        assert_eq!(date(UNIX_EPOCH - Duration::from_secs(10)), "1970-01-01");
    }
}
