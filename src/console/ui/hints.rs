//! The bottom line: the latest message, or the most used keys.

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::Line;
use ratatui::widgets::Paragraph;

use super::theme::Theme;
use crate::console::action::Action;
use crate::console::app::{App, Severity};

fn keys(app: &App, action: Action) -> String {
    app.config
        .keymap
        .keys_for(action)
        .first()
        .map(|k| k.to_string())
        .unwrap_or_else(|| "-".into())
}

pub fn draw(frame: &mut Frame, area: Rect, app: &App, theme: &Theme) {
    let line = match &app.message {
        Some((text, severity, _)) => {
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
                keys(app, Action::JogXPlus),
                keys(app, Action::JogXMinus),
                keys(app, Action::JogYPlus),
                keys(app, Action::JogYMinus),
                keys(app, Action::JogZPlus),
                keys(app, Action::JogZMinus),
                keys(app, Action::Stop),
                keys(app, Action::Home),
                keys(app, Action::SavePosition),
                keys(app, Action::Help),
                keys(app, Action::Quit),
            ),
            theme.dim(),
        ),
    };
    frame.render_widget(Paragraph::new(line), area);
}
