//! Text longer than its room: cut with a `…` where it shows, never silently.

/// `text` in at most `room` characters: its end, after a `…` when it is longer.
pub fn elide_start(text: &str, room: usize) -> String {
    let count = text.chars().count();
    if count <= room {
        return text.to_string();
    }
    let tail: String = text.chars().skip(count + 1 - room.max(1)).collect();
    format!("…{tail}")
}

/// `text` in at most `room` characters: its start, then a `…` when it is longer.
pub fn elide_end(text: &str, room: usize) -> String {
    if text.chars().count() <= room {
        return text.to_string();
    }
    let head: String = text.chars().take(room.saturating_sub(1)).collect();
    format!("{head}…")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_text_keeps_its_start_or_its_end_and_shows_the_cut() {
        assert_eq!(elide_end("position", 8), "position");
        assert_eq!(elide_end("position", 5), "posi…");
        assert_eq!(elide_start("position", 5), "…tion");
        assert_eq!(elide_start("position", 20), "position");
    }
}
