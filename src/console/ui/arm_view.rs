//! The arm view: the arm drawn from its reported joint angles (forward kinematics, see
//! [`arm_geometry`]) on two braille canvases, seen from above (X-Y) and from the side (X-Z).
//!
//! Without telemetry nothing is drawn: a guess would look like the arm. Labels (names) are
//! written after the canvas: one that does not fit is elided, one that would cover another is
//! dropped; none runs past its drawing.

use std::sync::{Arc, LazyLock};

use nalgebra::Vector3;
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::style::{Color, Style};
use ratatui::widgets::{Paragraph, Wrap};

use super::braille::Braille;
use super::numbers;
use super::theme::Theme;
use crate::console::app::MotionShown;
use crate::console::app::TrailShade;
pub use crate::console::arm_geometry::Projection;
use crate::console::arm_geometry::{self, ArmPose, jog_direction};
use crate::console::view::View;
use crate::kortex::Telemetry;
use crate::kortex::sanity::JOINT_ANGLE_DEG;
use crate::link::fence::{Aabb, Fence};
use crate::link::interface::TelemetrySource;

/// What the panel says over a link that sends no telemetry (the ack dialect).
pub const NO_TELEMETRY: &str = "no telemetry on this link: the arm is not drawn";
pub const NOT_FINITE: &str = "a joint angle is not a sane number (?): the arm is not drawn";
pub const WAITING: &str = "waiting for telemetry: the arm is drawn once its joints are known";

/// The fewest columns a drawing is worth drawing in.
pub const MIN_DRAWING_WIDTH: u16 = 16;
/// Columns per row that keep a drawing's proportions (a terminal cell is about twice as tall as
/// it is wide).
const COLUMNS_PER_ROW: f64 = 2.0;
/// The arrow's and the tool axes' lengths, m.
const ARROW_LENGTH: f64 = 0.2;
const AXIS_LENGTH: f64 = 0.1;
/// The base's half width, m.
const BASE_RADIUS: f64 = 0.06;
/// The longest label, columns.
const LABEL_MAX: usize = 14;

/// One drawing: its projection, its place and the world window it shows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drawing {
    pub projection: Projection,
    pub area: Rect,
    pub x_bounds: [f64; 2],
    pub y_bounds: [f64; 2],
}

impl Drawing {
    /// The cell a base-frame point is drawn in (the braille canvas's own rounding), if inside.
    pub fn cell(&self, p: &Vector3<f64>) -> Option<(u16, u16)> {
        let (x, y) = self.projection.project(p);
        let [left, right] = self.x_bounds;
        let [bottom, top] = self.y_bounds;
        if !(left..=right).contains(&x) || !(bottom..=top).contains(&y) {
            return None;
        }
        let dots_x = f64::from(self.area.width) * 2.0 - 1.0;
        let dots_y = f64::from(self.area.height) * 4.0 - 1.0;
        let dot_x = ((x - left) * dots_x / (right - left)).round() as u16;
        let dot_y = ((top - y) * dots_y / (top - bottom)).round() as u16;
        Some((self.area.x + dot_x / 2, self.area.y + dot_y / 4))
    }
}

/// The columns the panel wants at `height` rows to draw both views in proportion.
pub fn wanted_width(height: u16) -> u16 {
    let rows = f64::from(height.saturating_sub(2));
    let drawings: f64 = [Projection::Top, Projection::Side]
        .iter()
        .map(|p| (p.aspect() * rows * COLUMNS_PER_ROW).ceil())
        .sum();
    // Two borders and a column between the drawings.
    drawings as u16 + 3
}

/// Where the two drawings go inside the panel's `inner` area, each with its world window
/// widened to keep the arm's proportions.
pub fn drawings(inner: Rect) -> [Drawing; 2] {
    let [top, side] = [Projection::Top, Projection::Side];
    let usable = inner.width.saturating_sub(1);
    let share = top.aspect() / (top.aspect() + side.aspect());
    let top_width = (f64::from(usable) * share).round() as u16;
    let top_area = Rect {
        width: top_width,
        ..inner
    };
    let side_area = Rect {
        x: inner.x + top_width + 1,
        width: usable - top_width,
        ..inner
    };
    [(top, top_area), (side, side_area)].map(|(projection, area)| {
        let (x_bounds, y_bounds) = fitted_bounds(projection, area);
        Drawing {
            projection,
            area,
            x_bounds,
            y_bounds,
        }
    })
}

/// The projection's window widened in one direction to the area's proportions, centred.
fn fitted_bounds(projection: Projection, area: Rect) -> ([f64; 2], [f64; 2]) {
    let ([l, r], [b, t]) = projection.bounds();
    let columns = f64::from(area.width.max(1));
    let rows = f64::from(area.height.max(1)) * COLUMNS_PER_ROW;
    let (w, h) = (r - l, t - b);
    // Metres per column either way; the larger wins and the other side widens.
    let scale = (w / columns).max(h / rows);
    let extra_w = ((scale * columns - w) / 2.0).max(0.0);
    let extra_h = ((scale * rows - h) / 2.0).max(0.0);
    ([l - extra_w, r + extra_w], [b - extra_h, t + extra_h])
}

/// One saved position on the drawings.
struct Marker3 {
    name: String,
    at: Vector3<f64>,
    selected: bool,
}

/// Everything the drawings show, worked out once for both.
struct Scene {
    pose: ArmPose,
    trail: Vec<(TrailShade, Vector3<f64>)>,
    markers: Vec<Marker3>,
    arrow: Option<Vector3<f64>>,
    /// The arm profile's fence, drawn under the arm.
    fence: Option<Arc<Fence>>,
}

pub fn draw(frame: &mut Frame, area: Rect, view: &View, theme: &Theme) {
    let titles = super::telemetry_titles("Arm view", &[": top X-Y, side X-Z"], view);
    let block = super::fitted_panel(&titles, area.width, theme);
    // An angle out of physical range (1e9 deg) is not drawn as some other angle.
    let sane = |t: &&Telemetry| {
        t.joints
            .iter()
            .all(|j| JOINT_ANGLE_DEG.sane(j.position).is_some())
    };
    let Some(telemetry) = view.arm.telemetry.as_ref().filter(sane) else {
        let text = match view.motion_status.telemetry_source {
            TelemetrySource::None => NO_TELEMETRY,
            _ if view.arm.telemetry.is_some() => NOT_FINITE,
            _ => WAITING,
        };
        let paragraph = Paragraph::new(text)
            .style(theme.dim())
            .block(block)
            .wrap(Wrap { trim: true });
        frame.render_widget(paragraph, area);
        return;
    };
    let inner = block.inner(area);
    frame.render_widget(block, area);
    let position_deg = telemetry.joints.map(|j| j.position);
    let scene = Scene {
        pose: arm_geometry::arm_pose(&position_deg),
        trail: view
            .arm
            .trail
            .iter()
            .map(|(shade, [x, y, z])| (*shade, Vector3::new(*x, *y, *z)))
            .collect(),
        markers: markers(view),
        arrow: match view.motion_status.motion {
            MotionShown::Jog(motion) => {
                let frame = view.session.frames.then_some(view.arm.frame);
                jog_direction(motion, frame, &position_deg)
            }
            _ => None,
        },
        fence: view.session.fence.clone(),
    };
    if inner.width < 2 * MIN_DRAWING_WIDTH + 1 || inner.height < 3 {
        return;
    }
    for drawing in drawings(inner) {
        draw_one(frame, &drawing, &scene, theme);
    }
    super::grey_if_stale(frame, area, view, theme);
}

fn markers(view: &View) -> Vec<Marker3> {
    view.book
        .positions
        .entries()
        .enumerate()
        .filter_map(|(row, (name, entry))| {
            let [x, y, z] = entry.cartesian?.map(|tenths| f64::from(tenths) / 10_000.0);
            Some(Marker3 {
                name: name.to_string(),
                at: Vector3::new(x, y, z),
                selected: row == view.book.selected,
            })
        })
        .collect()
}

/// A colour, or the terminal's own without colour (`NO_COLOR`).
fn paint(theme: &Theme, color: Color) -> Color {
    if theme.color { color } else { Color::Reset }
}

fn draw_one(frame: &mut Frame, drawing: &Drawing, scene: &Scene, theme: &Theme) {
    let projection = drawing.projection;
    let at = |p: &Vector3<f64>| projection.project(p);
    let area = drawing.area;
    let mut ctx = Braille::new(area.width, area.height, drawing.x_bounds, drawing.y_bounds);
    envelope(&mut ctx, projection, theme);
    ctx.layer();
    if let Some(fence) = &scene.fence {
        fence_lines(&mut ctx, projection, fence, &scene.pose.tool(), theme);
        ctx.layer();
    }
    trail(&mut ctx, projection, &scene.trail, theme);
    ctx.layer();
    for marker in &scene.markers {
        let color = if marker.selected {
            Color::Yellow
        } else {
            Color::Cyan
        };
        cross(&mut ctx, at(&marker.at), 0.015, paint(theme, color));
    }
    ctx.layer();
    arm(&mut ctx, projection, &scene.pose, theme);
    ctx.layer();
    if let Some(direction) = scene.arrow {
        arrow(&mut ctx, projection, &scene.pose.tool(), &direction, theme);
    }
    ctx.layer();
    cell_mark(&mut ctx, at(&scene.pose.tool()), paint(theme, TOOL_COLOR));
    ctx.render(area, frame.buffer_mut());
    labels(frame, drawing, scene, theme);
}

/// The tool point's colour: its cell is filled in it (tests find it by it).
pub const TOOL_COLOR: Color = Color::LightMagenta;

/// The fence's box (blue) and zones (red) as rectangles, and the tool's sphere, in metres.
fn fence_lines(
    ctx: &mut Braille,
    projection: Projection,
    fence: &Fence,
    tool: &Vector3<f64>,
    theme: &Theme,
) {
    let rectangle = |ctx: &mut Braille, zone: &Aabb, color: Color| {
        let corner = |c: [f64; 3]| projection.project(&Vector3::from(c.map(|mm| mm / 1000.0)));
        let ((x1, y1), (x2, y2)) = (corner(zone.min), corner(zone.max));
        for (from, to) in [
            ((x1, y1), (x2, y1)),
            ((x2, y1), (x2, y2)),
            ((x2, y2), (x1, y2)),
            ((x1, y2), (x1, y1)),
        ] {
            ctx.line(from, to, color);
        }
    };
    if let Some(inside) = &fence.inside {
        rectangle(ctx, inside, paint(theme, Color::Blue));
    }
    for zone in fence.zones() {
        rectangle(ctx, &zone.zone, paint(theme, Color::LightRed));
    }
    if fence.tool_radius > 0.0 {
        let radius = fence.tool_radius / 1000.0;
        ctx.circle(projection.project(tool), radius, paint(theme, TOOL_COLOR));
    }
}

fn envelope(ctx: &mut Braille, projection: Projection, theme: &Theme) {
    let grey = paint(theme, Color::DarkGray);
    let reach = arm_geometry::reach();
    let shoulder = arm_geometry::shoulder();
    let (cx, cy) = projection.project(&shoulder);
    // From the side, only the part above the table: the arm cannot reach below it.
    let arc: Vec<(f64, f64)> = ENVELOPE_TURN
        .iter()
        .map(|(cos, sin)| (cx + reach * cos, cy + reach * sin))
        .collect();
    for pair in arc.windows(2) {
        let [(x1, y1), (x2, y2)] = [pair[0], pair[1]];
        if projection == Projection::Side && y1.min(y2) < 0.0 {
            continue;
        }
        ctx.line((x1, y1), (x2, y2), grey);
    }
    if projection == Projection::Side {
        // The table, as far as the envelope meets it.
        let x = (reach * reach - cy * cy).max(0.0).sqrt();
        ctx.line((-x, 0.0), (x, 0.0), grey);
    }
}

/// Straight pieces of the reach envelope's circle.
const ENVELOPE_SEGMENTS: u16 = 96;

/// The cosine and sine of the envelope's corners, a whole turn: worked out once, not per frame.
static ENVELOPE_TURN: LazyLock<Vec<(f64, f64)>> = LazyLock::new(|| {
    (0..=ENVELOPE_SEGMENTS)
        .map(|i| {
            let angle = std::f64::consts::TAU * f64::from(i) / f64::from(ENVELOPE_SEGMENTS);
            (angle.cos(), angle.sin())
        })
        .collect()
});

fn trail(
    ctx: &mut Braille,
    projection: Projection,
    points: &[(TrailShade, Vector3<f64>)],
    theme: &Theme,
) {
    for pair in points.windows(2) {
        let (age, to) = pair[1];
        let color = paint(theme, shade(age));
        let (from, to) = (projection.project(&pair[0].1), projection.project(&to));
        ctx.line(from, to, color);
    }
}

/// A trail piece's colour by its age: three shades, the newest third brightest.
fn shade(age: TrailShade) -> Color {
    match age {
        TrailShade::New => Color::White,
        TrailShade::Mid => Color::Gray,
        TrailShade::Old => Color::DarkGray,
    }
}

fn arm(ctx: &mut Braille, projection: Projection, pose: &ArmPose, theme: &Theme) {
    let at = |p: &Vector3<f64>| projection.project(p);
    // The base: a disc from above, a block on the table from the side.
    let base = paint(theme, Color::Gray);
    match projection {
        Projection::Top => ctx.circle((0.0, 0.0), BASE_RADIUS, base),
        Projection::Side => {
            for x in [-BASE_RADIUS, BASE_RADIUS] {
                ctx.line((x, 0.0), (x, 0.1), base);
            }
            ctx.line((-BASE_RADIUS, 0.1), (BASE_RADIUS, 0.1), base);
        }
    }
    let link = paint(theme, Color::White);
    for pair in pose.points.windows(2) {
        ctx.line(at(&pair[0]), at(&pair[1]), link);
    }
    ctx.layer();
    let joint = paint(theme, Color::LightBlue);
    for point in &pose.points[1..8] {
        cross(ctx, at(point), 0.012, joint);
    }
    ctx.layer();
    let colors = [Color::Red, Color::Green, Color::Blue];
    for (axis, color) in pose.tool_axes.iter().zip(colors) {
        let end = at(&(pose.tool() + axis * AXIS_LENGTH));
        ctx.line(at(&pose.tool()), end, paint(theme, color));
    }
}

fn arrow(
    ctx: &mut Braille,
    projection: Projection,
    tool: &Vector3<f64>,
    direction: &Vector3<f64>,
    theme: &Theme,
) {
    let color = paint(theme, Color::Yellow);
    let (x1, y1) = projection.project(tool);
    let (x2, y2) = projection.project(&(tool + direction * ARROW_LENGTH));
    let (dx, dy) = (x2 - x1, y2 - y1);
    let length = dx.hypot(dy);
    // Along the line of sight the arrow has no length here: the other drawing shows it.
    if length < 0.02 {
        return;
    }
    ctx.line((x1, y1), (x2, y2), color);
    let head = ARROW_LENGTH * 0.3;
    let angle = dy.atan2(dx);
    for turn in [2.6_f64, -2.6] {
        let (s, c) = (angle + turn).sin_cos();
        ctx.line((x2, y2), (x2 + head * c, y2 + head * s), color);
    }
}

/// A point and its four neighbours `d` away: a small cross.
fn cross(ctx: &mut Braille, (x, y): (f64, f64), d: f64, color: Color) {
    let dots = [(x, y), (x - d, y), (x + d, y), (x, y - d), (x, y + d)];
    ctx.points(&dots, color);
}

/// A whole braille cell filled at a point: the tool point stands out from the lines through it.
fn cell_mark(ctx: &mut Braille, (x, y): (f64, f64), color: Color) {
    let Some((x, y)) = ctx.dot(x, y) else {
        return;
    };
    let (left, top) = (x / 2 * 2, y / 4 * 4);
    for dx in 0..2 {
        for dy in 0..4 {
            ctx.paint(left + dx, top + dy, color);
        }
    }
}

/// The drawing's name in its top left corner, then the markers' names beside them (the
/// selected one first); a name that would cover another is left out.
fn labels(frame: &mut Frame, drawing: &Drawing, scene: &Scene, theme: &Theme) {
    let area = drawing.area;
    let caption = match drawing.projection {
        Projection::Top => "top",
        Projection::Side => "side",
    };
    let mut taken: Vec<(u16, u16, u16)> = Vec::new();
    // The tool point is never covered (a label may start right after it).
    if let Some((x, y)) = drawing.cell(&scene.pose.tool()) {
        taken.push((y, x, x));
    }
    let mut put = |frame: &mut Frame, x: u16, y: u16, text: &str, style: Style| {
        let room = usize::from(area.right().saturating_sub(x));
        let text = numbers::elide_name(text, room.min(LABEL_MAX));
        let width = numbers::width(&text) as u16;
        // A column kept between two labels, so that two names never read as one.
        let near = |&(row, from, to): &(u16, u16, u16)| row == y && x <= to && from <= x + width;
        if width == 0 || taken.iter().any(near) {
            return;
        }
        taken.push((y, x, x + width));
        frame.buffer_mut().set_string(x, y, &text, style);
    };
    put(frame, area.x, area.y, caption, theme.dim());
    let mut order: Vec<&Marker3> = scene.markers.iter().collect();
    order.sort_by_key(|m| !m.selected);
    for marker in order {
        let Some((x, y)) = drawing.cell(&marker.at) else {
            continue;
        };
        let style = if marker.selected {
            theme.selected()
        } else {
            theme.accent()
        };
        put(frame, x + 1, y, &marker.name, style);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn the_trail_fades_with_age() {
        let shade_at = |age| shade(TrailShade::of(age));
        assert_eq!(shade_at(Duration::from_millis(100)), Color::White);
        assert_eq!(shade_at(Duration::from_secs(5)), Color::Gray);
        assert_eq!(shade_at(Duration::from_millis(9900)), Color::DarkGray);
    }

    #[test]
    fn the_drawings_keep_the_arm_in_proportion() {
        for (width, height) in [(84, 17), (114, 23), (40, 10)] {
            for d in drawings(Rect::new(1, 1, width, height)) {
                // Metres per column the same both ways, a row counting two columns.
                let per_column = (d.x_bounds[1] - d.x_bounds[0]) / f64::from(d.area.width);
                let per_row = (d.y_bounds[1] - d.y_bounds[0]) / f64::from(d.area.height);
                assert!((per_row / per_column - COLUMNS_PER_ROW).abs() < 1e-9);
                // The whole window of the projection is inside.
                let ([l, r], [b, t]) = d.projection.bounds();
                assert!(d.x_bounds[0] <= l && d.x_bounds[1] >= r);
                assert!(d.y_bounds[0] <= b && d.y_bounds[1] >= t);
            }
        }
    }
}
