//! Confirmations, forms and a position's coordinates, drawn over the panels.

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Clear, Paragraph, Wrap};

use super::long_text::{elide_end, elide_start};
use super::theme::Theme;
use crate::console::app::Overlay;
use crate::console::view::View;

const DIALOG_WIDTH: u16 = 72;

pub fn draw(frame: &mut Frame, area: Rect, view: &View, theme: &Theme) {
    let (title, lines) = match &view.screen.overlay {
        Overlay::Confirm(confirm) => (
            " Confirm ".to_string(),
            vec![
                Line::styled(confirm.question(), theme.warning()),
                Line::raw(""),
                Line::raw(confirm.answers()),
            ],
        ),
        Overlay::Form(form) => {
            let mut lines = Vec::new();
            // The dialog's width less its borders and the labels.
            let room = usize::from(DIALOG_WIDTH.min(area.width)).saturating_sub(2 + 16);
            for (i, field) in form.fields.iter().enumerate() {
                let focused = i == form.focus;
                let value = if field.toggle {
                    format!("[{}] (space toggles)", field.value)
                } else if focused {
                    // The end, where typing goes, stays in view.
                    format!("{}_", elide_start(&field.value, room.saturating_sub(1)))
                } else {
                    elide_end(&field.value, room)
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
            if let Some(note) = form.note {
                lines.push(Line::styled(note, theme.dim()));
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
            let mut lines = super::position_pose::lines(view, name, coordinates.as_ref(), theme);
            lines.push(Line::raw(""));
            lines.push(Line::styled("any key closes", theme.dim()));
            (format!(" Position '{name}' "), lines)
        }
        Overlay::None | Overlay::Help => return,
    };
    let height = (lines.len() as u16 + 2).min(area.height);
    let width = DIALOG_WIDTH.min(area.width);
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
