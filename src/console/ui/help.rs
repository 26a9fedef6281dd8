//! The help overlay: the active keymap, every action with its keys.

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Clear, Paragraph};

use super::theme::Theme;
use crate::console::action::Action;
use crate::console::app::App;

pub fn draw(frame: &mut Frame, area: Rect, app: &App, theme: &Theme) {
    let keymap = &app.config.keymap;
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
    // Two columns when there is room.
    let inner_width = usize::from(area.width.saturating_sub(2));
    let column = 40;
    if inner_width >= 2 * column {
        let half = entries.len().div_ceil(2);
        for i in 0..half {
            let mut spans = Vec::new();
            for (keys, what) in [entries.get(i), entries.get(i + half)]
                .into_iter()
                .flatten()
            {
                spans.push(Span::styled(format!("{keys:>10} "), theme.title()));
                spans.push(Span::raw(format!("{:<width$}", what, width = column - 11)));
            }
            lines.push(Line::from(spans));
        }
    } else {
        for (keys, what) in &entries {
            lines.push(Line::from(vec![
                Span::styled(format!("{keys:>10} "), theme.title()),
                Span::raw(*what),
            ]));
        }
    }
    lines.push(Line::raw(""));
    lines.push(Line::styled("any key closes this help", theme.dim()));
    let block = Block::default().borders(Borders::ALL).title(Span::styled(
        format!(" Help: keymap '{}' ", keymap.name()),
        theme.title(),
    ));
    frame.render_widget(Clear, area);
    frame.render_widget(Paragraph::new(lines).block(block), area);
}
