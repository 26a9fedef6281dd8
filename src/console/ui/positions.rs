//! The named positions panel: the book, the selection, and names the operator does not know.
//!
//! Only the rows that fit are built: a book of 100 000 names costs a frame no more than one of
//! ten.

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, List, ListItem, ListState};

use super::theme::Theme;
use crate::console::app::BookState;
use crate::console::positions::BookEntry;
use crate::console::view::View;

pub fn draw(frame: &mut Frame, area: Rect, view: &View, theme: &Theme) {
    let where_ = if view.positions_on_operator {
        "operator"
    } else {
        "console"
    };
    let block = Block::default().borders(Borders::ALL).title(Span::styled(
        format!(" Positions ({where_}) "),
        theme.title(),
    ));
    // The book's state first: while it loads, or when it could not be read, the list below
    // holds only what was changed meanwhile.
    let state = match &view.book_state {
        BookState::Ready => None,
        BookState::Loading { file } => Some(Line::styled(
            format!("loading positions from {file}…"),
            theme.dim(),
        )),
        BookState::Failed { error } => Some(Line::styled(
            format!("not loaded, not saved: {error}"),
            theme.alarm(),
        )),
    };
    if view.positions.is_empty() {
        let line = state
            .unwrap_or_else(|| Line::styled("none yet: p saves the current pose", theme.dim()));
        frame.render_widget(List::new([ListItem::new(line)]).block(block), area);
        return;
    }
    let inner = block.inner(area);
    let header = usize::from(state.is_some());
    let rows = usize::from(inner.height).saturating_sub(header).max(1);
    // The same scrolling as a list drawn whole: the selection on the last row once past the
    // first screen.
    let first = (view.selected + 1).saturating_sub(rows);
    let mut items: Vec<ListItem> = state.into_iter().map(ListItem::new).collect();
    items.extend(
        view.positions
            .entries_from(first)
            .take(rows)
            .map(|(name, entry)| ListItem::new(row(name, entry, theme))),
    );
    let selected = header + view.selected - first;
    let mut list_state = ListState::default().with_selected(Some(selected));
    let list = List::new(items)
        .block(block)
        .highlight_style(theme.selected())
        .highlight_symbol("> ");
    frame.render_stateful_widget(list, area, &mut list_state);
}

/// One position: the marks first, the coordinates last (a narrow panel cuts the end of the
/// line).
fn row<'a>(name: &'a str, entry: &BookEntry, theme: &Theme) -> Line<'a> {
    let mut spans = vec![Span::raw(name)];
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
    Line::from(spans)
}
