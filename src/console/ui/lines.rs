//! Lines of text a row each, cut at the right edge: what ratatui's
//! `Paragraph::new(lines).block(block)` draws (no wrap, no scroll), at a fraction of its cost.
//!
//! The panels' text is nearly all printable ASCII, a character a cell: such a line is written a
//! byte at a time; any other line (wide or combining characters, controls, an alignment of its
//! own) is drawn by ratatui's paragraph, on its own row. The tests hold it to the paragraph.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::text::Line;
use ratatui::widgets::{Block, Paragraph, Widget};

use crate::text::is_printable_ascii;

/// Draws `lines` inside `block` (when given) in `area`, the first on the top row; lines
/// beyond the last row are not drawn, and each line is cut at the right edge.
pub fn draw(buffer: &mut Buffer, area: Rect, block: Option<Block>, lines: &[Line]) {
    let area = area.intersection(buffer.area);
    let inner = block.as_ref().map_or(area, |block| block.inner(area));
    if let Some(block) = block {
        block.render(area, buffer);
    }
    for (line, y) in lines.iter().zip(inner.top()..inner.bottom()) {
        let row = Rect {
            y,
            height: 1,
            ..inner
        };
        if !write_ascii(buffer, row, line) {
            Paragraph::new(line.clone()).render(row, buffer);
        }
    }
}

/// Writes a left-aligned line of printable ASCII along `row`, a character a cell; `false`
/// (nothing written) for any other line.
fn write_ascii(buffer: &mut Buffer, row: Rect, line: &Line) -> bool {
    let aligned_left = matches!(
        line.alignment,
        None | Some(ratatui::layout::Alignment::Left)
    );
    if !aligned_left
        || !line
            .spans
            .iter()
            .all(|span| is_printable_ascii(&span.content))
    {
        return false;
    }
    let mut x = row.left();
    for span in &line.spans {
        let style = line.style.patch(span.style);
        for byte in span.content.bytes() {
            if x >= row.right() {
                return true;
            }
            buffer[(x, row.y)]
                .set_char(char::from(byte))
                .set_style(style);
            x += 1;
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;
    use ratatui::style::{Color, Modifier, Style};
    use ratatui::text::Span;
    use ratatui::widgets::Borders;

    use super::*;

    fn by_paragraph(area: Rect, block: Option<Block>, lines: &[Line]) -> Buffer {
        let mut buffer = Buffer::empty(Rect::new(0, 0, 30, 8));
        let mut paragraph = Paragraph::new(lines.to_vec());
        if let Some(block) = block {
            paragraph = paragraph.block(block);
        }
        paragraph.render(area, &mut buffer);
        buffer
    }

    fn by_lines(area: Rect, block: Option<Block>, lines: &[Line]) -> Buffer {
        let mut buffer = Buffer::empty(Rect::new(0, 0, 30, 8));
        draw(&mut buffer, area, block, lines);
        buffer
    }

    #[test]
    fn a_line_is_written_along_its_row_and_cut_at_the_edge() {
        let lines = [
            Line::from(vec![
                Span::styled("ab", Style::new().fg(Color::Red)),
                Span::raw("cdef"),
            ]),
            Line::styled("xy", Style::new().bg(Color::Blue)),
        ];
        let mut buffer = Buffer::empty(Rect::new(0, 0, 6, 3));
        draw(&mut buffer, Rect::new(1, 0, 4, 2), None, &lines);
        let mut expected = Buffer::with_lines([" abcd ", " xy   ", "      "]);
        for x in 1..3 {
            expected[(x, 0)].set_fg(Color::Red);
            expected[(x, 1)].set_bg(Color::Blue);
        }
        assert_eq!(buffer, expected);
    }

    fn text() -> impl Strategy<Value = String> {
        // Mostly ASCII; some wide, combining and control characters, for the fallback.
        prop::collection::vec(
            prop_oneof![
                8 => prop::char::range(' ', '~'),
                1 => prop::sample::select(vec!['é', '漢', '\u{301}', '\t', '⣿', '\u{7f}']),
            ],
            0..14,
        )
        .prop_map(|chars| chars.into_iter().collect())
    }

    fn style() -> impl Strategy<Value = Style> {
        prop::sample::select(vec![
            Style::new(),
            Style::new().fg(Color::Red),
            Style::new().bg(Color::Blue).add_modifier(Modifier::BOLD),
            Style::new()
                .fg(Color::Reset)
                .remove_modifier(Modifier::BOLD),
        ])
    }

    fn line() -> impl Strategy<Value = Line<'static>> {
        (
            prop::collection::vec((text(), style()), 0..4),
            style(),
            prop::sample::select(vec![
                None,
                Some(ratatui::layout::Alignment::Left),
                Some(ratatui::layout::Alignment::Right),
            ]),
        )
            .prop_map(|(spans, style, alignment)| {
                let spans: Vec<Span> = spans
                    .into_iter()
                    .map(|(text, style)| Span::styled(text, style))
                    .collect();
                let mut line = Line::from(spans).style(style);
                line.alignment = alignment;
                line
            })
    }

    proptest! {
        #[test]
        fn it_draws_what_ratatuis_paragraph_draws(
            x in 0u16..6,
            y in 0u16..3,
            width in 0u16..26,
            height in 0u16..6,
            bordered in any::<bool>(),
            lines in prop::collection::vec(line(), 0..8),
        ) {
            let area = Rect::new(x, y, width, height);
            let block = bordered.then(|| Block::default().borders(Borders::ALL).title(" t "));
            prop_assert_eq!(
                by_lines(area, block.clone(), &lines),
                by_paragraph(area, block, &lines)
            );
        }
    }
}
