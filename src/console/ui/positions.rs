//! The named positions panel: the book, the selection, and names the operator does not know.
//!
//! Only the rows that fit are built: a book of 100 000 names costs a frame no more than one of
//! ten.

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{List, ListItem, ListState};

use super::numbers;
use super::theme::Theme;
use crate::console::app::BookState;
use crate::console::positions::BookEntry;
use crate::console::view::View;

pub fn draw(frame: &mut Frame, area: Rect, view: &View, theme: &Theme) {
    let where_ = if view.session.positions_on_operator {
        "operator"
    } else {
        "console"
    };
    let block = super::panel(&format!("Positions ({where_})"), theme);
    let inner = block.inner(area);
    // The highlight symbol takes two columns of every row of a list with a selection.
    let row_width = if view.book.positions.is_empty() {
        usize::from(inner.width)
    } else {
        usize::from(inner.width).saturating_sub(2)
    };
    // The book's state first: while it loads, or when it could not be read, the list below
    // holds only what was changed meanwhile.
    let state = match &view.book.state {
        BookState::Ready => None,
        BookState::Loading { file } => Some(Line::styled(
            numbers::elide(&format!("loading positions from {file}…"), row_width),
            theme.dim(),
        )),
        BookState::Failed { error } => Some(Line::styled(
            numbers::elide(&format!("not loaded, not saved: {error}"), row_width),
            theme.alarm(),
        )),
    };
    if view.book.positions.is_empty() {
        let line = state.unwrap_or_else(|| {
            Line::styled(
                numbers::elide("none yet: p saves the current pose", row_width),
                theme.dim(),
            )
        });
        frame.render_widget(List::new([ListItem::new(line)]).block(block), area);
        return;
    }
    let header = usize::from(state.is_some());
    let rows = usize::from(inner.height).saturating_sub(header).max(1);
    // The same scrolling as a list drawn whole: the selection on the last row once past the
    // first screen.
    let first = (view.book.selected + 1).saturating_sub(rows);
    let mut items: Vec<ListItem> = state.into_iter().map(ListItem::new).collect();
    items.extend(
        view.book
            .positions
            .entries_from(first)
            .take(rows)
            .map(|(name, entry)| ListItem::new(row(name, entry, row_width, theme))),
    );
    let selected = header + view.book.selected - first;
    let mut list_state = ListState::default().with_selected(Some(selected));
    let list = List::new(items)
        .block(block)
        .highlight_style(theme.selected())
        .highlight_symbol("> ");
    frame.render_stateful_widget(list, area, &mut list_state);
}

/// One position in `width` columns: the name, its marks, its coordinates. When that does not
/// fit, the anchor's parent goes, then the name is elided to keep the coordinates whole (the
/// unknown-to-operator warning shortened if need be), then
/// the coordinates go whole; the name and a warning that the operator does not know it stay
/// (elided last of all).
fn row(name: &str, entry: &BookEntry, width: usize, theme: &Theme) -> Line<'static> {
    // Book names keep the name rule (repaired as the file loads); this keeps the panel safe
    // whatever a name holds.
    let shown = crate::text::shown(name);
    let name: &str = &shown;
    // A position not saved outranks one the operator does not know: it is lost on quitting.
    let (mark, short_marks, mark_style) = if entry.unsaved {
        (UNSAVED, SHORT_UNSAVED, theme.alarm())
    } else {
        (UNKNOWN, SHORT_UNKNOWN, theme.warning())
    };
    let unknown =
        (entry.unsaved || entry.unknown_to_operator).then(|| Span::styled(mark, mark_style));
    let parent = entry
        .parent
        .as_ref()
        .filter(|_| entry.anchor)
        .map(|parent| Span::styled(format!("  @{parent}"), theme.accent()));
    let coordinates = entry.cartesian.map(|[x, y, z]| {
        let mm = |tenths: i32| numbers::fixed(f64::from(tenths) / 10.0, 0);
        Span::styled(format!("  {} {} {} mm", mm(x), mm(y), mm(z)), theme.dim())
    });
    let name_width = numbers::width(name);
    let unknown_width = unknown.as_ref().map_or(0, |s| numbers::width(&s.content));
    let rest = |spans: &[&Option<Span<'static>>]| -> usize {
        spans
            .iter()
            .filter_map(|s| s.as_ref())
            .map(|s| numbers::width(&s.content))
            .sum()
    };
    let line = |name: String, tail: Vec<Option<Span<'static>>>| {
        let mut spans = vec![Span::raw(name)];
        spans.extend(unknown.clone());
        spans.extend(tail.into_iter().flatten());
        Line::from(spans)
    };
    if name_width + unknown_width + rest(&[&parent, &coordinates]) <= width {
        return line(name.to_string(), vec![parent, coordinates]);
    }
    let coordinates_width = rest(&[&coordinates]);
    if unknown_width + coordinates_width + NAME_MIN_WIDTH.min(name_width) <= width {
        let room = width - unknown_width - coordinates_width;
        return line(numbers::elide_name(name, room), vec![coordinates]);
    }
    // Then a shorter warning, so that a long name never pushes the coordinates out of view.
    if unknown.is_some() {
        for short in short_marks {
            let mark_width = numbers::width(short);
            if mark_width + coordinates_width + NAME_MIN_WIDTH.min(name_width) <= width {
                let room = width - mark_width - coordinates_width;
                let mut spans = vec![Span::raw(numbers::elide_name(name, room))];
                spans.push(Span::styled(short, mark_style));
                spans.extend(coordinates);
                return Line::from(spans);
            }
        }
    }
    if name_width + unknown_width <= width || unknown.is_none() {
        return line(numbers::elide_name(name, width), Vec::new());
    }
    // The name at its shortest, and as much of the warning as fits.
    let name = numbers::elide_name(name, NAME_MIN_WIDTH.min(width));
    let room = width.saturating_sub(numbers::width(&name));
    let warning = numbers::elide(mark, room);
    Line::from(vec![Span::raw(name), Span::styled(warning, mark_style)])
}

/// The mark of a name the operator does not know.
const UNKNOWN: &str = "  unknown to operator";
/// Shorter forms of [`UNKNOWN`] for a narrow panel.
const SHORT_UNKNOWN: [&str; 2] = ["  unknown", "  ?"];
/// The mark of a position whose last change could not be written to the file.
const UNSAVED: &str = "  NOT SAVED";
const SHORT_UNSAVED: [&str; 2] = ["  unsaved", "  !"];

/// The fewest columns of a name shown beside its coordinates.
const NAME_MIN_WIDTH: usize = 4;
