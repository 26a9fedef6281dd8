//! Numbers as a technician reads them, and text cut to a width without cutting a number.
//!
//! - No `-0.00`: a value that rounds to zero shows without a sign.
//! - Joint angles read in (−180, 180]: a continuous joint just below zero reads −0.34, not
//!   359.66 (the Gen3 reports 0 to 360).
//! - Text too wide for its place is cut at a word boundary and ends in `…`; a word with a digit
//!   in it (a number, an address, a port) is dropped whole, never shown in part.

use ratatui::text::Span;

/// The ellipsis that ends elided text (one column wide).
pub const ELLIPSIS: char = '…';

/// How a value that is not known shows: one out of physical range or not a number (the
/// decision is `kortex::sanity`'s), never as a number.
pub const NOT_KNOWN: &str = "?";

/// [`fixed`] of a known value, [`NOT_KNOWN`] for none or for one that is not finite.
pub fn fixed_or_unknown<V: Into<f64>>(value: Option<V>, decimals: usize) -> String {
    match value.map(Into::into) {
        Some(v) if v.is_finite() => fixed(v, decimals),
        _ => NOT_KNOWN.to_string(),
    }
}

/// `value` with `decimals` decimals, without the sign of a value that rounds to zero.
pub fn fixed(value: impl Into<f64>, decimals: usize) -> String {
    let text = format!("{:.decimals$}", value.into());
    match text.strip_prefix('-') {
        Some(magnitude) if magnitude.bytes().all(|b| b == b'0' || b == b'.') => {
            magnitude.to_string()
        }
        _ => text,
    }
}

/// The width of `text` in terminal columns.
pub fn width(text: &str) -> usize {
    Span::raw(text).width()
}

/// The columns taken by the first `n` characters of `text`, for every `n` (0 to its length).
fn prefix_widths(chars: &[char]) -> Vec<usize> {
    let mut widths = Vec::with_capacity(chars.len() + 1);
    let mut total = 0;
    widths.push(0);
    let mut buf = [0; 4];
    for c in chars {
        total += width(c.encode_utf8(&mut buf));
        widths.push(total);
    }
    widths
}

/// `text` cut to at most `max` columns: whole when it fits; otherwise the words that fit,
/// then `…`. A first word without a digit that alone is too wide is cut inside (a name reads
/// fine cut); one with a digit is left out whole.
pub fn elide(text: &str, max: usize) -> String {
    if width(text) <= max {
        return text.to_string();
    }
    if max == 0 {
        return String::new();
    }
    let room = max - 1;
    let chars: Vec<char> = text.chars().collect();
    let widths = prefix_widths(&chars);
    // The most characters that fit in `room` columns (fewer than all: the text is too wide).
    let fitting = widths.iter().rposition(|w| *w <= room).unwrap_or(0);
    // The last word boundary (a space) within them.
    let boundary = (1..=fitting)
        .rev()
        .find(|&end| chars[end] == ' ' || chars[end - 1] == ' ');
    let kept: String = match boundary {
        Some(end) => chars[..end]
            .iter()
            .collect::<String>()
            .trim_end()
            .to_string(),
        None => {
            let first_word: String = chars.iter().take_while(|c| **c != ' ').collect();
            if first_word.chars().any(|c| c.is_ascii_digit()) {
                String::new()
            } else {
                chars[..fitting].iter().collect()
            }
        }
    };
    format!("{kept}{ELLIPSIS}")
}

/// The first of `candidates` (longest first) that fits `max` columns whole; else the last one
/// elided.
pub fn first_fitting(candidates: &[String], max: usize) -> String {
    match candidates.iter().find(|c| width(c) <= max) {
        Some(fits) => fits.clone(),
        None => elide(candidates.last().map_or("", String::as_str), max),
    }
}

/// A name cut to at most `max` columns, anywhere, ending in `…` when cut (a name is not a
/// number: `pos-12…` still reads as a cut name).
pub fn elide_name(name: &str, max: usize) -> String {
    if width(name) <= max {
        return name.to_string();
    }
    if max == 0 {
        return String::new();
    }
    let chars: Vec<char> = name.chars().collect();
    let widths = prefix_widths(&chars);
    let fitting = widths.iter().rposition(|w| *w < max).unwrap_or(0);
    let kept: String = chars[..fitting].iter().collect();
    format!("{kept}{ELLIPSIS}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_value_that_rounds_to_zero_has_no_sign() {
        assert_eq!(fixed(-0.001_f32, 2), "0.00");
        assert_eq!(fixed(-0.0_f64, 1), "0.0");
        assert_eq!(fixed(-0.004_f64, 2), "0.00");
        assert_eq!(fixed(-0.4_f64, 0), "0");
        assert_eq!(fixed(-0.005_f64, 2), "-0.01");
        assert_eq!(fixed(-12.5_f32, 2), "-12.50");
        assert_eq!(fixed(0.0_f32, 2), "0.00");
        assert_eq!(fixed(1234.56_f64, 1), "1234.6");
        assert_eq!(fixed(-1234.56_f64, 1), "-1234.6");
    }

    #[test]
    fn angles_wrap_into_minus_180_exclusive_to_180_inclusive() {
        use crate::kortex::gen3::signed_deg as signed_angle;
        assert!((signed_angle(359.66) - -0.34).abs() < 1e-3);
        assert_eq!(signed_angle(180.0), 180.0);
        assert_eq!(signed_angle(-180.0), 180.0);
        assert_eq!(signed_angle(0.0), 0.0);
        assert_eq!(signed_angle(360.0), 0.0);
        assert_eq!(signed_angle(230.0), -130.0);
        assert_eq!(signed_angle(-190.0), 170.0);
        assert_eq!(signed_angle(540.0), 180.0);
        assert_eq!(fixed(signed_angle(359.999), 2), "0.00");
    }

    #[test]
    fn text_that_fits_stays_whole() {
        assert_eq!(elide("talos 127.0.0.1:44718", 21), "talos 127.0.0.1:44718");
        assert_eq!(elide("", 0), "");
    }

    #[test]
    fn elided_text_never_ends_in_part_of_a_number() {
        // The port would be cut: the whole address goes.
        assert_eq!(elide("talos 127.0.0.1:44718 (icd)", 20), "talos…");
        assert_eq!(elide("no reply within 500 ms", 18), "no reply within…");
        assert_eq!(elide("no reply within 500 ms", 19), "no reply within…");
        assert_eq!(elide("no reply within 500 ms", 20), "no reply within 500…");
        assert_eq!(elide("A5 5A 00 07", 8), "A5 5A…");
        assert!(width(&elide("A5 5A 00 07", 8)) <= 8);
    }

    #[test]
    fn a_long_first_word_is_cut_inside_only_without_digits() {
        assert_eq!(elide("maximum_core_temperature", 8), "maximum…");
        assert_eq!(elide("127.0.0.1:44718", 8), "…");
        assert_eq!(elide("anything", 1), "…");
        assert_eq!(elide("anything", 0), "");
    }

    #[test]
    fn names_are_cut_anywhere() {
        assert_eq!(elide_name("a-very-long-name", 7), "a-very…");
        assert_eq!(elide_name("pick", 4), "pick");
        assert_eq!(elide_name("pick", 1), "…");
        assert_eq!(elide_name("pick", 0), "");
    }

    #[test]
    fn wide_characters_count_double() {
        assert_eq!(width("位置"), 4);
        assert_eq!(elide_name("位置位置", 5), "位置…");
        assert_eq!(elide("位置 12", 5), "位置…");
    }

    #[test]
    fn elided_text_fits_its_width() {
        let text = "talos 127.0.0.1:44718 (icd, crc16), operator 1.0";
        for max in 0..60 {
            let cut = elide(text, max);
            assert!(width(&cut) <= max, "{max}: {cut:?}");
        }
    }
}
