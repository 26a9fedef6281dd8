//! The help overlay: the active keymap, every action with its keys.

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Clear, Paragraph};

use super::theme::Theme;
use crate::console::action::Action;
use crate::console::view::View;

pub fn draw(frame: &mut Frame, area: Rect, view: &View, theme: &Theme) {
    let keymap = &view.keymap;
    let mut lines = vec![
        Line::styled(
            "Hold a jog key to move; release it to stop. Space stops everything.",
            theme.accent(),
        ),
        Line::styled(
            "A keyboard is not an e-stop: keep the hardware e-stop in reach.",
            theme.warning(),
        ),
        Line::raw(""),
    ];
    let entries: Vec<(String, &str)> = Action::ALL
        .iter()
        .map(|a| {
            let keys: Vec<String> = keymap.keys_for(*a).iter().map(|k| k.to_string()).collect();
            let keys = if keys.is_empty() {
                "-".to_string()
            } else {
                keys.join(" ")
            };
            (keys, a.describe())
        })
        .collect();
    // One column when it fits; else two, each as wide as its longest entry, with the right
    // one's descriptions cut short if they must be (at 80x24 every action still shows).
    let inner_width = usize::from(area.width.saturating_sub(2));
    let inner_height = usize::from(area.height.saturating_sub(2));
    let widest = |part: &[(String, &str)]| {
        let keys = part.iter().map(|(k, _)| k.len()).max().unwrap_or(0);
        let what = part.iter().map(|(_, w)| w.len()).max().unwrap_or(0);
        (keys, what)
    };
    if lines.len() + entries.len() <= inner_height || inner_width < 60 {
        let (keys_width, _) = widest(&entries);
        for (keys, what) in &entries {
            lines.push(Line::from(vec![
                Span::styled(format!("{keys:>keys_width$} "), theme.title()),
                Span::raw(*what),
            ]));
        }
    } else {
        let half = entries.len().div_ceil(2);
        let (left, right) = entries.split_at(half);
        let (left_keys, left_what) = widest(left);
        let (right_keys, _) = widest(right);
        let room = inner_width.saturating_sub(left_keys + 1 + left_what + 2 + right_keys + 1);
        for (i, (keys, what)) in left.iter().enumerate() {
            let mut spans = vec![
                Span::styled(format!("{keys:>left_keys$} "), theme.title()),
                Span::raw(format!("{what:<left_what$}  ")),
            ];
            if let Some((keys, what)) = right.get(i) {
                spans.push(Span::styled(format!("{keys:>right_keys$} "), theme.title()));
                spans.push(Span::raw(shorten(what, room)));
            }
            lines.push(Line::from(spans));
        }
    }
    let block = Block::default()
        .borders(Borders::ALL)
        .title(Span::styled(
            format!(" Help: keymap '{}' ", keymap.name()),
            theme.title(),
        ))
        .title_bottom(Span::styled(" any key closes this help ", theme.dim()));
    frame.render_widget(Clear, area);
    frame.render_widget(Paragraph::new(lines).block(block), area);
}

/// `text` cut to `width` characters, ending in "..." when cut (ASCII: the Linux console's
/// font may have no ellipsis).
fn shorten(text: &str, width: usize) -> String {
    if text.chars().count() <= width {
        return text.to_string();
    }
    let mut short: String = text.chars().take(width.saturating_sub(3)).collect();
    short.push_str("...");
    short
}
