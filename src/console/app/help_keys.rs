//! The help overlay's keys: down/up scroll a line, pagedown/pageup a page, home/end to the
//! ends; any other key closes it.

use super::App;
use crate::console::keymap::KeyName;

impl App {
    /// The help overlay's first shown line.
    pub fn help_scroll(&self) -> usize {
        self.screen.help_scroll()
    }

    pub(super) fn open_help(&mut self) {
        self.screen.open_help();
    }

    /// Scrolls the help for a scrolling key and says whether it was one (the help stays open).
    pub(super) fn scroll_help(&mut self, key: &KeyName) -> bool {
        self.screen.on_help_key(key, &self.config.keymap)
    }
}
