//! The tool panel: TCP pose, twist and wrench.

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Paragraph};

use super::theme::Theme;
use crate::console::app::App;

pub fn draw(frame: &mut Frame, area: Rect, app: &App, theme: &Theme) {
    let block = Block::default()
        .borders(Borders::ALL)
        .title(Span::styled(" Tool (TCP, base frame) ", theme.title()));
    let Some(t) = &app.telemetry else {
        frame.render_widget(
            Paragraph::new(super::no_telemetry_text(app)).block(block),
            area,
        );
        return;
    };
    let p = t.tcp.pose;
    let v = t.tcp.twist;
    let w = t.tcp.wrench;
    let dim = theme.dim();
    let row = |label: &str, values: [f32; 3], precision: usize| {
        let [a, b, c] = values;
        Line::from(vec![
            Span::styled(format!("{label:<10}"), dim),
            Span::raw(format!(
                "{a:>8.precision$} {b:>8.precision$} {c:>8.precision$}"
            )),
        ])
    };
    let lines = vec![
        Line::styled(format!("{:<10}{:>8} {:>8} {:>8}", "", "x", "y", "z"), dim),
        row("pos mm", [p.x, p.y, p.z].map(|v| v * 1000.0), 1),
        row("rot deg", [p.theta_x, p.theta_y, p.theta_z], 2),
        row("vel mm/s", [v.x, v.y, v.z].map(|v| v * 1000.0), 1),
        row("ang deg/s", [v.theta_x, v.theta_y, v.theta_z], 1),
        row("force N", [w.force_x, w.force_y, w.force_z], 2),
        row("torque Nm", [w.torque_x, w.torque_y, w.torque_z], 2),
    ];
    frame.render_widget(Paragraph::new(lines).block(block), area);
}
