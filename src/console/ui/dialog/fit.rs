//! The dialog's text fitted to its room: lines wrapped at spaces to the dialog's width, its last
//! lines (a question's answers, a form's keys) always whole, what is above them cut to the rows
//! left with a `…`, and a question's list shortened to the things that fit, the rest counted
//! (`… and 9997 more`).

use ratatui::style::Style;
use ratatui::text::{Line, Span};

use super::super::numbers::{self, ELLIPSIS};
use crate::console::form::QuestionText;

/// A row of cells: each character with its style.
type Row = Vec<(char, Style)>;

/// `body` above `foot`, wrapped to `width` columns, in at most `rows` rows: the foot whole (its
/// last rows when even it is too tall), the body cut to the rows left.
pub fn fit(body: &[Line], foot: &[Line], width: usize, rows: usize) -> Vec<Line<'static>> {
    let mut foot = wrap_all(foot, width);
    let foot = foot.split_off(foot.len().saturating_sub(rows));
    let room = rows - foot.len();
    let mut fitted = cut(wrap_all(body, width), room, width);
    fitted.extend(foot);
    fitted.into_iter().map(line).collect()
}

/// The rows of `question` (drawn in `style`) above `foot`, wrapped to `width` columns, in at most
/// `rows` rows: the foot whole; the question whole when it fits, else with as many of its list's
/// things as fit and the count of the rest; words that still do not fit are cut with a `…`.
pub fn question(
    question: &QuestionText,
    style: Style,
    foot: &[Line],
    width: usize,
    rows: usize,
) -> Vec<Line<'static>> {
    let room = rows.saturating_sub(wrap_all(foot, width).len());
    let wrapped = |shown: usize| {
        wrap_row(
            &cells(&Line::styled(question.with_first(shown), style)),
            width,
        )
    };
    let fits = |shown: usize| wrapped(shown).len() <= room;
    // No more things than the room's cells could hold, each taking a column or more: a long
    // list is never joined whole.
    let mut most = 0;
    let mut used = numbers::width(&question.before);
    for thing in question.list {
        used += numbers::width(thing) + numbers::width(question.separator);
        if used > width * room {
            break;
        }
        most += 1;
    }
    let shown = if most == question.list.len() && fits(most) {
        most
    } else {
        // The most things that fit, fewer than all (more things, more rows).
        let (mut low, mut high) = (0, most.min(question.list.len().saturating_sub(1)));
        while low < high {
            let mid = (low + high).div_ceil(2);
            if fits(mid) {
                low = mid;
            } else {
                high = mid - 1;
            }
        }
        low
    };
    let body = wrapped(shown).into_iter().map(line).collect::<Vec<_>>();
    fit(&body, foot, width, rows)
}

fn wrap_all(lines: &[Line], width: usize) -> Vec<Row> {
    lines
        .iter()
        .flat_map(|line| wrap_row(&cells(line), width))
        .collect()
}

/// The first `rows` of `wrapped`; when some are left out, the last one kept ends with `…`.
fn cut(mut wrapped: Vec<Row>, rows: usize, width: usize) -> Vec<Row> {
    if wrapped.len() <= rows {
        return wrapped;
    }
    wrapped.truncate(rows);
    if let Some(last) = wrapped.last_mut() {
        let style = last.last().map(|(_, style)| *style).unwrap_or_default();
        while !last.is_empty() && row_width(last) + 1 > width {
            last.pop();
        }
        *last = trimmed(std::mem::take(last));
        last.push((ELLIPSIS, style));
    }
    wrapped
}

fn cells(line: &Line) -> Row {
    line.spans
        .iter()
        .flat_map(|span| {
            let style = line.style.patch(span.style);
            span.content.chars().map(move |c| (c, style))
        })
        .collect()
}

fn char_width(c: char) -> usize {
    numbers::width(c.encode_utf8(&mut [0; 4]))
}

fn row_width(row: &[(char, Style)]) -> usize {
    row.iter().map(|(c, _)| char_width(*c)).sum()
}

/// `row` in rows of at most `width` columns: broken after a space where it can be, inside a word
/// only when the word alone is wider than a row. A row broken off loses its trailing spaces, and
/// the row after a break starts with a word.
fn wrap_row(row: &[(char, Style)], width: usize) -> Vec<Row> {
    let width = width.max(1);
    let mut rows = Vec::new();
    let mut current: Row = Vec::new();
    let mut used = 0;
    let mut rest = row;
    while !rest.is_empty() {
        // The next run of spaces, or of anything else (a word).
        let spaces = rest[0].0 == ' ';
        let end = rest
            .iter()
            .position(|(c, _)| (*c == ' ') != spaces)
            .unwrap_or(rest.len());
        let (run, after) = rest.split_at(end);
        rest = after;
        let run_width = row_width(run);
        if spaces {
            // Spaces that begin a row after a break are dropped; at a row's end, trimmed.
            if current.is_empty() && !rows.is_empty() {
                continue;
            }
            for cell in run {
                if used < width {
                    current.push(*cell);
                    used += 1;
                }
            }
            continue;
        }
        if used + run_width > width && run_width <= width && !current.is_empty() {
            rows.push(trimmed(std::mem::take(&mut current)));
            used = 0;
        }
        for cell in run {
            let w = char_width(cell.0);
            if used + w > width && !current.is_empty() {
                rows.push(trimmed(std::mem::take(&mut current)));
                used = 0;
            }
            current.push(*cell);
            used += w;
        }
    }
    rows.push(current);
    rows
}

fn trimmed(mut row: Row) -> Row {
    while row.last().is_some_and(|(c, _)| *c == ' ') {
        row.pop();
    }
    row
}

/// A row as a line, a span per run of one style.
fn line(row: Row) -> Line<'static> {
    let mut spans: Vec<Span<'static>> = Vec::new();
    let mut text = String::new();
    let mut style = None;
    for (c, cell_style) in row {
        if style.is_some_and(|s| s != cell_style) {
            spans.push(Span::styled(
                std::mem::take(&mut text),
                style.unwrap_or_default(),
            ));
        }
        style = Some(cell_style);
        text.push(c);
    }
    if let Some(style) = style {
        spans.push(Span::styled(text, style));
    }
    Line::from(spans)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn texts(lines: &[Line]) -> Vec<String> {
        lines.iter().map(ToString::to_string).collect()
    }

    fn wrapped(text: &str, width: usize) -> Vec<String> {
        wrap_row(&cells(&Line::raw(text)), width)
            .into_iter()
            .map(|row| line(row).to_string())
            .collect()
    }

    #[test]
    fn text_wraps_at_spaces_and_inside_a_word_only_when_it_is_wider_than_a_row() {
        assert_eq!(wrapped("move the arm", 8), ["move the", "arm"]);
        assert_eq!(wrapped("move   the arm", 6), ["move", "the", "arm"]);
        assert_eq!(wrapped("abcdefghij xy", 4), ["abcd", "efgh", "ij", "xy"]);
        assert_eq!(wrapped("", 4), [""]);
        // Leading spaces of the first row are kept (a label's indent).
        assert_eq!(wrapped("  ab cd", 5), ["  ab", "cd"]);
        // Wide characters count two columns.
        assert_eq!(wrapped("位置位置 ab", 4), ["位置", "位置", "ab"]);
        for text in ["a long question → with → arrows", "x".repeat(50).as_str()] {
            for width in 1..20 {
                for row in wrapped(text, width) {
                    assert!(numbers::width(&row) <= width, "{width}: {row}");
                }
            }
        }
    }

    #[test]
    fn the_foot_always_shows_and_the_body_is_cut_with_an_ellipsis() {
        let body = [Line::raw(
            "one two three four five six seven eight nine ten",
        )];
        let foot = [Line::raw(""), Line::raw("y: yes")];
        let rows = fit(&body, &foot, 10, 4);
        assert_eq!(texts(&rows), ["one two", "three fou…", "", "y: yes"]);
        assert_eq!(texts(&fit(&body, &foot, 60, 4)).len(), 3, "all of it fits");
    }

    #[test]
    fn a_long_list_shows_what_fits_and_counts_the_rest() {
        let legs: Vec<String> = (0..10_000).map(|i| format!("p{i}")).collect();
        let text = QuestionText {
            before: "Play 'big', 10000 legs: ".into(),
            list: &legs,
            separator: " → ",
            after: "?".into(),
        };
        let foot = [Line::raw(""), Line::raw("y or enter: yes")];
        let rows = texts(&question(&text, Style::default(), &foot, 30, 5));
        assert_eq!(
            rows,
            [
                "Play 'big', 10000 legs: p0 →",
                "p1 → p2 → p3 → p4 → p5 → p6 →",
                "p7 → p8 → p9 … and 9990 more?",
                "",
                "y or enter: yes"
            ]
        );
        // Fewer rows: fewer legs, and more counted.
        let rows = texts(&question(&text, Style::default(), &foot, 30, 4));
        assert_eq!(
            rows[..2],
            [
                "Play 'big', 10000 legs: p0 →",
                "p1 → p2 → p3 … and 9996 more?"
            ]
        );
        // No room even for the count: the question is cut, the answers still show.
        let rows = texts(&question(&text, Style::default(), &foot, 30, 3));
        assert_eq!(
            rows,
            ["Play 'big', 10000 legs: … and…", "", "y or enter: yes"]
        );
        // A short list shows whole.
        let text = QuestionText {
            list: &legs[..2],
            ..text
        };
        let rows = texts(&question(&text, Style::default(), &foot, 40, 5));
        assert_eq!(rows[0], "Play 'big', 10000 legs: p0 → p1?");
    }
}
