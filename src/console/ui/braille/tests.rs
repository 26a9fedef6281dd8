use proptest::prelude::*;
use ratatui::symbols::Marker;
use ratatui::widgets::Widget;
use ratatui::widgets::canvas::{Canvas, Circle, Line, Points};

use super::*;

/// One thing drawn, in world coordinates.
#[derive(Debug, Clone)]
enum Shape {
    Line((f64, f64), (f64, f64)),
    Points(Vec<(f64, f64)>),
    Circle((f64, f64), f64),
    Layer,
}

const COLORS: [Color; 4] = [Color::Red, Color::Green, Color::Blue, Color::Yellow];

/// What ratatui's braille canvas draws of `shapes` in a `width` x `height` buffer.
fn by_ratatui(width: u16, height: u16, bounds: ([f64; 2], [f64; 2]), shapes: &[Shape]) -> Buffer {
    let area = Rect::new(0, 0, width, height);
    let mut buffer = Buffer::empty(area);
    Canvas::default()
        .marker(Marker::Braille)
        .x_bounds(bounds.0)
        .y_bounds(bounds.1)
        .paint(|ctx| {
            for (i, shape) in shapes.iter().enumerate() {
                let color = COLORS[i % COLORS.len()];
                match shape {
                    Shape::Line(a, b) => ctx.draw(&Line::new(a.0, a.1, b.0, b.1, color)),
                    Shape::Points(points) => ctx.draw(&Points::new(points, color)),
                    Shape::Circle(c, r) => ctx.draw(&Circle::new(c.0, c.1, *r, color)),
                    Shape::Layer => ctx.layer(),
                }
            }
        })
        .render(area, &mut buffer);
    buffer
}

/// What [`Braille`] draws of `shapes` in the same buffer.
fn by_braille(width: u16, height: u16, bounds: ([f64; 2], [f64; 2]), shapes: &[Shape]) -> Buffer {
    let area = Rect::new(0, 0, width, height);
    let mut buffer = Buffer::empty(area);
    let mut drawing = Braille::new(width, height, bounds.0, bounds.1);
    for (i, shape) in shapes.iter().enumerate() {
        let color = COLORS[i % COLORS.len()];
        match shape {
            Shape::Line(a, b) => drawing.line(*a, *b, color),
            Shape::Points(points) => drawing.points(points, color),
            Shape::Circle(c, r) => drawing.circle(*c, *r, color),
            Shape::Layer => drawing.layer(),
        }
    }
    drawing.render(area, &mut buffer);
    buffer
}

#[test]
fn a_line_across_two_cells_is_their_bottom_dots() {
    // A 2x1 drawing over x 0..3, y 0..1: four dots across, four down. The line along the
    // bottom (y = 0) lights the bottom row of dots: braille dots 7 and 8 of both cells, U+28C0.
    let mut buffer = Buffer::empty(Rect::new(0, 0, 2, 1));
    let mut drawing = Braille::new(2, 1, [0.0, 3.0], [0.0, 1.0]);
    drawing.line((0.0, 0.0), (3.0, 0.0), Color::Red);
    drawing.render(buffer.area, &mut buffer);
    assert_eq!(buffer[(0, 0)].symbol(), "\u{28C0}");
    assert_eq!(buffer[(1, 0)].symbol(), "\u{28C0}");
    assert_eq!(buffer[(0, 0)].fg, Color::Red);
}

#[test]
fn an_upper_layer_covers_a_cell_whole_and_leaves_the_others() {
    // The left column's dots (1, 2, 3, 7: U+2847) in red, then in a layer above, the top left
    // dot (dot 1: U+2801) in green: the cell shows the green dot alone.
    let mut buffer = Buffer::empty(Rect::new(0, 0, 2, 1));
    let mut drawing = Braille::new(2, 1, [0.0, 3.0], [0.0, 3.0]);
    drawing.line((0.0, 0.0), (0.0, 3.0), Color::Red);
    drawing.line((3.0, 0.0), (3.0, 3.0), Color::Red);
    drawing.layer();
    drawing.points(&[(0.0, 3.0)], Color::Green);
    drawing.render(buffer.area, &mut buffer);
    assert_eq!(buffer[(0, 0)].symbol(), "\u{2801}");
    assert_eq!(buffer[(0, 0)].fg, Color::Green);
    // The right column's dots (4, 5, 6, 8: U+28B8) in the cell the layer did not touch.
    assert_eq!(buffer[(1, 0)].symbol(), "\u{28B8}");
    assert_eq!(buffer[(1, 0)].fg, Color::Red);
}

#[test]
fn a_point_outside_the_window_is_not_drawn() {
    let mut buffer = Buffer::empty(Rect::new(0, 0, 2, 1));
    let mut drawing = Braille::new(2, 1, [0.0, 1.0], [0.0, 1.0]);
    drawing.points(&[(1.5, 0.5), (0.5, -0.1), (f64::NAN, 0.5)], Color::Red);
    drawing.line((2.0, 2.0), (3.0, 3.0), Color::Red);
    drawing.render(buffer.area, &mut buffer);
    assert_eq!(buffer, Buffer::empty(Rect::new(0, 0, 2, 1)));
}

fn coordinate() -> impl Strategy<Value = f64> {
    // Mostly inside the window (-1..1), some beyond it, for the clipping.
    -1.6..1.6f64
}

fn point() -> impl Strategy<Value = (f64, f64)> {
    (coordinate(), coordinate())
}

fn shape() -> impl Strategy<Value = Shape> {
    prop_oneof![
        4 => (point(), point()).prop_map(|(a, b)| Shape::Line(a, b)),
        2 => prop::collection::vec(point(), 0..6).prop_map(Shape::Points),
        1 => (point(), 0.0..1.2f64).prop_map(|(c, r)| Shape::Circle(c, r)),
        2 => Just(Shape::Layer),
    ]
}

proptest! {
    #[test]
    fn it_draws_what_ratatuis_braille_canvas_draws(
        width in 1u16..40,
        height in 1u16..16,
        x_bounds in (-1.2..-0.2f64, 0.2..1.2f64),
        y_bounds in (-1.2..-0.2f64, 0.2..1.2f64),
        shapes in prop::collection::vec(shape(), 0..12),
    ) {
        let bounds = ([x_bounds.0, x_bounds.1], [y_bounds.0, y_bounds.1]);
        prop_assert_eq!(
            by_braille(width, height, bounds, &shapes),
            by_ratatui(width, height, bounds, &shapes)
        );
    }
}
