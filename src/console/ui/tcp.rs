//! The tool panel: TCP pose, twist and wrench.

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;

use super::theme::Theme;
use crate::console::view::View;

pub fn draw(frame: &mut Frame, area: Rect, view: &View, theme: &Theme) {
    let block = super::panel(
        &super::telemetry_title("Tool (TCP, base frame)", view),
        theme,
    );
    let Some(t) = &view.telemetry else {
        return super::draw_no_telemetry(frame, area, block, view);
    };
    let p = t.tcp.pose;
    let v = t.tcp.twist;
    let w = t.tcp.wrench;
    let dim = theme.dim();
    // 36 columns inside the borders; one column less per number where that does not fit (the
    // right-hand panel at 80 columns has 32).
    let (label_w, value_w) = if area.width >= 36 + 2 {
        (10, 8)
    } else {
        (9, 7)
    };
    let row = |label: &str, values: [f32; 3], precision: usize| {
        let [a, b, c] = values;
        Line::from(vec![
            Span::styled(format!("{label:<label_w$}"), dim),
            Span::raw(format!(
                "{a:>value_w$.precision$} {b:>value_w$.precision$} {c:>value_w$.precision$}"
            )),
        ])
    };
    let lines = vec![
        Line::styled(
            format!(
                "{:<label_w$}{:>value_w$} {:>value_w$} {:>value_w$}",
                "", "x", "y", "z"
            ),
            dim,
        ),
        row("pos mm", [p.x, p.y, p.z].map(|v| v * 1000.0), 1),
        row("rot deg", [p.theta_x, p.theta_y, p.theta_z], 2),
        row("vel mm/s", [v.x, v.y, v.z].map(|v| v * 1000.0), 1),
        row("ang deg/s", [v.theta_x, v.theta_y, v.theta_z], 1),
        row("force N", [w.force_x, w.force_y, w.force_z], 2),
        row("torque Nm", [w.torque_x, w.torque_y, w.torque_z], 2),
    ];
    frame.render_widget(Paragraph::new(lines).block(block), area);
    super::grey_if_stale(frame, area, view, theme);
}
