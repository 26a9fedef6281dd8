//! Confirmations, forms and a position's coordinates, drawn over the panels. Their last lines
//! (a question's answers, a form's keys) always show, at every size the console draws: what
//! is above them gives way first (`dialog/fit.rs`).

mod fit;

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Clear, Paragraph};

use super::long_text::elide_start;
use super::numbers::elide_name;
use super::theme::Theme;
use crate::console::app::Overlay;
use crate::console::view::View;

const DIALOG_WIDTH: u16 = 72;

pub fn draw(frame: &mut Frame, area: Rect, view: &View, theme: &Theme) {
    // Below the status bar, as the help: what the arm is doing stays in view.
    let room = super::help::area(area);
    let width = DIALOG_WIDTH.min(area.width);
    // Inside the borders.
    let columns = usize::from(width.saturating_sub(2));
    let most_rows = usize::from(room.height.saturating_sub(2));
    let (title, lines) = match &view.screen.overlay {
        Overlay::Confirm(confirm) => {
            let answers = [Line::raw(""), Line::raw(confirm.answers())];
            let lines = fit::question(
                &confirm.text(),
                theme.warning(),
                &answers,
                columns,
                most_rows,
            );
            ("Confirm".to_string(), lines)
        }
        Overlay::Form(form) => {
            let mut lines = Vec::new();
            // The dialog's width less its borders and the labels.
            let room = columns.saturating_sub(16);
            for (i, field) in form.fields.iter().enumerate() {
                let focused = i == form.focus;
                let value = if field.toggle {
                    format!("[{}] (space toggles)", field.value)
                } else if focused {
                    // The end, where typing goes, stays in view.
                    format!("{}_", elide_start(&field.value, room.saturating_sub(1)))
                } else {
                    elide_name(&field.value, room)
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
            // What was wrong shows with the keys, below the fields.
            let mut foot = Vec::new();
            if let Some(error) = &form.error {
                foot.push(Line::styled(error.clone(), theme.alarm()));
            }
            foot.push(Line::styled(
                "tab/up/down: field  enter: ok  esc: cancel",
                theme.dim(),
            ));
            (
                form.title().to_string(),
                fit::fit(&lines, &foot, columns, most_rows),
            )
        }
        Overlay::Position { name, coordinates } => {
            let lines = super::position_pose::lines(view, name, coordinates.as_ref(), theme);
            let close = [Line::raw(""), Line::styled("any key closes", theme.dim())];
            (
                format!("Position '{name}'"),
                fit::fit(&lines, &close, columns, most_rows),
            )
        }
        Overlay::Fence(open) => {
            let Some(screen) = &view.arm.fence_screen else {
                return;
            };
            let mut lines: Vec<Line> = screen
                .rows
                .iter()
                .enumerate()
                .map(|(i, row)| {
                    let style = if i == open.selected {
                        theme.selected()
                    } else {
                        ratatui::style::Style::default()
                    };
                    let mark = if i == open.selected { ">" } else { " " };
                    let text = format!("{mark} {:<22} {}", elide_name(&row.label, 22), row.detail);
                    Line::styled(text, style)
                })
                .collect();
            if let Some([x, y, z]) = screen.corner {
                lines.push(Line::styled(
                    format!("corner 1 marked at {x} {y} {z} mm"),
                    theme.dim(),
                ));
            }
            if let Some(why) = &screen.unwritten {
                lines.push(Line::styled(format!("NOT WRITTEN: {why}"), theme.alarm()));
            }
            let mut foot = vec![Line::raw("")];
            match &open.naming {
                Some((naming, text)) => {
                    let what = match naming {
                        crate::console::app::Naming::Zone { .. } => "zone name",
                        crate::console::app::Naming::Profile => "profile name",
                    };
                    foot.push(Line::from(vec![
                        Span::styled(format!("{what}: "), theme.selected()),
                        Span::raw(format!(
                            "{}_",
                            elide_start(text, columns.saturating_sub(16))
                        )),
                    ]));
                    foot.push(Line::styled("enter: ok  esc: cancel", theme.dim()));
                }
                None => {
                    foot.push(Line::styled(
                        "up/down  s: face at the tool  c: mark corner  e: zone on/off",
                        theme.dim(),
                    ));
                    foot.push(Line::styled(
                        "x: delete zone  u: undo  esc: close",
                        theme.dim(),
                    ));
                }
            }
            (
                "Fence".to_string(),
                fit::fit(&lines, &foot, columns, most_rows),
            )
        }
        Overlay::None | Overlay::Help => return,
    };
    let height = (lines.len() as u16 + 2).min(room.height);
    // In the middle of the screen, or as near as leaves the status bar in view.
    let middle = area.y + (area.height - height) / 2;
    let rect = Rect {
        x: area.x + (area.width - width) / 2,
        y: middle.clamp(room.y, room.bottom() - height),
        width,
        height,
    };
    let block = super::panel(&title, theme);
    frame.render_widget(Clear, rect);
    // Wrapped to the dialog's width already: a row each.
    frame.render_widget(Paragraph::new(lines).block(block), rect);
}
