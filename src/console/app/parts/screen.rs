//! The screen: overlays, the bottom line, the command log, the size, the help's scroll.

use std::collections::VecDeque;
use std::sync::Arc;
use std::time::Instant;

use super::super::message::{Message, Messages, Until};
use super::super::{MIN_HEIGHT, MIN_WIDTH, Overlay, Severity};
use crate::console::form::{Confirm, Form};
use crate::console::keymap::{KeyName, Keymap, NamedKey};
use crate::console::ui::help::scroll_limits;
use crate::link::interface::{ArmEvent, LogEntry, PositionCoordinates};

const LOG_CAPACITY: usize = 500;

const DOWN: KeyName = KeyName::named(NamedKey::Down);
const UP: KeyName = KeyName::named(NamedKey::Up);
const PAGE_DOWN: KeyName = KeyName::named(NamedKey::PageDown);
const PAGE_UP: KeyName = KeyName::named(NamedKey::PageUp);
const HOME: KeyName = KeyName::named(NamedKey::Home);
const END: KeyName = KeyName::named(NamedKey::End);

/// The screen: what is drawn over the panels, the bottom line, the command log, the size.
#[derive(Debug, Clone)]
pub(in crate::console::app) struct Screen {
    overlay: Overlay,
    /// The bottom line, each message tied to what ends it.
    messages: Messages,
    /// Shared with the views built from it: a view takes its lines without copying them.
    log: VecDeque<Arc<LogEntry>>,
    hex: bool,
    size: (u16, u16),
    help_scroll: usize,
}

/// What the screen shows of itself: cut to what a screen can show.
#[derive(Debug, Clone, PartialEq)]
pub struct ScreenView {
    /// The terminal's size as the app last heard it.
    pub size: (u16, u16),
    /// The newest log entries a screen can show, shared with the app's log, not copied.
    pub log: VecDeque<Arc<LogEntry>>,
    pub hex: bool,
    pub message: Option<(String, Severity)>,
    pub overlay: Overlay,
    pub help_scroll: usize,
}

impl Default for Screen {
    fn default() -> Screen {
        Screen {
            overlay: Overlay::None,
            messages: Messages::default(),
            log: VecDeque::new(),
            hex: false,
            size: (80, 24),
            help_scroll: 0,
        }
    }
}

impl Screen {
    pub(in crate::console::app) fn overlay(&self) -> &Overlay {
        &self.overlay
    }

    /// The name of the position a go-to question asks about (read before its answer closes it).
    pub(in crate::console::app) fn goto_in_question(&self) -> Option<String> {
        match &self.overlay {
            Overlay::Confirm(Confirm::GoTo(name)) => Some(name.clone()),
            _ => None,
        }
    }

    pub(in crate::console::app) fn show(&mut self, overlay: Overlay) {
        self.overlay = overlay;
    }

    /// Closes the overlay and hands it back.
    pub(in crate::console::app) fn take_overlay(&mut self) -> Overlay {
        std::mem::replace(&mut self.overlay, Overlay::None)
    }

    pub(in crate::console::app) fn overlay_is_none(&self) -> bool {
        self.overlay == Overlay::None
    }

    pub(in crate::console::app) fn form_open(&self) -> bool {
        matches!(self.overlay, Overlay::Form(_))
    }

    pub(in crate::console::app) fn question_open(&self) -> bool {
        matches!(self.overlay, Overlay::Confirm(_))
    }

    pub(in crate::console::app) fn form_mut(&mut self) -> Option<&mut Form> {
        match &mut self.overlay {
            Overlay::Form(form) => Some(form),
            _ => None,
        }
    }

    /// Whether the position overlay shows `name`.
    pub(in crate::console::app) fn shows_position(&self, name: &str) -> bool {
        matches!(&self.overlay, Overlay::Position { name: shown, .. } if shown == name)
    }

    /// The operator's answer about `name`, into its overlay if that is open.
    pub(in crate::console::app) fn on_position(
        &mut self,
        name: String,
        coordinates: PositionCoordinates,
    ) {
        if self.shows_position(&name) {
            self.overlay = Overlay::Position {
                name,
                coordinates: Some(coordinates),
            };
        }
    }

    pub(in crate::console::app) fn size(&self) -> (u16, u16) {
        self.size
    }

    pub(in crate::console::app) fn on_resize(&mut self, width: u16, height: u16) {
        self.size = (width, height);
    }

    pub(in crate::console::app) fn fits(&self) -> bool {
        self.size.0 >= MIN_WIDTH && self.size.1 >= MIN_HEIGHT
    }

    pub(in crate::console::app) fn hex(&self) -> bool {
        self.hex
    }

    pub(in crate::console::app) fn on_toggle_hex(&mut self) {
        self.hex = !self.hex;
    }

    pub(in crate::console::app) fn log(&self) -> &VecDeque<Arc<LogEntry>> {
        &self.log
    }

    /// A log line; equal telemetry polls in a row share one counted line.
    pub(in crate::console::app) fn on_log(&mut self, entry: LogEntry) {
        let count = entry.count.max(1);
        if let Some(last) = self.log.back_mut()
            && entry.poll
            && last.poll
            && last.name == entry.name
            && last.outcome == entry.outcome
        {
            let count = last.count.saturating_add(count);
            *last = Arc::new(LogEntry { count, ..entry });
            return;
        }
        if self.log.len() >= LOG_CAPACITY {
            self.log.pop_front();
        }
        self.log.push_back(Arc::new(LogEntry { count, ..entry }));
    }

    pub(in crate::console::app) fn help_scroll(&self) -> usize {
        self.help_scroll
    }

    pub(in crate::console::app) fn open_help(&mut self) {
        self.help_scroll = 0;
        self.overlay = Overlay::Help;
    }

    /// Scrolls the help for a scrolling key and says whether it was one.
    pub(in crate::console::app) fn on_help_key(&mut self, key: &KeyName, keymap: &Keymap) -> bool {
        let (last, page) = scroll_limits(keymap, self.size);
        let now = self.help_scroll.min(last);
        self.help_scroll = match *key {
            DOWN => now + 1,
            UP => now.saturating_sub(1),
            PAGE_DOWN => now + page,
            PAGE_UP => now.saturating_sub(page),
            HOME => 0,
            END => last,
            _ => return false,
        }
        .min(last);
        true
    }

    pub(in crate::console::app) fn message(&self) -> Option<(&str, Severity)> {
        self.messages.shown().map(|m| (m.text.as_str(), m.severity))
    }

    pub(in crate::console::app) fn say_until(
        &mut self,
        text: String,
        severity: Severity,
        until: Until,
        now: Instant,
    ) {
        self.messages.say(text, severity, until, now);
    }

    pub(in crate::console::app) fn message_deadline(&self) -> Option<Instant> {
        self.messages.deadline()
    }

    /// Arm events that end a message (see [`Messages::on_arm`]).
    pub(in crate::console::app) fn messages_on_arm(
        &mut self,
        event: &ArmEvent,
        telemetry_expected: bool,
    ) {
        self.messages.on_arm(event, telemetry_expected);
    }

    /// Messages whose state no longer `holds` go (see [`Messages::settle`]).
    pub(in crate::console::app) fn settle_messages(&mut self, holds: impl Fn(&Message) -> bool) {
        self.messages.settle(holds);
    }

    /// What the screen shows, its log cut to the newest `rows` lines.
    pub(in crate::console::app) fn view(&self, rows: usize) -> ScreenView {
        ScreenView {
            size: self.size,
            log: self
                .log
                .iter()
                .skip(self.log.len().saturating_sub(rows))
                .cloned()
                .collect(),
            hex: self.hex,
            message: self
                .message()
                .map(|(text, severity)| (text.to_string(), severity)),
            overlay: self.overlay.clone(),
            help_scroll: self.help_scroll,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_go_to_in_question_is_named_only_by_a_go_to_question() {
        let mut screen = Screen::default();
        assert_eq!(screen.goto_in_question(), None);
        screen.show(Overlay::Confirm(Confirm::GoTo("bench".into())));
        assert_eq!(screen.goto_in_question(), Some("bench".into()));
        screen.show(Overlay::Confirm(Confirm::Resave("bench".into())));
        assert_eq!(screen.goto_in_question(), None);
        screen.show(Overlay::Confirm(Confirm::Home));
        assert_eq!(screen.goto_in_question(), None);
    }
}
