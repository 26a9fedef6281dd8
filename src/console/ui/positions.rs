//! The named positions panel: the book, the selection, and names the operator does not know.

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, List, ListItem, ListState};

use super::theme::Theme;
use crate::console::app::App;

pub fn draw(frame: &mut Frame, area: Rect, app: &App, theme: &Theme) {
    let where_ = if app.config.positions_on_operator {
        "operator"
    } else {
        "console"
    };
    let block = Block::default().borders(Borders::ALL).title(Span::styled(
        format!(" Positions ({where_}) "),
        theme.title(),
    ));
    if app.positions.is_empty() {
        let hint = Line::styled("none yet: p saves the current pose", theme.dim());
        frame.render_widget(List::new([ListItem::new(hint)]).block(block), area);
        return;
    }
    let items: Vec<ListItem> = app
        .positions
        .entries()
        .map(|(name, entry)| {
            // The marks first, the coordinates last: a narrow panel cuts the end of the line.
            let mut spans = vec![Span::raw(name.to_string())];
            if entry.unknown_to_operator {
                spans.push(Span::styled("  unknown to operator", theme.warning()));
            }
            if entry.anchor
                && let Some(parent) = &entry.parent
            {
                spans.push(Span::styled(format!("  @{parent}"), theme.accent()));
            }
            if let Some([x, y, z]) = entry.cartesian {
                spans.push(Span::styled(
                    format!(
                        "  {:.0} {:.0} {:.0} mm",
                        f64::from(x) / 10.0,
                        f64::from(y) / 10.0,
                        f64::from(z) / 10.0
                    ),
                    theme.dim(),
                ));
            }
            ListItem::new(Line::from(spans))
        })
        .collect();
    let mut state = ListState::default().with_selected(Some(app.selected));
    let list = List::new(items)
        .block(block)
        .highlight_style(theme.selected())
        .highlight_symbol("> ");
    frame.render_stateful_widget(list, area, &mut state);
}
