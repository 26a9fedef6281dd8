//! The command log: every request and reply with id, name, outcome and latency; frames in hex
//! when toggled (formatted here from the raw bytes and writes the driver logs).

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};

use super::numbers;
use super::theme::Theme;
use crate::console::view::View;
use crate::link::interface::Traffic;
use crate::talos::hex::spaced_hex;

pub fn draw(frame: &mut Frame, area: Rect, app: &View, theme: &Theme) {
    let title = if app.screen.hex {
        "Command log (hex)"
    } else {
        "Command log"
    };
    let block = super::panel(title, theme);
    let rows = usize::from(area.height.saturating_sub(2));
    let width = usize::from(area.width.saturating_sub(2));
    let mut lines: Vec<Line> = Vec::new();
    for entry in app.screen.log.iter().rev() {
        let id = match entry.id {
            Some(id) => format!("{id:>6} "),
            None => "     - ".into(),
        };
        let name = format!("{:<14} ", entry.name);
        let outcome = if entry.count > 1 {
            format!("{} x{}", entry.outcome, entry.count)
        } else {
            entry.outcome.clone()
        };
        let latency = match entry.latency {
            Some(l) => format!(" {} ms", numbers::fixed(l.as_secs_f64() * 1000.0, 1)),
            None => String::new(),
        };
        // Too wide: the latency goes, then the outcome is elided (never inside a number).
        let room = width.saturating_sub(numbers::width(&id) + numbers::width(&name));
        let (outcome, latency) = if numbers::width(&outcome) + numbers::width(&latency) <= room {
            (outcome, latency)
        } else {
            (numbers::elide(&outcome, room), String::new())
        };
        let outcome_style = if entry.ok {
            theme.ok()
        } else {
            theme.warning()
        };
        let mut entry_lines = vec![Line::from(vec![
            Span::styled(id, theme.dim()),
            Span::raw(name),
            Span::styled(outcome, outcome_style),
            Span::styled(latency, theme.dim()),
        ])];
        if app.screen.hex {
            for text in traffic_lines(&entry.traffic) {
                entry_lines.push(Line::styled(numbers::elide(&text, width), theme.dim()));
            }
        }
        // Newest at the bottom: collect newest first, then reverse.
        lines.extend(entry_lines.into_iter().rev());
        if lines.len() >= rows {
            break;
        }
    }
    lines.truncate(rows);
    lines.reverse();
    super::lines::draw(frame.buffer_mut(), area, Some(block), &lines);
}

/// The lines under a log entry in hex mode: a Talos request (`>`) and its reply (`<`) as hex
/// bytes; a Modbus command's writes on one line, in order.
pub fn traffic_lines(traffic: &Traffic) -> Vec<String> {
    match traffic {
        Traffic::None => Vec::new(),
        Traffic::Talos { request, reply } => {
            let mut lines = vec![format!("  > {}", spaced_hex(request))];
            if let Some(reply) = reply {
                lines.push(format!("  < {}", spaced_hex(reply)));
            }
            lines
        }
        Traffic::Modbus(writes) if writes.is_empty() => Vec::new(),
        Traffic::Modbus(writes) => {
            let writes: Vec<String> = writes.iter().map(ToString::to_string).collect();
            vec![format!("  > {}", writes.join("; "))]
        }
    }
}
