//! Confirmations, forms and a position's coordinates, drawn over the panels.

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Clear, Paragraph, Wrap};

use super::numbers::fixed;
use super::theme::Theme;
use crate::console::app::{Overlay, polar_of};
use crate::console::view::View;

/// Tenths as a number with one decimal.
fn tenths(value: i32) -> String {
    fixed(f64::from(value) / 10.0, 1)
}

pub fn draw(frame: &mut Frame, area: Rect, view: &View, theme: &Theme) {
    let (title, lines) = match &view.overlay {
        Overlay::Confirm(confirm) => (
            " Confirm ".to_string(),
            vec![
                Line::styled(confirm.question(), theme.warning()),
                Line::raw(""),
                Line::raw("y or enter: yes    any other key: no"),
            ],
        ),
        Overlay::Form(form) => {
            let mut lines = Vec::new();
            for (i, field) in form.fields.iter().enumerate() {
                let focused = i == form.focus;
                let value = if field.toggle {
                    format!("[{}] (space toggles)", field.value)
                } else if focused {
                    format!("{}_", field.value)
                } else {
                    field.value.clone()
                };
                lines.push(Line::from(vec![
                    Span::styled(
                        format!("{:>14}: ", field.label),
                        if focused {
                            theme.selected()
                        } else {
                            theme.dim()
                        },
                    ),
                    Span::raw(value),
                ]));
            }
            lines.push(Line::raw(""));
            if let Some(error) = &form.error {
                lines.push(Line::styled(error.clone(), theme.alarm()));
            }
            lines.push(Line::styled(
                "tab/up/down: field  enter: ok  esc: cancel",
                theme.dim(),
            ));
            (format!(" {} ", form.title()), lines)
        }
        Overlay::Position { name, coordinates } => {
            let mut lines = Vec::new();
            match coordinates {
                None => lines.push(Line::styled("asking the operator...", theme.dim())),
                Some(c) => {
                    match c.cartesian {
                        Some([x, y, z]) => lines.push(Line::raw(format!(
                            "cartesian  x {}  y {}  z {} mm",
                            tenths(x),
                            tenths(y),
                            tenths(z)
                        ))),
                        None => lines.push(Line::raw("cartesian  unknown")),
                    }
                    match c.polar.or(c.cartesian.map(polar_of)) {
                        Some([d, a, r]) => lines.push(Line::raw(format!(
                            "polar      elevation {}  azimuth {} deg  radius {} mm",
                            tenths(d),
                            tenths(a),
                            tenths(r)
                        ))),
                        None => lines.push(Line::raw("polar      unknown")),
                    }
                }
            }
            lines.push(Line::raw(""));
            lines.push(Line::styled("any key closes", theme.dim()));
            (format!(" Position '{name}' "), lines)
        }
        Overlay::None | Overlay::Help => return,
    };
    let height = (lines.len() as u16 + 2).min(area.height);
    let width = 72.min(area.width);
    let rect = Rect {
        x: area.x + (area.width - width) / 2,
        y: area.y + (area.height - height) / 2,
        width,
        height,
    };
    let block = Block::default()
        .borders(Borders::ALL)
        .title(Span::styled(title, theme.title()));
    frame.render_widget(Clear, rect);
    frame.render_widget(
        Paragraph::new(lines)
            .block(block)
            .wrap(Wrap { trim: false }),
        rect,
    );
}
