//! The bottom line: the latest message, or the most used keys.

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::Line;
use ratatui::widgets::Paragraph;

use super::theme::Theme;
use crate::console::action::Action;
use crate::console::app::Severity;
use crate::console::view::View;

fn keys(view: &View, action: Action) -> String {
    view.keymap
        .keys_for(action)
        .first()
        .map(|k| k.to_string())
        .unwrap_or_else(|| "-".into())
}

pub fn draw(frame: &mut Frame, area: Rect, view: &View, theme: &Theme) {
    let line = match &view.message {
        Some((text, severity)) => {
            let style = match severity {
                Severity::Info => theme.accent(),
                Severity::Warning => theme.warning(),
                Severity::Error => theme.alarm(),
            };
            Line::styled(text.clone(), style)
        }
        None => Line::styled(
            format!(
                "{}{}{}{}{}{} jog  arrows pan  {} stop  {} home  {} save  {} help  {} quit",
                keys(view, Action::JogXPlus),
                keys(view, Action::JogXMinus),
                keys(view, Action::JogYPlus),
                keys(view, Action::JogYMinus),
                keys(view, Action::JogZPlus),
                keys(view, Action::JogZMinus),
                keys(view, Action::Stop),
                keys(view, Action::Home),
                keys(view, Action::SavePosition),
                keys(view, Action::Help),
                keys(view, Action::Quit),
            ),
            theme.dim(),
        ),
    };
    frame.render_widget(Paragraph::new(line), area);
}
