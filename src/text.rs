//! Text from outside (a book, a keymap, a network peer) made safe to show and log: the one
//! sanitiser every such path goes through.
//! - [`shown`]: control characters (C0, DEL, C1) and bidi controls (U+202A-U+202E, U+2066-U+2069,
//!   U+200E, U+200F, U+061C) become visible escapes (`\n`, `\u{202e}`), so none can reverse the
//!   line or move the cursor.
//! - [`logged`]: the same, plus `\\`, cut to [`LOG_FIELD_CHARS`] with the full length noted.
//! - [`name_repair`]: a position name from a file made to pass the typed-name rule.

use std::borrow::Cow;
use std::fmt::{self, Write};

/// A logged field longer than this many characters is cut.
pub const LOG_FIELD_CHARS: usize = 200;

/// All printable ASCII (one cell a byte), from the bytes without decoding: the screen's fast path.
pub fn is_printable_ascii(text: &str) -> bool {
    text.bytes().all(|b| matches!(b, b' '..=b'~'))
}

/// Whether `c` must not reach a terminal or a log as it is.
pub fn is_unsafe(c: char) -> bool {
    c.is_control() || is_bidi_control(c)
}

/// The bidirectional formatting characters: embeddings and overrides, isolates, marks.
pub fn is_bidi_control(c: char) -> bool {
    matches!(c, '\u{202A}'..='\u{202E}' | '\u{2066}'..='\u{2069}' | '\u{200E}' | '\u{200F}' | '\u{061C}')
}

/// Writes the visible escape of an unsafe character.
fn escape(c: char, out: &mut impl Write) -> fmt::Result {
    match c {
        '\n' => out.write_str("\\n"),
        '\r' => out.write_str("\\r"),
        '\t' => out.write_str("\\t"),
        '\0' => out.write_str("\\0"),
        c => write!(out, "\\u{{{:x}}}", u32::from(c)),
    }
}

/// `text` for the screen, unsafe characters escaped; borrowed when there are none.
pub fn shown(text: &str) -> Cow<'_, str> {
    if !text.chars().any(is_unsafe) {
        return Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        if is_unsafe(c) {
            // Writing to a String cannot fail.
            let _ = escape(c, &mut out);
        } else {
            out.push(c);
        }
    }
    Cow::Owned(out)
}

/// A field for a log line: see [`logged`].
#[derive(Debug, Clone, Copy)]
pub struct Logged<'a>(&'a str);

/// `text` as a log field: escaped and capped (see the module's notes). Formats lazily.
pub fn logged(text: &str) -> Logged<'_> {
    Logged(text)
}

impl fmt::Display for Logged<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut chars = self.0.chars();
        for c in chars.by_ref().take(LOG_FIELD_CHARS) {
            if c == '\\' {
                f.write_str("\\\\")?;
            } else if is_unsafe(c) {
                escape(c, f)?;
            } else {
                f.write_char(c)?;
            }
        }
        if chars.next().is_some() {
            let total = self.0.chars().count();
            write!(f, "… ({total} characters, {} bytes)", self.0.len())?;
        }
        Ok(())
    }
}

/// The longest name the rule admits, in bytes (the Talos ICD's UINT8 length prefix).
pub const MAX_NAME_BYTES: usize = 255;

/// Whether `byte` may be in a name: printable ASCII.
pub fn name_byte(byte: u8) -> bool {
    (0x20..=0x7E).contains(&byte)
}

/// A name that breaks the rule, made into one that keeps it: characters outside printable ASCII
/// escaped, outer spaces dropped, cut to [`MAX_NAME_BYTES`], `unnamed` if nothing is left. `None`
/// when `name` keeps the rule; the caller makes it unique.
pub fn name_repair(name: &str) -> Option<String> {
    let keeps = !name.is_empty()
        && name.len() <= MAX_NAME_BYTES
        && name.bytes().all(name_byte)
        && !name.starts_with(' ')
        && !name.ends_with(' ');
    if keeps {
        return None;
    }
    let mut repaired = String::new();
    for c in name.chars() {
        if repaired.len() >= MAX_NAME_BYTES {
            break;
        }
        if c.is_ascii() && name_byte(c as u8) {
            repaired.push(c);
        } else {
            // A control character by its escape, any other by its code point.
            let _ = escape(c, &mut repaired);
        }
    }
    // Every character pushed is ASCII: any byte index is a character boundary.
    repaired.truncate(MAX_NAME_BYTES);
    let trimmed = repaired.trim_matches(' ');
    Some(if trimmed.is_empty() {
        "unnamed".to_string()
    } else {
        trimmed.to_string()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn controls_of_every_class_are_escaped_for_the_screen() {
        assert_eq!(shown("pick"), "pick");
        assert!(matches!(shown("pick"), Cow::Borrowed(_)));
        assert_eq!(shown("a\nb\rc\td\0e"), "a\\nb\\rc\\td\\0e");
        // ESC (a terminal escape sequence's start), BEL, DEL, and C1's CSI.
        assert_eq!(shown("\u{1b}[2J"), "\\u{1b}[2J");
        assert_eq!(shown("\u{7}\u{7f}\u{9b}"), "\\u{7}\\u{7f}\\u{9b}");
        // Wide and accented text is not touched.
        assert_eq!(shown("位置 é"), "位置 é");
    }

    #[test]
    fn bidi_overrides_isolates_and_marks_are_escaped() {
        for c in ('\u{202A}'..='\u{202E}').chain('\u{2066}'..='\u{2069}') {
            let text = format!("ab{c}cd");
            let out = shown(&text);
            assert!(!out.contains(c), "{c:?}");
            assert_eq!(out, format!("ab\\u{{{:x}}}cd", u32::from(c)));
        }
        assert_eq!(shown("a\u{200F}b\u{061C}"), "a\\u{200f}b\\u{61c}");
        // Combining marks are not controls: shown as they are.
        assert_eq!(shown("e\u{301}"), "e\u{301}");
    }

    #[test]
    fn a_log_field_is_one_escaped_line_and_capped() {
        assert_eq!(logged("pick").to_string(), "pick");
        let forged = "x\n2026-01-01T00:00:00Z  INFO forged line\r\0";
        let line = logged(forged).to_string();
        assert!(!line.contains(['\n', '\r', '\0']), "{line}");
        assert_eq!(line, "x\\n2026-01-01T00:00:00Z  INFO forged line\\r\\0");
        // A backslash in the name cannot pass for an escape.
        assert_eq!(logged("a\\nb").to_string(), "a\\\\nb");
        let huge = "n".repeat(1 << 20);
        let line = logged(&huge).to_string();
        assert!(
            line.starts_with(&"n".repeat(LOG_FIELD_CHARS)),
            "kept the start"
        );
        assert!(
            line.ends_with("… (1048576 characters, 1048576 bytes)"),
            "{}",
            &line[LOG_FIELD_CHARS..]
        );
        assert_eq!(line.chars().count(), LOG_FIELD_CHARS + 37);
        // Exactly the cap: not cut.
        let at_cap = "m".repeat(LOG_FIELD_CHARS);
        assert_eq!(logged(&at_cap).to_string(), at_cap);
        assert_eq!(logged("\u{202E}").to_string(), "\\u{202e}");
    }

    #[test]
    fn a_name_breaking_the_rule_is_repaired_into_one_that_keeps_it() {
        assert_eq!(name_repair("pick 1"), None);
        assert_eq!(name_repair("").as_deref(), Some("unnamed"));
        assert_eq!(name_repair("   ").as_deref(), Some("unnamed"));
        assert_eq!(name_repair(" pick ").as_deref(), Some("pick"));
        assert_eq!(name_repair("a\0b").as_deref(), Some("a\\0b"));
        assert_eq!(
            name_repair("evil\u{202E}gpj").as_deref(),
            Some("evil\\u{202e}gpj")
        );
        assert_eq!(name_repair("é").as_deref(), Some("\\u{e9}"));
        let megabyte = "m".repeat(1 << 20);
        assert_eq!(name_repair(&megabyte), Some("m".repeat(255)));
        let marks = format!("a{}", "\u{301}".repeat(100_000));
        let repaired = name_repair(&marks).expect("repaired");
        assert!(repaired.len() <= MAX_NAME_BYTES);
        assert!(repaired.starts_with("a\\u{301}"), "{repaired}");
        for name in ["", "a\0b", "\u{202E}", &megabyte, &marks, " x", "\u{301}"] {
            let repaired = name_repair(name).expect("repaired");
            assert!(
                !repaired.is_empty()
                    && repaired.len() <= MAX_NAME_BYTES
                    && repaired.bytes().all(name_byte)
                    && !repaired.starts_with(' ')
                    && !repaired.ends_with(' '),
                "{repaired:?}"
            );
            assert_eq!(
                name_repair(&repaired),
                None,
                "a repaired name keeps the rule"
            );
        }
    }
}
