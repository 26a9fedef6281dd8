//! The lines of the `v` dialog: everything known about one named position, with units. Over
//! Talos the coordinates are the operator's answer; the orientation, joint angles and frame are
//! what the console remembered when the pose was saved.

use ratatui::text::Line;

use super::numbers::fixed;
use super::theme::Theme;
use crate::console::coords::polar_of;
use crate::console::positions::BookEntry;
use crate::console::view::View;
use crate::link::interface::PositionCoordinates;

/// Label column width, so the values line up.
const LABEL: usize = 13;

pub fn lines(
    view: &View,
    name: &str,
    coordinates: Option<&PositionCoordinates>,
    theme: &Theme,
) -> Vec<Line<'static>> {
    let entry = view.book.positions.get(name);
    let mut lines = Vec::new();
    let Some(c) = coordinates else {
        lines.push(Line::styled("asking the operator...", theme.dim()));
        return lines;
    };
    let frame = entry.map_or("base frame", |e| e.frame.label());
    lines.push(row(
        "cartesian",
        match c.cartesian {
            Some(xyz) => format!("{}  ({frame})", cartesian_text(xyz)),
            None => "unknown".into(),
        },
    ));
    lines.push(row(
        "polar",
        match c.polar.or(c.cartesian.map(polar_of)) {
            Some(polar) => {
                let [d, a, r] = polar.map(|v| fixed(tenths(v), 1));
                format!("elevation {d}  azimuth {a} deg  radius {r} mm")
            }
            None => "unknown".into(),
        },
    ));
    let Some(entry) = entry else {
        return lines;
    };
    remembered_lines(entry, c, &mut lines);
    lines
}

/// The book's part: the remembered place when the operator's differs, orientation, joints,
/// parent.
fn remembered_lines(entry: &BookEntry, c: &PositionCoordinates, lines: &mut Vec<Line<'static>>) {
    if let Some(xyz) = entry.cartesian
        && c.cartesian.is_some_and(|now| now != xyz)
    {
        lines.push(row("remembered", cartesian_text(xyz)));
    }
    lines.push(row(
        "orientation",
        match entry.orientation {
            Some(angles) => {
                let [x, y, z] = angles.map(|v| fixed(f64::from(v), 2));
                format!("θx {x}  θy {y}  θz {z} deg")
            }
            None => "unknown".into(),
        },
    ));
    match entry.joints {
        Some(joints) => {
            let joint = |i: usize| {
                let angle = about_zero(f64::from(joints[i]));
                format!("J{} {}", i + 1, fixed(angle, 2))
            };
            let first: Vec<String> = (0..4).map(joint).collect();
            let rest: Vec<String> = (4..7).map(joint).collect();
            lines.push(row("joints", format!("{}  deg", first.join("  "))));
            lines.push(row("", format!("{}  deg (-180 to 180)", rest.join("  "))));
        }
        None => lines.push(row("joints", "not recorded".into())),
    }
    if let Some(parent) = &entry.parent {
        let how = if entry.anchor { ", anchored" } else { "" };
        lines.push(row("parent", format!("{parent}{how}")));
    }
}

fn row(label: &str, value: String) -> Line<'static> {
    Line::raw(format!("{label:<LABEL$}{value}"))
}

fn cartesian_text(xyz: [i32; 3]) -> String {
    let [x, y, z] = xyz.map(|v| fixed(tenths(v), 1));
    format!("x {x}  y {y}  z {z} mm")
}

fn tenths(value: i32) -> f64 {
    f64::from(value) / 10.0
}

/// A reported angle (0 to 360 degrees) as a technician reads it: -0.5, not 359.5.
///
/// In f64, unlike [`crate::kortex::gen3::signed_deg`] (f32): for a negative angle in a book the
/// two round differently (-127.975 reads -127.97 here, -127.98 there).
fn about_zero(degrees: f64) -> f64 {
    let turned = degrees.rem_euclid(360.0);
    if turned > 180.0 {
        turned - 360.0
    } else {
        turned
    }
}

#[cfg(test)]
mod tests {
    use super::{about_zero, fixed};

    #[test]
    fn no_negative_zero() {
        assert_eq!(fixed(-0.001, 2), "0.00");
        assert_eq!(fixed(-0.01, 2), "-0.01");
        assert_eq!(fixed(359.66, 2), "359.66");
        assert_eq!(fixed(about_zero(359.66), 2), "-0.34");
        assert_eq!(fixed(about_zero(180.0), 2), "180.00");
        assert_eq!(fixed(about_zero(230.0), 2), "-130.00");
    }
}
