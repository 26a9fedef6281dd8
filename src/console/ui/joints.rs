//! The joints panel: position (against limits), velocity, torque, current and temperature of
//! all seven joints.
//!
//! Angles read in (−180, 180] ([`numbers`](super::numbers)), as the title says. A panel too
//! narrow for every column drops whole columns, the least needed first (`BY_PRIORITY`).

use ratatui::Frame;
use ratatui::layout::{Constraint, Rect};
use ratatui::style::Style;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Cell, Row, Table};

use super::numbers::{NOT_KNOWN, fixed_or_unknown, width as text_width};
use super::theme::Theme;
use crate::console::view::View;
use crate::kortex::gen3::{JOINT_LIMITS_DEG, limit_margin, signed_deg as signed_angle};
use crate::kortex::{Telemetry, sanity};

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
const GAUGE_WIDTH: usize = 11;
/// How the title states the angle convention, longest first.
const CONVENTION: [&str; 2] = [", deg in (-180, 180]", " (-180, 180]"];

/// The columns, in the order they give way last to first: name, position, velocity, torque,
/// current, temperature, limits gauge.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Column {
    Name,
    Position,
    Velocity,
    Torque,
    Current,
    Temperature,
    Gauge,
}

const BY_PRIORITY: [Column; 7] = [
    Column::Name,
    Column::Position,
    Column::Velocity,
    Column::Torque,
    Column::Current,
    Column::Temperature,
    Column::Gauge,
];
const ON_SCREEN: [Column; 7] = [
    Column::Name,
    Column::Position,
    Column::Gauge,
    Column::Velocity,
    Column::Torque,
    Column::Current,
    Column::Temperature,
];

/// The columns counted for the layout: name, position, velocity and torque.
pub const COMFORTABLE_COLUMNS: usize = 4;
/// The fewest columns the panel shows: name and position.
pub const MIN_COLUMNS: usize = 2;

impl Column {
    fn header(self, wide: bool) -> &'static str {
        match (self, wide) {
            (Column::Name, _) => "",
            (Column::Position, true) => "pos deg",
            (Column::Position, false) => "pos",
            (Column::Gauge, _) => "limits",
            (Column::Velocity, true) => "vel deg/s",
            (Column::Velocity, false) => "vel",
            (Column::Torque, true) => "torque Nm",
            (Column::Torque, false) => "Nm",
            (Column::Current, true) => "cur A",
            (Column::Current, false) => "A",
            (Column::Temperature, true) => "temp C",
            (Column::Temperature, false) => "C",
        }
    }

    fn text(self, t: &Telemetry, i: usize) -> String {
        let j = &t.joints[i];
        // A value out of physical range shows as `?`, never as a number.
        let position = sanity::JOINT_ANGLE_DEG.sane(j.position);
        match self {
            Column::Name => format!("J{}", i + 1),
            Column::Position => fixed_or_unknown(position.map(signed_angle), 2),
            Column::Gauge => match (limit(i), position) {
                (Some(l), Some(p)) => gauge(p, l, GAUGE_WIDTH),
                (Some(_), None) => NOT_KNOWN.into(),
                (None, _) => "continuous".into(),
            },
            Column::Velocity => fixed_or_unknown(sanity::JOINT_SPEED_DEG_S.sane(j.velocity), 2),
            Column::Torque => fixed_or_unknown(sanity::JOINT_TORQUE_NM.sane(j.torque), 2),
            Column::Current => fixed_or_unknown(sanity::CURRENT_A.sane(j.current), 2),
            Column::Temperature => fixed_or_unknown(sanity::TEMPERATURE_C.sane(j.temperature), 1),
        }
    }

    /// The column's width: its widest entry or heading. Numbers get at least 4 columns so a
    /// column does not jump at every change of sign.
    fn width(self, entries: &EntryWidths, wide: bool) -> usize {
        let entries = entries.0[self as usize];
        let floor = match self {
            Column::Name => 2,
            Column::Gauge => GAUGE_WIDTH,
            Column::Position => 7,
            _ => 4,
        };
        entries.max(text_width(self.header(wide))).max(floor)
    }

    fn right_aligned(self) -> bool {
        !matches!(self, Column::Name | Column::Gauge)
    }
}

/// "-----|-----" gauge of a limited joint's position between its limits.
fn gauge(position: f32, limit: f32, width: usize) -> String {
    let fraction = ((signed_angle(position) + limit) / (2.0 * limit)).clamp(0.0, 1.0);
    let at = ((fraction * (width.saturating_sub(1)) as f32).round() as usize).min(width - 1);
    (0..width)
        .map(|i| if i == at { '|' } else { '-' })
        .collect()
}

/// Each column's widest entry (by `Column as usize`), worked out once for every layout tried.
struct EntryWidths([usize; BY_PRIORITY.len()]);

impl EntryWidths {
    fn of(t: Option<&Telemetry>) -> EntryWidths {
        let mut widths = [0; BY_PRIORITY.len()];
        if let Some(t) = t {
            for column in BY_PRIORITY {
                widths[column as usize] = (0..t.joints.len())
                    .map(|i| text_width(&column.text(t, i)))
                    .max()
                    .unwrap_or(0);
            }
        }
        EntryWidths(widths)
    }
}

/// The table's width (borders included) with `columns`, `spacing` columns apart.
fn table_width(entries: &EntryWidths, columns: &[Column], wide: bool, spacing: usize) -> usize {
    let cells: usize = columns.iter().map(|c| c.width(entries, wide)).sum();
    cells + spacing * columns.len().saturating_sub(1) + 2
}

/// The panel's width (borders included) with its `columns` most needed columns and short
/// headings.
pub fn width(view: &View, columns: usize) -> u16 {
    let columns = &BY_PRIORITY[..columns.clamp(MIN_COLUMNS, BY_PRIORITY.len())];
    let entries = EntryWidths::of(view.arm.telemetry.as_ref());
    u16::try_from(table_width(&entries, columns, false, 1)).unwrap_or(u16::MAX)
}

/// The most columns that fit `width`, in screen order; then, where they fit too, two columns
/// between them and wide headings (headings one column apart run together).
fn choose_columns(entries: &EntryWidths, width: u16) -> (Vec<Column>, bool, u16) {
    for count in (MIN_COLUMNS..=BY_PRIORITY.len()).rev() {
        let kept = &BY_PRIORITY[..count];
        for (wide, spacing) in [(true, 2), (false, 2), (true, 1), (false, 1)] {
            if table_width(entries, kept, wide, spacing) <= usize::from(width) {
                let shown = ON_SCREEN.into_iter().filter(|c| kept.contains(c)).collect();
                return (shown, wide, spacing as u16);
            }
        }
    }
    (vec![Column::Name, Column::Position], false, 1)
}

pub fn draw(frame: &mut Frame, area: Rect, view: &View, theme: &Theme) {
    let titles = super::telemetry_titles("Joints", &CONVENTION, view);
    let block = super::fitted_panel(&titles, area.width, theme);
    let Some(t) = &view.arm.telemetry else {
        return super::draw_no_telemetry(frame, area, block, view);
    };
    let entries = EntryWidths::of(Some(t));
    let (columns, wide, spacing) = choose_columns(&entries, area.width);
    let cell = |column: Column, text: String, style: Style| {
        let line = Line::from(Span::styled(text, style));
        Cell::from(if column.right_aligned() {
            line.right_aligned()
        } else {
            line
        })
    };
    let header: Vec<Cell> = columns
        .iter()
        .map(|c| cell(*c, c.header(wide).to_string(), Style::default()))
        .collect();
    let rows = (0..t.joints.len()).map(|i| {
        let position = t.joints[i].position;
        let near = limit_margin(i, position).is_some_and(|m| m < NEAR_LIMIT);
        let selected = usize::from(view.keys.joint) == i + 1;
        // Within 5 degrees the gauge turns to the warning colour (the status bar names it).
        let gauge_warns = view
            .arm
            .near_limits
            .iter()
            .any(|n| usize::from(n.joint) == i + 1);
        let cells: Vec<Cell> = columns
            .iter()
            .map(|c| {
                let style = match c {
                    Column::Name if selected => theme.selected(),
                    Column::Name => theme.title(),
                    Column::Position if near => theme.warning(),
                    Column::Gauge if gauge_warns => theme.warning(),
                    _ => Style::default(),
                };
                cell(*c, c.text(t, i), style)
            })
            .collect();
        Row::new(cells)
    });
    let widths: Vec<Constraint> = columns
        .iter()
        .map(|c| Constraint::Length(u16::try_from(c.width(&entries, wide)).unwrap_or(u16::MAX)))
        .collect();
    let table = Table::new(rows, widths)
        .column_spacing(spacing)
        .header(Row::new(header).style(theme.dim()))
        .block(block);
    frame.render_widget(table, area);
    super::grey_if_stale(frame, area, view, theme);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_gauge_places_a_limited_joint_between_its_limits() {
        assert_eq!(gauge(0.0, 100.0, 11), "-----|-----");
        assert_eq!(gauge(359.0, 100.0, 11), "-----|-----");
        assert_eq!(gauge(260.0, 100.0, 11), "|----------");
        assert_eq!(gauge(100.0, 100.0, 11), "----------|");
    }
}
