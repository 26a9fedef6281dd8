//! The arm panel: robot state, faults and warnings by name, arm health and speed limits.

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Wrap};

use super::numbers::{fixed, fixed_or_unknown};
use super::theme::Theme;
use crate::console::view::View;
use crate::kortex::{Coded, RobotState, sanity};

pub fn draw(frame: &mut Frame, area: Rect, view: &View, theme: &Theme) {
    let titles = super::telemetry_titles("Arm", &[], view);
    let block = super::fitted_panel(&titles, area.width, theme);
    let Some(t) = &view.arm.telemetry else {
        return super::draw_no_telemetry(frame, area, block, view);
    };
    let in_fault = matches!(t.robot_state, Coded::Known(RobotState::InFault));
    let state_style = match t.robot_state {
        _ if in_fault => theme.alarm(),
        // A number the ICD does not list shows as itself: `unknown (65535)`.
        Coded::Unknown(_) => theme.warning(),
        Coded::Known(_) => theme.ok(),
    };
    let mut lines = vec![Line::from(vec![
        Span::styled("state ", theme.dim()),
        Span::styled(format!(" {} ", t.robot_state), state_style),
    ])];
    // Values out of physical range show as `?` in every panel; this line names them.
    let insane = t.insane_fields();
    if let Some(first) = insane.first() {
        let more = match insane.len() {
            1 => String::new(),
            n => format!(" (+{} more)", n - 1),
        };
        lines.push(Line::from(vec![
            Span::styled("NONSENSE ", theme.alarm()),
            Span::styled(format!("{first}{more}"), theme.warning()),
        ]));
    }
    let none = |label| Line::from(vec![Span::styled(label, theme.dim()), Span::raw("none")]);
    let (faults, warnings) = (t.faults.names().join(", "), t.warnings.names().join(", "));
    lines.push(match faults.is_empty() {
        true => none("faults "),
        false => Line::from(vec![
            Span::styled("FAULTS ", theme.alarm()),
            Span::styled(format!(" {faults}"), theme.warning()),
        ]),
    });
    lines.push(match warnings.is_empty() {
        true => none("warnings "),
        false => Line::from(vec![
            Span::styled("warnings ", theme.warning()),
            Span::raw(warnings),
        ]),
    });
    // A figure and its unit, and a name and its figure, are joined by no-break spaces: a
    // narrow panel wraps between them, not inside.
    // The wide lines take 50 columns; the left-hand panel at 80 columns has 42 inside, where
    // a wrapped line would push the last one out of the panel.
    let narrow = area.width < 50 + 2;
    let (power, ambient) = if narrow {
        ("", "amb")
    } else {
        ("power ", "ambient")
    };
    lines.push(Line::from(vec![
        Span::styled(power, theme.dim()),
        Span::raw(format!(
            "{}\u{a0}V {}\u{a0}A  cpu\u{a0}{}\u{a0}C  {ambient}\u{a0}{}\u{a0}C",
            fixed_or_unknown(sanity::VOLTAGE_V.sane(t.arm.voltage), 1),
            fixed_or_unknown(sanity::CURRENT_A.sane(t.arm.current), 2),
            fixed_or_unknown(sanity::TEMPERATURE_C.sane(t.arm.cpu_temperature), 1),
            fixed_or_unknown(sanity::TEMPERATURE_C.sane(t.arm.ambient_temperature), 1)
        )),
    ]));
    let action = if narrow {
        format!("action {}", t.action.status.key())
    } else {
        format!("action {} #{}", t.action.status, t.action.id)
    };
    lines.push(Line::from(vec![
        Span::styled(if narrow { "max " } else { "limits " }, theme.dim()),
        Span::raw(format!(
            "{}\u{a0}mm/s {}\u{a0}deg/s  {action}",
            fixed(t.speed_limits.linear * 1000.0, 0),
            fixed(t.speed_limits.angular, 0),
        )),
    ]));
    frame.render_widget(
        Paragraph::new(lines).block(block).wrap(Wrap { trim: true }),
        area,
    );
    super::grey_if_stale(frame, area, view, theme);
}
