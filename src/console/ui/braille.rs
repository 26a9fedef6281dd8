//! Braille drawings: the dots ratatui's `Canvas` with `Marker::Braille` draws, in the same
//! cells and colours, at a fraction of its cost.
//!
//! ratatui's canvas walks every cell of every layer into the buffer (the arm view's drawings
//! have eight layers each); here a layer only touches the cells it painted, and the buffer is
//! written once. The tests hold it to ratatui's canvas.

use std::sync::LazyLock;

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::Color;
use ratatui::symbols::braille::BRAILLE;

const DOTS_ACROSS: usize = 2;
const DOTS_DOWN: usize = 4;

/// The cosine and sine of every whole degree, worked out once (a circle is 360 dots).
static DEGREES: LazyLock<Vec<(f64, f64)>> = LazyLock::new(|| {
    (0..360)
        .map(|degrees| f64::from(degrees).to_radians().sin_cos())
        .map(|(sin, cos)| (cos, sin))
        .collect()
});

/// One cell's dots (bit `x + 2 * y` for the dot in column `x`, row `y`) and their colour.
#[derive(Debug, Clone, Copy, Default)]
struct Dots {
    pattern: u8,
    color: Option<Color>,
}

/// A drawing on braille dots over a world window, in layers: a cell painted in a layer shows
/// that layer's dots and colour alone, over whatever the layers below it painted there.
#[derive(Debug)]
pub struct Braille {
    width: usize,
    x_bounds: [f64; 2],
    y_bounds: [f64; 2],
    /// Dots across and down.
    resolution: (f64, f64),
    /// What the layers below the current one show.
    below: Vec<Dots>,
    layer: Vec<Dots>,
    /// The cells the current layer painted, each once.
    painted: Vec<usize>,
}

impl Braille {
    /// A blank drawing `width` x `height` cells showing the world window given by the bounds
    /// (x left to right, y bottom to top).
    pub fn new(width: u16, height: u16, x_bounds: [f64; 2], y_bounds: [f64; 2]) -> Braille {
        let cells = usize::from(width) * usize::from(height);
        Braille {
            width: usize::from(width),
            x_bounds,
            y_bounds,
            resolution: (
                f64::from(width) * DOTS_ACROSS as f64,
                f64::from(height) * DOTS_DOWN as f64,
            ),
            below: vec![Dots::default(); cells],
            layer: vec![Dots::default(); cells],
            painted: Vec::new(),
        }
    }

    /// The dot a world point falls on (rounded to the nearest), or `None` outside the window.
    pub fn dot(&self, x: f64, y: f64) -> Option<(usize, usize)> {
        let [left, right] = self.x_bounds;
        let [bottom, top] = self.y_bounds;
        // Not a number is in no window.
        if !(left..=right).contains(&x) || !(bottom..=top).contains(&y) {
            return None;
        }
        let (width, height) = (right - left, top - bottom);
        if width <= 0.0 || height <= 0.0 {
            return None;
        }
        let dot_x = ((x - left) * (self.resolution.0 - 1.0) / width).round() as usize;
        let dot_y = ((top - y) * (self.resolution.1 - 1.0) / height).round() as usize;
        Some((dot_x, dot_y))
    }

    /// Paints one dot; a dot outside the drawing is left out.
    pub fn paint(&mut self, dot_x: usize, dot_y: usize, color: Color) {
        if dot_x >= self.width * DOTS_ACROSS {
            return;
        }
        let index = (dot_y / DOTS_DOWN) * self.width + dot_x / DOTS_ACROSS;
        let Some(cell) = self.layer.get_mut(index) else {
            return;
        };
        if cell.pattern == 0 {
            self.painted.push(index);
        }
        cell.pattern |= 1 << (dot_x % DOTS_ACROSS + DOTS_ACROSS * (dot_y % DOTS_DOWN));
        cell.color = Some(color);
    }

    /// The world points that fall inside the window, a dot each.
    pub fn points(&mut self, points: &[(f64, f64)], color: Color) {
        for &(x, y) in points {
            self.point(x, y, color);
        }
    }

    /// A world point's dot, if it falls inside the window.
    fn point(&mut self, x: f64, y: f64, color: Color) {
        if let Some((dot_x, dot_y)) = self.dot(x, y) {
            self.paint(dot_x, dot_y, color);
        }
    }

    /// A straight line between two world points, clipped to the window.
    pub fn line(&mut self, from: (f64, f64), to: (f64, f64), color: Color) {
        let Some((from, to)) = clip(self.x_bounds, self.y_bounds, from, to) else {
            return;
        };
        let (Some((x1, y1)), Some((x2, y2))) = (self.dot(from.0, from.1), self.dot(to.0, to.1))
        else {
            return;
        };
        for_each_line_dot(x1, y1, x2, y2, |x, y| self.paint(x, y, color));
    }

    /// A circle's outline: a dot every degree.
    pub fn circle(&mut self, centre: (f64, f64), radius: f64, color: Color) {
        for (cos, sin) in DEGREES.iter() {
            self.point(
                radius.mul_add(*cos, centre.0),
                radius.mul_add(*sin, centre.1),
                color,
            );
        }
    }

    /// Ends the current layer: what it painted covers the layers below, cell by cell.
    pub fn layer(&mut self) {
        for index in self.painted.drain(..) {
            self.below[index] = std::mem::take(&mut self.layer[index]);
        }
    }

    /// Writes the drawing into `area` of `buffer` (the drawing's size): each painted cell's
    /// braille character in its colour. Cells with no dots are left as they are (ratatui's
    /// canvas also sets the terminal's own background on every cell of its area: the panels
    /// draw on that background already).
    pub fn render(mut self, area: Rect, buffer: &mut Buffer) {
        self.layer();
        let height = self.below.len() / self.width.max(1);
        let area = area.intersection(buffer.area);
        let rows = height.min(usize::from(area.height));
        let columns = self.width.min(usize::from(area.width));
        for row in 0..rows {
            for column in 0..columns {
                let dots = self.below[row * self.width + column];
                if dots.pattern == 0 {
                    continue;
                }
                let cell = &mut buffer[(area.x + column as u16, area.y + row as u16)];
                cell.set_char(BRAILLE[usize::from(dots.pattern)]);
                if let Some(color) = dots.color {
                    cell.set_fg(color);
                }
            }
        }
    }
}

/// The part of a line inside the window (Cohen-Sutherland), or `None` when none is.
fn clip(
    [x_min, x_max]: [f64; 2],
    [y_min, y_max]: [f64; 2],
    mut from: (f64, f64),
    mut to: (f64, f64),
) -> Option<((f64, f64), (f64, f64))> {
    const LEFT: u8 = 1;
    const RIGHT: u8 = 2;
    const BOTTOM: u8 = 4;
    const TOP: u8 = 8;
    let region = |(x, y): (f64, f64)| {
        let beyond = |past: bool, edge: u8| if past { edge } else { 0 };
        beyond(x < x_min, LEFT)
            | beyond(x > x_max, RIGHT)
            | beyond(y < y_min, BOTTOM)
            | beyond(y > y_max, TOP)
    };
    // Where the line from `p` towards `q` crosses the first window edge `p` is beyond.
    let onto_edge = |p: (f64, f64), q: (f64, f64), outside: u8| {
        let (dx, dy) = (q.0 - p.0, q.1 - p.1);
        if outside & LEFT != 0 {
            (x_min, p.1 + (x_min - p.0) * dy / dx)
        } else if outside & RIGHT != 0 {
            (x_max, p.1 + (x_max - p.0) * dy / dx)
        } else if outside & BOTTOM != 0 {
            (p.0 + (y_min - p.1) * dx / dy, y_min)
        } else {
            (p.0 + (y_max - p.1) * dx / dy, y_max)
        }
    };
    let (mut from_region, mut to_region) = (region(from), region(to));
    loop {
        if from_region & to_region != 0 {
            return None;
        } else if from_region != 0 {
            from = onto_edge(from, to, from_region);
            from_region = region(from);
        } else if to_region != 0 {
            to = onto_edge(to, from, to_region);
            to_region = region(to);
        } else {
            return Some((from, to));
        }
    }
}

/// The dots of a line between two dots (Bresenham's), each once.
fn for_each_line_dot(
    x1: usize,
    y1: usize,
    x2: usize,
    y2: usize,
    mut dot: impl FnMut(usize, usize),
) {
    let (dx, dy) = (x2.abs_diff(x1), y2.abs_diff(y1));
    if dx == 0 {
        (y1.min(y2)..=y1.max(y2)).for_each(|y| dot(x1, y));
    } else if dy == 0 {
        (x1.min(x2)..=x1.max(x2)).for_each(|x| dot(x, y1));
    } else if dy < dx {
        // Mostly across: a dot per column, from the left.
        let (from, to) = if x1 > x2 {
            ((x2, y2), (x1, y1))
        } else {
            ((x1, y1), (x2, y2))
        };
        steps(from, to, &mut dot);
    } else {
        // Mostly down: a dot per row, from the top.
        let (from, to) = if y1 > y2 {
            ((y2, x2), (y1, x1))
        } else {
            ((y1, x1), (y2, x2))
        };
        steps(from, to, |y, x| dot(x, y));
    }
}

/// Bresenham's steps from `from` to `to`, each `(major, minor)` with `major` increasing one at
/// a time (its span at least the minor's), `minor` following it to the nearest dot.
fn steps(
    (major_from, minor_from): (usize, usize),
    (major_to, minor_to): (usize, usize),
    mut dot: impl FnMut(usize, usize),
) {
    let major_span = (major_to - major_from) as isize;
    let minor_span = minor_to.abs_diff(minor_from) as isize;
    let mut error = 2 * minor_span - major_span;
    let mut minor = minor_from;
    for major in major_from..=major_to {
        dot(major, minor);
        if error > 0 {
            minor = if minor_from > minor_to {
                minor.saturating_sub(1)
            } else {
                minor + 1
            };
            error -= 2 * major_span;
        }
        error += 2 * minor_span;
    }
}

#[cfg(test)]
mod tests;
