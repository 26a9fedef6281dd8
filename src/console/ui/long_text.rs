//! Text wider than its room: its end after a `…` (its start: [`numbers::elide_name`]). Measured
//! in terminal columns, so a name in wide characters fits its field as an ASCII one does.

use super::numbers::{self, ELLIPSIS};

/// `text` in at most `room` columns: its end, after a `…` when it is wider (the field being
/// typed into shows where the cursor is).
pub fn elide_start(text: &str, room: usize) -> String {
    if numbers::width(text) <= room {
        return text.to_string();
    }
    if room == 0 {
        return String::new();
    }
    let mut used = numbers::width(ELLIPSIS.encode_utf8(&mut [0; 4]));
    let mut tail = Vec::new();
    for c in text.chars().rev() {
        let w = numbers::width(c.encode_utf8(&mut [0; 4]));
        if used + w > room {
            break;
        }
        used += w;
        tail.push(c);
    }
    let tail: String = tail.iter().rev().collect();
    format!("{ELLIPSIS}{tail}")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::console::ui::numbers::elide_name as elide_end;

    #[test]
    fn long_text_keeps_its_start_or_its_end_and_shows_the_cut() {
        assert_eq!(elide_end("position", 8), "position");
        assert_eq!(elide_end("position", 5), "posi…");
        assert_eq!(elide_start("position", 5), "…tion");
        assert_eq!(elide_start("position", 20), "position");
    }

    #[test]
    fn wide_characters_are_counted_in_columns_and_nothing_overflows() {
        // Four characters two columns wide: 8 columns.
        let wide = "位置位置";
        assert_eq!(elide_end(wide, 8), wide);
        assert_eq!(elide_end(wide, 5), "位置…");
        assert_eq!(elide_start(wide, 5), "…位置");
        assert_eq!(elide_start(wide, 4), "…置");
        for room in 0..10 {
            assert!(numbers::width(&elide_end(wide, room)) <= room, "{room}");
            assert!(numbers::width(&elide_start(wide, room)) <= room, "{room}");
            assert!(
                numbers::width(&elide_start("position", room)) <= room,
                "{room}"
            );
        }
    }
}
