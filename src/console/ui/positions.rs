//! The named positions panel: the book, the selection, and names the operator does not know.
//!
//! Only the rows that fit are built: a book of 100 000 names costs a frame no more than one of
//! ten.

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, List, ListItem, ListState};

use super::long_text::elide_end;
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
    let width = usize::from(inner.width).saturating_sub(HIGHLIGHT.len());
    let mut items: Vec<ListItem> = state.into_iter().map(ListItem::new).collect();
    items.extend(
        view.positions
            .entries_from(first)
            .take(rows)
            .map(|(name, entry)| ListItem::new(row(name, entry, width, theme))),
    );
    let selected = header + view.selected - first;
    let mut list_state = ListState::default().with_selected(Some(selected));
    let list = List::new(items)
        .block(block)
        .highlight_style(theme.selected())
        .highlight_symbol(HIGHLIGHT);
    frame.render_stateful_widget(list, area, &mut list_state);
}

/// One position in `width` columns: the name, the marks, the coordinates. Long names (and
/// parents) are elided with `…` so the coordinates stay in view.
fn row(name: &str, entry: &BookEntry, width: usize, theme: &Theme) -> Line<'static> {
    let coordinates = entry.cartesian.map(|[x, y, z]| {
        format!(
            "  {:.0} {:.0} {:.0} mm",
            f64::from(x) / 10.0,
            f64::from(y) / 10.0,
            f64::from(z) / 10.0
        )
    });
    let parent = match (entry.anchor, &entry.parent) {
        (true, Some(parent)) => Some(parent.as_str()),
        _ => None,
    };
    let name_len = name.chars().count();
    let coordinates_len = coordinates.as_ref().map_or(0, |c| c.chars().count());
    // The longest "unknown" mark that leaves the name some room.
    let unknown = entry.unknown_to_operator.then(|| {
        UNKNOWN_MARKS
            .into_iter()
            .find(|mark| {
                width.saturating_sub(coordinates_len + mark.len()) >= name_len.min(NAME_WANTED)
            })
            .unwrap_or(UNKNOWN_MARKS[UNKNOWN_MARKS.len() - 1])
    });
    let fixed = coordinates_len + unknown.map_or(0, str::len);
    // What the name and the parent mark ("  @parent") share; the parent gets at most half.
    let room = width.saturating_sub(fixed);
    let parent_len = parent.map_or(0, |p| p.chars().count() + 3);
    let (name_room, parent_room) = if name_len + parent_len <= room {
        (name_len, parent_len)
    } else {
        let parent_room = parent_len.min(room / 2);
        (room - parent_room, parent_room)
    };
    let mut spans = vec![Span::raw(elide_end(name, name_room.max(MIN_NAME)))];
    if let Some(mark) = unknown {
        spans.push(Span::styled(mark, theme.warning()));
    }
    if let Some(parent) = parent
        && parent_room > 3
    {
        let shown = elide_end(parent, parent_room - 3);
        spans.push(Span::styled(format!("  @{shown}"), theme.accent()));
    }
    if let Some(coordinates) = coordinates {
        spans.push(Span::styled(coordinates, theme.dim()));
    }
    Line::from(spans)
}

/// The selection's mark, before every row.
const HIGHLIGHT: &str = "> ";
/// The mark of a name the operator does not know, shorter as the panel narrows.
const UNKNOWN_MARKS: [&str; 3] = ["  unknown to operator", "  unknown", "  ?"];
/// The room a name should keep before its marks are shortened.
const NAME_WANTED: usize = 10;
/// A name keeps at least this much (its first letter and the `…`), however narrow the panel.
const MIN_NAME: usize = 2;
