//! The joints panel: position (against limits), velocity, torque, current and temperature of
//! all seven joints.

use ratatui::Frame;
use ratatui::layout::{Constraint, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Cell, Row, Table};

use super::theme::Theme;
use crate::console::view::View;
use crate::kortex::gen3::JOINT_LIMITS_DEG;

/// Joint `joint`'s limit in degrees (Gen3: J2, J4, J6 limited; the others turn continuously).
fn limit(joint: usize) -> Option<f32> {
    JOINT_LIMITS_DEG
        .get(joint)
        .copied()
        .flatten()
        .map(|l| l as f32)
}

/// Within this many degrees of a limit the position is highlighted.
const NEAR_LIMIT: f32 = 10.0;

/// A reported 0-360 angle as a signed one, -180..180.
fn signed(deg: f32) -> f32 {
    if deg > 180.0 { deg - 360.0 } else { deg }
}

/// "▕====|   ▏" style gauge of a limited joint's position between its limits.
fn gauge(position: f32, limit: f32, width: usize) -> String {
    let fraction = ((signed(position) + limit) / (2.0 * limit)).clamp(0.0, 1.0);
    let at = ((fraction * (width.saturating_sub(1)) as f32).round() as usize).min(width - 1);
    (0..width)
        .map(|i| if i == at { '|' } else { '-' })
        .collect()
}

pub fn draw(frame: &mut Frame, area: Rect, view: &View, theme: &Theme) {
    let block = super::panel(&super::telemetry_title("Joints", view), theme);
    let Some(t) = &view.telemetry else {
        return super::draw_no_telemetry(frame, area, block, view);
    };
    let wide = area.width >= 70;
    let header = if wide {
        vec![
            "",
            "pos deg",
            "limits",
            "vel deg/s",
            "torque Nm",
            "cur A",
            "temp C",
        ]
    } else {
        vec!["", "pos", "vel", "Nm", "A", "C"]
    };
    // Numbers and their headings right-aligned in their columns.
    let right = |text: String| Cell::from(Line::from(text).right_aligned());
    let header: Vec<Cell> = header
        .into_iter()
        .enumerate()
        .map(|(i, h)| match (i, wide) {
            (0, _) | (2, true) => Cell::from(h),
            _ => right(h.to_string()),
        })
        .collect();
    let rows = t.joints.iter().enumerate().map(|(i, j)| {
        let near = limit(i).is_some_and(|l| l - signed(j.position).abs() < NEAR_LIMIT);
        let selected = usize::from(view.joint) == i + 1;
        let name = Cell::from(Span::styled(
            format!("J{}", i + 1),
            if selected {
                theme.selected()
            } else {
                theme.title()
            },
        ));
        let pos = Cell::from(
            Line::from(Span::styled(
                format!("{:.2}", j.position),
                if near {
                    theme.warning()
                } else {
                    Default::default()
                },
            ))
            .right_aligned(),
        );
        let mut cells = vec![name, pos];
        if wide {
            cells.push(Cell::from(match limit(i) {
                Some(l) => gauge(j.position, l, 11),
                None => "continuous".into(),
            }));
        }
        cells.extend([
            right(format!("{:.2}", j.velocity)),
            right(format!("{:.2}", j.torque)),
            right(format!("{:.2}", j.current)),
            right(format!("{:.1}", j.temperature)),
        ]);
        Row::new(cells)
    });
    let widths: Vec<Constraint> = if wide {
        vec![
            Constraint::Length(3),
            Constraint::Length(8),
            Constraint::Length(11),
            Constraint::Length(9),
            Constraint::Length(9),
            Constraint::Length(6),
            Constraint::Length(6),
        ]
    } else {
        vec![
            Constraint::Length(3),
            Constraint::Length(7),
            Constraint::Length(7),
            Constraint::Length(6),
            Constraint::Length(5),
            Constraint::Length(5),
        ]
    };
    let table = Table::new(rows, widths)
        .header(Row::new(header).style(theme.dim()))
        .block(block);
    frame.render_widget(table, area);
    super::grey_if_stale(frame, area, view, theme);
}
