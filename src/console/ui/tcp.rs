//! The tool panel: TCP pose and twist in the base frame, and the wrench in the tool frame.
//!
//! The Kinova ICD lists the TCP wrench (input registers 128-139) without a frame; the simulator
//! (`sim::arm_model`) gives it as a wrist sensor measures it, in the tool frame. Long labels
//! (`pos mm`) where they fit, unit labels (`mm`) otherwise; the numbers keep their width.

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};

use super::numbers::{fixed_or_unknown, width as text_width};
use super::theme::Theme;
use crate::console::view::View;
use crate::kortex::Telemetry;

/// The fewest columns a number gets: `-1234.5` mm.
const VALUE_MIN_WIDTH: usize = 7;
/// Each row's long label, unit label, and decimals.
const ROWS: [(&str, &str, usize); 6] = [
    ("pos mm", "mm", 1),
    ("rot deg", "deg", 2),
    ("vel mm/s", "mm/s", 1),
    ("ang deg/s", "deg/s", 1),
    ("force N", "N", 2),
    ("torque Nm", "Nm", 2),
];
/// Label columns: the longest label and a space.
const LONG_LABEL: usize = 10;
const SHORT_LABEL: usize = 6;

/// Every row's three figures, as shown.
fn figures(t: &Telemetry) -> [[String; 3]; 6] {
    let p = t.tcp.pose;
    let v = t.tcp.twist;
    let w = t.tcp.wrench;
    use crate::kortex::sanity as s;
    // As reported (m, m/s), each row with its physical range and its scale for the screen.
    let rows: [([f32; 3], s::Bounds, f32); 6] = [
        ([p.x, p.y, p.z], s::TOOL_POSITION_M, 1000.0),
        (
            [p.theta_x, p.theta_y, p.theta_z],
            s::TOOL_ORIENTATION_DEG,
            1.0,
        ),
        ([v.x, v.y, v.z], s::TOOL_LINEAR_SPEED_M_S, 1000.0),
        (
            [v.theta_x, v.theta_y, v.theta_z],
            s::TOOL_ANGULAR_SPEED_DEG_S,
            1.0,
        ),
        ([w.force_x, w.force_y, w.force_z], s::TOOL_FORCE_N, 1.0),
        ([w.torque_x, w.torque_y, w.torque_z], s::TOOL_TORQUE_NM, 1.0),
    ];
    std::array::from_fn(|row| {
        let (values, bounds, scale) = rows[row];
        // A value out of physical range shows as `?`, never as a number.
        values.map(|v| fixed_or_unknown(bounds.sane(v).map(|v| v * scale), ROWS[row].2))
    })
}

/// The columns each figure gets: the widest one, at least [`VALUE_MIN_WIDTH`].
fn value_width(figures: Option<&[[String; 3]; 6]>) -> usize {
    figures
        .map(|figures| {
            figures
                .iter()
                .flatten()
                .map(|f| text_width(f))
                .max()
                .unwrap_or(0)
        })
        .unwrap_or(0)
        .max(VALUE_MIN_WIDTH)
}

/// The panel's width (borders included), with long labels or unit labels.
pub fn width(view: &View, long_labels: bool) -> u16 {
    let figures = view.arm.telemetry.as_ref().map(figures);
    panel_width(value_width(figures.as_ref()), long_labels)
}

/// The panel's width with figures `value_width` columns wide.
fn panel_width(value_width: usize, long_labels: bool) -> u16 {
    let label = if long_labels { LONG_LABEL } else { SHORT_LABEL };
    u16::try_from(2 + label + 3 * value_width + 2).unwrap_or(u16::MAX)
}

pub fn draw(frame: &mut Frame, area: Rect, view: &View, theme: &Theme) {
    // The fence's nearest face or zone, while the title has room for it.
    let nearest = view
        .arm
        .fence_nearest
        .as_ref()
        .map(|(name, mm)| format!(", {name} {mm:.0} mm"));
    let titles = super::telemetry_titles("Tool (TCP)", &[nearest.as_deref().unwrap_or("")], view);
    let block = super::fitted_panel(&titles, area.width, theme);
    let Some(t) = &view.arm.telemetry else {
        return super::draw_no_telemetry(frame, area, block, view);
    };
    let figures = figures(t);
    let value_w = value_width(Some(&figures));
    let long = area.width >= panel_width(value_w, true);
    let label_w = if long { LONG_LABEL } else { SHORT_LABEL };
    let dim = theme.dim();
    let row = |label: &str, [a, b, c]: &[String; 3]| {
        Line::from(vec![
            Span::styled(format!("{label:<label_w$}"), dim),
            Span::raw(format!("{a:>value_w$} {b:>value_w$} {c:>value_w$}")),
        ])
    };
    // The frame names sit in the label column of the lines above the figures they frame.
    let frame_line = |name: &str, with_axes: bool| {
        let name = if long { name } else { &name[..4] };
        let axes = if with_axes {
            format!("{:>value_w$} {:>value_w$} {:>value_w$}", "x", "y", "z")
        } else {
            String::new()
        };
        Line::styled(format!("{name:<label_w$}{axes}"), dim)
    };
    let label = |i: usize| if long { ROWS[i].0 } else { ROWS[i].1 };
    let mut lines = vec![frame_line("base frame", true)];
    lines.extend((0..4).map(|i| row(label(i), &figures[i])));
    lines.push(frame_line("tool frame", false));
    lines.extend((4..6).map(|i| row(label(i), &figures[i])));
    super::lines::draw(frame.buffer_mut(), area, Some(block), &lines);
    super::grey_if_stale(frame, area, view, theme);
}
