//! Ages as the screen shows them.

use std::time::Duration;

/// Ages below this are shown in tenths of a second, above it in whole seconds.
pub(super) const AGE_TENTHS_UNTIL: Duration = Duration::from_secs(10);

/// An age for the screen: `1.8 s`, or `42 s` once past ten seconds.
pub fn age_text(age: Duration) -> String {
    if age < AGE_TENTHS_UNTIL {
        format!("{:.1} s", age.as_secs_f64())
    } else {
        format!("{} s", age.as_secs())
    }
}
