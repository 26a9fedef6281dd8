//! Rendering: a pure function of the frame's [`View`](super::view::View), one file per panel.

pub mod arm;
pub mod dialog;
pub mod help;
pub mod hints;
pub mod joints;
pub mod log;
pub mod positions;
pub mod status;
pub mod tcp;
pub mod theme;

use ratatui::Frame;
use ratatui::layout::{Constraint, Direction, Layout, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Paragraph, Wrap};

use super::app::{MIN_HEIGHT, MIN_WIDTH, Overlay};
use super::view::View;
use crate::link::interface::TelemetrySource;
pub use theme::Theme;

/// What a telemetry panel says when it has nothing to show.
pub fn no_telemetry_text(view: &View) -> &'static str {
    match view.telemetry_source {
        TelemetrySource::None => "no telemetry: the ack-dialect operator sends none back",
        _ => "waiting for telemetry...",
    }
}

/// A telemetry panel's title, with the telemetry's age when it is old.
pub fn telemetry_title(title: &str, view: &View) -> String {
    match view.telemetry_stale {
        Some(age) => format!("{title} (stale {})", super::app::age_text(age)),
        None => title.to_string(),
    }
}

/// Greys out the inside of a telemetry panel whose values are old (call after drawing it).
pub fn grey_if_stale(frame: &mut Frame, area: Rect, view: &View, theme: &Theme) {
    if view.telemetry_stale.is_some() {
        let inner = Block::default().borders(Borders::ALL).inner(area);
        frame.buffer_mut().set_style(inner, theme.stale());
    }
}

/// A bordered panel with a bold title.
pub fn panel(title: &str, theme: &Theme) -> Block<'static> {
    Block::default()
        .borders(Borders::ALL)
        .title(Span::styled(format!(" {title} "), theme.title()))
}

/// Draws a telemetry panel's notice when there is no telemetry to show.
pub fn draw_no_telemetry(frame: &mut Frame, area: Rect, block: Block, view: &View) {
    frame.render_widget(
        Paragraph::new(no_telemetry_text(view))
            .block(block)
            .wrap(Wrap { trim: true }),
        area,
    );
}

/// Draws the whole screen.
pub fn draw(frame: &mut Frame, view: &View, theme: &Theme) {
    let area = frame.area();
    if area.width < MIN_WIDTH || area.height < MIN_HEIGHT {
        let text = format!(
            "terminal too small ({}x{}): motion stopped. Need {MIN_WIDTH}x{MIN_HEIGHT}.",
            area.width, area.height
        );
        frame.render_widget(
            Paragraph::new(Line::styled(text, theme.alarm())).wrap(Default::default()),
            area,
        );
        return;
    }
    // A tall terminal gives half its extra rows to the arm and positions row, half to the log.
    let extra = area.height.saturating_sub(24) / 2;
    let rows = Layout::default()
        .direction(Direction::Vertical)
        .constraints([
            Constraint::Length(2),
            Constraint::Length(10),
            Constraint::Length(7 + extra),
            Constraint::Min(3),
            Constraint::Length(1),
        ])
        .split(area);
    status::draw(frame, rows[0], view, theme);
    let top = split_columns(rows[1], 58);
    joints::draw(frame, top[0], view, theme);
    tcp::draw(frame, top[1], view, theme);
    let middle = split_columns(rows[2], 55);
    arm::draw(frame, middle[0], view, theme);
    positions::draw(frame, middle[1], view, theme);
    log::draw(frame, rows[3], view, theme);
    hints::draw(frame, rows[4], view, theme);
    match &view.overlay {
        Overlay::None => {}
        Overlay::Help => help::draw(frame, help::area(area), view, theme),
        _ => dialog::draw(frame, area, view, theme),
    }
}

fn split_columns(area: Rect, left_percent: u16) -> std::rc::Rc<[Rect]> {
    Layout::default()
        .direction(Direction::Horizontal)
        .constraints([
            Constraint::Percentage(left_percent),
            Constraint::Percentage(100 - left_percent),
        ])
        .split(area)
}
