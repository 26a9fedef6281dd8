//! The help overlay: every action of the active keymap, in sections, each with its keys, its
//! name as a keymap file spells it and what it does.
//!
//! A key name is never cut, a description wraps under itself; the rows scroll (the app keeps
//! the offset, [`scroll_limits`]). The status bar stays visible: what the arm is doing stays on
//! screen while the help is open.

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::style::Style;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Clear};

use super::theme::Theme;
use crate::console::action::Action;
use crate::console::keymap::Keymap;
use crate::console::view::View;

/// Rows kept visible above the overlay: the status bar.
const STATUS_ROWS: u16 = 2;
/// The keys column is at least this wide (or as wide as the longest key name), so a key list
/// such as `space kp5 kp0` wraps rather than squeezing the descriptions.
const MIN_KEYS_WIDTH: usize = 14;
/// Below this many columns for the descriptions, each description goes on lines of its own.
const MIN_DESCRIPTION_WIDTH: usize = 24;
/// Between two columns.
const GAP: usize = 2;
/// The indent of a description under its key in the narrow layout.
const INDENT: usize = 4;

/// Where the overlay goes on a screen of `screen`'s size: everything below the status bar (no
/// panel peeks out beside it).
pub fn area(screen: Rect) -> Rect {
    let top = STATUS_ROWS.min(screen.height.saturating_sub(3));
    Rect {
        y: screen.y + top,
        height: screen.height - top,
        ..screen
    }
}

/// The largest scroll offset and a page's rows, for the help of `keymap` on a terminal of
/// `size` (columns, rows): the app clamps its offset with these.
pub fn scroll_limits(keymap: &Keymap, size: (u16, u16)) -> (usize, usize) {
    let inner = inner(area(Rect::new(0, 0, size.0, size.1)));
    let rows = usize::from(inner.height);
    let total = content(keymap, usize::from(inner.width), &Theme { color: false }).len();
    (total.saturating_sub(rows), rows.saturating_sub(1).max(1))
}

pub fn draw(frame: &mut Frame, area: Rect, view: &View, theme: &Theme) {
    let keymap = &view.session.keymap;
    let inside = inner(area);
    let lines = content(keymap, usize::from(inside.width), theme);
    let rows = usize::from(inside.height);
    let max_scroll = lines.len().saturating_sub(rows);
    let scroll = view.screen.help_scroll.min(max_scroll);
    let bottom = if max_scroll == 0 {
        " any key closes this help ".to_string()
    } else {
        let (first, last, total) = (scroll + 1, (scroll + rows).min(lines.len()), lines.len());
        let shown = format!("{first}-{last} of {total}");
        let long = format!(" lines {shown}; down/up pagedown/pageup scroll; other keys close ");
        if long.chars().count() + 2 <= usize::from(area.width) {
            long
        } else {
            format!(" {shown}; pagedown/pageup ")
        }
    };
    let block = Block::default()
        .borders(Borders::ALL)
        .title(Span::styled(
            format!(" Help: keymap '{}' ", keymap.name()),
            theme.title(),
        ))
        .title_bottom(Span::styled(bottom, theme.dim()));
    let visible: Vec<Line> = lines.into_iter().skip(scroll).take(rows).collect();
    frame.render_widget(Clear, area);
    super::lines::draw(frame.buffer_mut(), area, Some(block), &visible);
}

fn inner(area: Rect) -> Rect {
    Block::default().borders(Borders::ALL).inner(area)
}

/// Every line of the help for an overlay `width` columns wide inside.
fn content(keymap: &Keymap, width: usize, theme: &Theme) -> Vec<Line<'static>> {
    let mut lines = Vec::new();
    let header = [
        (
            "Hold a jog key to move; release it to stop. Space stops everything.",
            theme.accent(),
        ),
        (
            "A keyboard is not an e-stop: keep the hardware e-stop in reach.",
            theme.warning(),
        ),
    ];
    for (text, style) in header {
        let words: Vec<&str> = text.split(' ').collect();
        for line in wrap(&words, width) {
            lines.push(Line::styled(line, style));
        }
    }
    let entries: Vec<(Action, Vec<String>)> = Action::ALL
        .into_iter()
        .map(|action| {
            let keys: Vec<String> = keymap
                .keys_for(action)
                .iter()
                .map(ToString::to_string)
                .collect();
            (action, keys)
        })
        .collect();
    let longest_key = entries
        .iter()
        .flat_map(|(_, keys)| keys.iter().map(|k| k.chars().count()))
        .max()
        .unwrap_or(1);
    let widest_keys = entries
        .iter()
        .map(|(_, keys)| joined_width(keys))
        .max()
        .unwrap_or(1);
    let keys_width = widest_keys.min(longest_key.max(MIN_KEYS_WIDTH));
    let name_width = Action::ALL
        .iter()
        .map(|a| a.name().len())
        .max()
        .unwrap_or(0);
    let description_width = width.saturating_sub(keys_width + name_width + 2 * GAP);
    let columns = description_width >= MIN_DESCRIPTION_WIDTH;
    let mut section = "";
    for (action, keys) in &entries {
        if action.section() != section {
            section = action.section();
            lines.push(Line::raw(""));
            lines.push(Line::styled(section.to_string(), theme.title()));
        }
        let keys: Vec<&str> = if keys.is_empty() {
            vec!["-"]
        } else {
            keys.iter().map(String::as_str).collect()
        };
        let words: Vec<&str> = action.describe().split(' ').collect();
        if columns {
            let key_lines = wrap(&keys, keys_width);
            let what = wrap(&words, description_width);
            for i in 0..key_lines.len().max(what.len()) {
                let name = if i == 0 { action.name() } else { String::new() };
                lines.push(Line::from(vec![
                    Span::styled(
                        format!("{:<keys_width$}", cell(&key_lines, i)),
                        theme.title(),
                    ),
                    Span::styled(
                        format!("{:GAP$}{name:<name_width$}{:GAP$}", "", ""),
                        theme.accent(),
                    ),
                    Span::raw(cell(&what, i).to_string()),
                ]));
            }
        } else {
            // Narrow: the keys and the name on a line, the description indented below.
            let mut first = keys.clone();
            let name = action.name();
            first.push(&name);
            for (i, line) in wrap(&first, width).into_iter().enumerate() {
                let style = if i == 0 {
                    theme.title()
                } else {
                    Style::default()
                };
                lines.push(Line::styled(line, style));
            }
            for line in wrap(&words, width.saturating_sub(INDENT)) {
                lines.push(Line::raw(format!("{:INDENT$}{line}", "")));
            }
        }
    }
    lines
}

fn cell(lines: &[String], i: usize) -> &str {
    lines.get(i).map(String::as_str).unwrap_or("")
}

fn joined_width(words: &[String]) -> usize {
    let letters: usize = words.iter().map(|w| w.chars().count()).sum();
    letters + words.len().saturating_sub(1)
}

/// `words` joined by spaces into lines of at most `width` characters; a word longer than
/// `width` gets a line of its own, whole (a key name is never cut).
fn wrap(words: &[&str], width: usize) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for word in words.iter().filter(|w| !w.is_empty()) {
        let needed = line.chars().count() + usize::from(!line.is_empty()) + word.chars().count();
        if !line.is_empty() && needed > width {
            lines.push(std::mem::take(&mut line));
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(word);
    }
    if !line.is_empty() || lines.is_empty() {
        lines.push(line);
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrapping_keeps_words_whole() {
        assert_eq!(wrap(&["space", "kp5", "kp0"], 9), vec!["space kp5", "kp0"]);
        assert_eq!(wrap(&["kppagedown", "x"], 4), vec!["kppagedown", "x"]);
        assert_eq!(wrap(&[], 4), vec![""]);
    }

    #[test]
    fn every_action_is_listed_with_its_name_at_any_width() {
        for name in Keymap::builtin_names() {
            let Some(keymap) = Keymap::builtin(name) else {
                panic!("no {name}")
            };
            for width in [36, 60, 78, 98] {
                let text: Vec<String> = content(&keymap, width, &Theme { color: false })
                    .iter()
                    .map(|line| line.spans.iter().map(|s| s.content.as_ref()).collect())
                    .collect();
                for line in &text {
                    assert!(line.trim_end().chars().count() <= width, "{width}: {line}");
                }
                let all = text.join("\n");
                for action in Action::ALL {
                    assert!(all.contains(&action.name()), "{name} {width}: {action:?}");
                }
                for key in keymap.bindings().keys() {
                    let key = key.to_string();
                    assert!(
                        text.iter().any(|l| l.split(' ').any(|word| word == key)),
                        "{name} {width}: key {key} missing"
                    );
                }
            }
        }
    }
}
