//! Rendering: a pure function of the frame's [`View`], one file per panel.
//!
//! At every size from the minimum up, no number is ever cut: panels give way whole by the
//! priority documented in [`layout`], columns give way whole inside a panel, and text too
//! wide for its place ends in `…` before a number rather than inside one ([`numbers`]).

pub mod arm;
pub mod arm_view;
mod braille;
pub mod dialog;
pub mod help;
pub mod hints;
pub mod history;
pub mod joints;
pub mod layout;
mod lines;
pub mod log;
mod long_text;
pub mod numbers;
pub mod position_pose;
pub mod positions;
pub mod status;
pub mod tcp;
pub mod theme;

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Paragraph, Wrap};

use super::app::{MIN_HEIGHT, MIN_WIDTH, Overlay};
use super::view::View;
use crate::link::interface::TelemetrySource;
pub use theme::Theme;

/// What a telemetry panel says when it has nothing to show.
pub fn no_telemetry_text(view: &View) -> &'static str {
    match view.motion_status.telemetry_source {
        TelemetrySource::None => "no telemetry: the ack-dialect operator sends none back",
        _ => "waiting for telemetry...",
    }
}

/// Greys out the inside of a telemetry panel whose values are old (call after drawing it).
pub fn grey_if_stale(frame: &mut Frame, area: Rect, view: &View, theme: &Theme) {
    if view.motion_status.telemetry_stale.is_some() {
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

/// A bordered panel `width` columns wide titled by the first of `titles` (longest first) that
/// fits whole between its corners; the last one elided when none does.
pub fn fitted_panel(titles: &[String], width: u16, theme: &Theme) -> Block<'static> {
    // Two corners and a space either side of the title.
    let room = usize::from(width).saturating_sub(4);
    panel(&numbers::first_fitting(titles, room), theme)
}

/// A telemetry panel's titles, longest first: `title` with each of `details` (longest first),
/// then `title` alone; each with the telemetry's age when it is old (the age goes last).
pub fn telemetry_titles(title: &str, details: &[&str], view: &View) -> Vec<String> {
    let stale = view
        .motion_status
        .telemetry_stale
        .map(|age| format!(" (stale {})", super::app::age_text(age)))
        .unwrap_or_default();
    let mut titles: Vec<String> = details
        .iter()
        .map(|detail| format!("{title}{detail}{stale}"))
        .collect();
    titles.push(format!("{title}{stale}"));
    if !stale.is_empty() {
        titles.push(format!("{title} (stale)"));
    }
    titles
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

/// Draws the whole screen. Whatever text reached it (a name from a file, a keymap's, an
/// operator's reply), no control or bidi character reaches the terminal.
pub fn draw(frame: &mut Frame, view: &View, theme: &Theme) {
    draw_panels(frame, view, theme);
    neutralise(frame.buffer_mut());
}

/// The last guard before the terminal: a cell holding a control or bidi character (text that
/// reached a panel without [`crate::text::shown`]) keeps only its other characters, or shows
/// U+FFFD when it had none.
pub fn neutralise(buffer: &mut ratatui::buffer::Buffer) {
    for cell in buffer.content.iter_mut() {
        let symbol = cell.symbol();
        // Most cells hold one printable ASCII character: decided without decoding it.
        if crate::text::is_printable_ascii(symbol) || !symbol.chars().any(crate::text::is_unsafe) {
            continue;
        }
        let kept: String = symbol
            .chars()
            .filter(|c| !crate::text::is_unsafe(*c))
            .collect();
        cell.set_symbol(if kept.is_empty() { "\u{FFFD}" } else { &kept });
    }
}

fn draw_panels(frame: &mut Frame, view: &View, theme: &Theme) {
    let area = frame.area();
    if area.width < MIN_WIDTH || area.height < MIN_HEIGHT {
        let arm = if view.session.simulated {
            "SIMULATED ARM: "
        } else {
            ""
        };
        let text = format!(
            "{arm}terminal too small ({}x{}): motion stopped. Need {MIN_WIDTH}x{MIN_HEIGHT}.",
            area.width, area.height
        );
        frame.render_widget(
            Paragraph::new(Line::styled(text, theme.alarm())).wrap(Default::default()),
            area,
        );
        return;
    }
    let widths = layout::TopWidths {
        tool_long: tcp::width(view, true),
        tool_short: tcp::width(view, false),
        joints_comfortable: joints::width(view, joints::COMFORTABLE_COLUMNS),
        joints_min: joints::width(view, joints::MIN_COLUMNS),
    };
    let places = layout::layout(area, widths);
    status::draw(frame, places.status, view, theme);
    let panels: [(Option<Rect>, Panel); 7] = [
        (places.joints, joints::draw),
        (places.tool, tcp::draw),
        (places.arm, arm::draw),
        (places.positions, positions::draw),
        (places.log, log::draw),
        (places.history, history::draw),
        (places.arm_view, arm_view::draw),
    ];
    for (place, draw) in panels {
        if let Some(place) = place {
            draw(frame, place, view, theme);
        }
    }
    hints::draw(frame, places.bottom, view, theme);
    match &view.screen.overlay {
        Overlay::None => {}
        Overlay::Help => help::draw(frame, help::area(area), view, theme),
        _ => dialog::draw(frame, area, view, theme),
    }
}

type Panel = fn(&mut Frame, Rect, &View, &Theme);
