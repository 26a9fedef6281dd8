//! The history panel: sparklines of the last 30 s, a bucket per column, of the TCP speed and
//! each joint's torque or current (docs/user-guide.md, "History and joint limits"). Numbers are
//! never cut: the sparkline gives way first, then the speed's peak.

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};

use super::numbers::{self, fixed};
use super::theme::Theme;
use crate::console::action::Action;
use crate::console::view::View;

/// Sparkline levels, lowest first.
const LEVELS: [char; 8] = ['▁', '▂', '▃', '▄', '▅', '▆', '▇', '█'];
/// The row label's width (`TCP `, `J1  `).
const LABEL: usize = 4;
/// Fewer sparkline columns than this say nothing: the values show alone.
const MIN_SPARK: usize = 4;
/// The hardest joint's marker, after its value.
const HARDEST: &str = " ◀";

/// The last `width` values of `values` as sparkline characters scaled to `max`.
pub fn sparkline(values: &[Option<f64>], max: f64, width: usize) -> String {
    let start = values.len().saturating_sub(width);
    let shown = &values[start..];
    let pad = width.saturating_sub(shown.len());
    let bars = shown.iter().map(|v| match v {
        None => ' ',
        // A bucket holding a value out of physical range: not known.
        Some(v) if !v.is_finite() => '?',
        Some(v) if max > 0.0 => {
            let level = (v / max * (LEVELS.len() - 1) as f64).round();
            LEVELS[(level.max(0.0) as usize).min(LEVELS.len() - 1)]
        }
        Some(_) => LEVELS[0],
    });
    std::iter::repeat_n(' ', pad).chain(bars).collect()
}

fn peak(values: &[Option<f64>]) -> f64 {
    values
        .iter()
        .flatten()
        .copied()
        .filter(|v| v.is_finite())
        .fold(0.0, f64::max)
}

/// The keys bound to cycling the plotted quantity, for the heading.
fn cycle_keys(view: &View) -> Option<String> {
    let keys: Vec<String> = view
        .session
        .keymap
        .keys_for(Action::HistoryCycle)
        .into_iter()
        .map(|k| k.to_string())
        .collect();
    (!keys.is_empty()).then(|| keys.join("/"))
}

/// The joints' heading, the longest that fits `width`: what is plotted, who works hardest (and
/// how hard), which key plots the other quantity.
fn heading(view: &View, width: usize) -> String {
    let history = &view.arm.history;
    let quantity = history.quantity;
    let (name, unit) = (quantity.name(), quantity.unit());
    let hardest = history.hardest.map(|(joint, mean)| (joint, fixed(mean, 2)));
    let keys = cycle_keys(view)
        .map(|keys| format!(", {keys}: {}", quantity.next().name()))
        .unwrap_or_default();
    let candidates: Vec<String> = match hardest {
        Some((joint, mean)) => vec![
            format!("|{name}| {unit}, hardest J{joint} (mean {mean}){keys}"),
            format!("{name} {unit}, hardest J{joint} (mean {mean}){keys}"),
            format!("{name} {unit}, hardest J{joint} {mean}{keys}"),
            format!("{name} {unit}, hardest J{joint}{keys}"),
            format!("{name} {unit}, hardest J{joint} {mean}"),
            format!("{name} {unit}, hardest J{joint}"),
        ],
        None => vec![format!("|{name}| {unit}{keys}"), format!("{name} {unit}")],
    };
    numbers::first_fitting(&candidates, width)
}

pub fn draw(frame: &mut Frame, area: Rect, view: &View, theme: &Theme) {
    let titles = super::telemetry_titles("History", &[", last 30 s"], view);
    let block = super::fitted_panel(&titles, area.width, theme);
    if view.arm.telemetry.is_none() {
        return super::draw_no_telemetry(frame, area, block, view);
    }
    let inner = block.inner(area);
    let width = usize::from(inner.width);
    let history = &view.arm.history;
    let mut lines = Vec::with_capacity(9);

    // The TCP speed: the latest value, then the window's peak where it fits.
    let speed_peak = peak(&history.speed);
    let now = numbers::fixed_or_unknown(Some(history.speed_now.unwrap_or(0.0)), 1);
    let long = format!(" {now} mm/s, peak {}", fixed(speed_peak, 1));
    let short = format!(" {now} mm/s");
    let value = [long, short]
        .into_iter()
        .find(|v| LABEL + MIN_SPARK + numbers::width(v) <= width)
        .unwrap_or_else(|| format!(" {now}"));
    let spark = width.saturating_sub(LABEL + numbers::width(&value));
    lines.push(Line::from(vec![
        Span::styled("TCP ", theme.title()),
        Span::styled(sparkline(&history.speed, speed_peak, spark), theme.accent()),
        Span::raw(value),
    ]));

    // The joints' heading: what is plotted, how to change it, who works hardest.
    lines.push(Line::styled(heading(view, width), theme.dim()));

    // One row per joint, on one scale.
    let joints_peak = history.joints.iter().map(|j| peak(j)).fold(0.0, f64::max);
    let latest: Vec<String> = history
        .joints
        .iter()
        .map(|j| {
            let latest = j.iter().rev().flatten().next().copied().unwrap_or(0.0);
            numbers::fixed_or_unknown(Some(latest), 2)
        })
        .collect();
    let value_width = latest.iter().map(|v| numbers::width(v)).max().unwrap_or(0);
    let tail = 1 + value_width + numbers::width(HARDEST);
    let spark = width.saturating_sub(LABEL + tail);
    for (i, series) in history.joints.iter().enumerate() {
        let joint = i as u8 + 1;
        let hardest = history.hardest.is_some_and(|(j, _)| j == joint);
        let marker = if hardest { HARDEST } else { "  " };
        let label_style = if hardest {
            theme.warning()
        } else {
            theme.title()
        };
        lines.push(Line::from(vec![
            Span::styled(format!("{:<LABEL$}", format!("J{joint}")), label_style),
            Span::styled(sparkline(series, joints_peak, spark), theme.accent()),
            Span::raw(format!(" {:>value_width$}", latest[i])),
            Span::styled(marker, theme.warning()),
        ]));
    }
    super::lines::draw(frame.buffer_mut(), area, Some(block), &lines);
    super::grey_if_stale(frame, area, view, theme);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sparkline_scales_to_its_peak_and_keeps_the_newest_columns() {
        let values = [Some(0.0), Some(5.0), None, Some(10.0)];
        assert_eq!(sparkline(&values, 10.0, 4), "▁▅ █");
        assert_eq!(sparkline(&values, 10.0, 2), " █");
        assert_eq!(sparkline(&values, 10.0, 6), "  ▁▅ █");
        assert_eq!(sparkline(&values, 0.0, 1), "▁");
        assert_eq!(sparkline(&[Some(f64::NAN), Some(10.0)], 10.0, 2), "?█");
    }
}
