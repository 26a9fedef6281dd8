//! Styles, with a plain variant for `NO_COLOR` (emphasis by bold and reverse video only).

use ratatui::style::{Color, Modifier, Style};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Theme {
    pub color: bool,
}

impl Theme {
    /// Colour unless `NO_COLOR` is set to anything non-empty (no-color.org).
    pub fn from_env() -> Theme {
        let no_color = std::env::var_os("NO_COLOR").is_some_and(|v| !v.is_empty());
        Theme { color: !no_color }
    }

    fn colored(&self, color: Color) -> Style {
        if self.color {
            Style::default().fg(color)
        } else {
            Style::default()
        }
    }

    pub fn title(&self) -> Style {
        Style::default().add_modifier(Modifier::BOLD)
    }

    pub fn dim(&self) -> Style {
        self.colored(Color::DarkGray)
    }

    pub fn ok(&self) -> Style {
        self.colored(Color::Green)
    }

    pub fn warning(&self) -> Style {
        self.colored(Color::Yellow).add_modifier(Modifier::BOLD)
    }

    /// Faults and lost links: must stand out even without colour.
    pub fn alarm(&self) -> Style {
        self.badge(Color::White, Color::Red)
    }

    pub fn moving(&self) -> Style {
        self.badge(Color::Black, Color::Yellow)
    }

    /// Values from telemetry too old to trust: greyed out (dimmed without colour).
    pub fn stale(&self) -> Style {
        if self.color {
            Style::default()
                .fg(Color::DarkGray)
                .bg(Color::Reset)
                .remove_modifier(Modifier::BOLD | Modifier::REVERSED)
        } else {
            Style::default().add_modifier(Modifier::DIM)
        }
    }

    pub fn selected(&self) -> Style {
        Style::default().add_modifier(Modifier::REVERSED)
    }

    pub fn accent(&self) -> Style {
        self.colored(Color::Cyan)
    }

    /// The built-in simulated arm's badge: plain to see, and unlike any alarm or motion.
    pub fn simulated(&self) -> Style {
        self.badge(Color::Black, Color::Cyan)
    }

    /// Bold `fg` on `bg`; bold and reversed without colour.
    fn badge(&self, fg: Color, bg: Color) -> Style {
        if self.color {
            Style::default().fg(fg).bg(bg).add_modifier(Modifier::BOLD)
        } else {
            Style::default().add_modifier(Modifier::BOLD | Modifier::REVERSED)
        }
    }
}
