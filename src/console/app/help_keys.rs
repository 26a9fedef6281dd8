//! The help overlay's keys: down/up scroll a line, pagedown/pageup a page, home/end to the
//! ends; any other key closes it.

use super::{App, Overlay};
use crate::console::keymap::{KeyName, NamedKey};
use crate::console::ui::help::scroll_limits;

const DOWN: KeyName = KeyName::named(NamedKey::Down);
const UP: KeyName = KeyName::named(NamedKey::Up);
const PAGE_DOWN: KeyName = KeyName::named(NamedKey::PageDown);
const PAGE_UP: KeyName = KeyName::named(NamedKey::PageUp);
const HOME: KeyName = KeyName::named(NamedKey::Home);
const END: KeyName = KeyName::named(NamedKey::End);

impl App {
    /// The help overlay's first shown line.
    pub fn help_scroll(&self) -> usize {
        self.screen.help_scroll
    }

    pub(super) fn open_help(&mut self) {
        self.screen.help_scroll = 0;
        self.screen.overlay = Overlay::Help;
    }

    /// Scrolls the help for a scrolling key and says whether it was one (the help stays open).
    pub(super) fn scroll_help(&mut self, key: &KeyName) -> bool {
        let (last, page) = scroll_limits(&self.config.keymap, self.screen.size);
        let now = self.screen.help_scroll.min(last);
        self.screen.help_scroll = match *key {
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
}
