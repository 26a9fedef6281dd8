//! The stop set written the moment the jog key comes up, by the reader that reads its release.
//!
//! After each input the event loop names the jog key whose release alone stops the arm
//! (`JogEngine::stopped_by_release`: the one home of that fact). The reader checks each key event
//! it decodes against it, in the order read, and on a match has the Talos link write the stop
//! set it keeps encoded ahead ([`StopAhead`]) before the event goes on. The release then reaches
//! the app as any other, and the app stops the arm as it always does: its own stop set (and
//! the Modbus STOP) follow. A key is fired for once; the loop names it again if it must.

use std::sync::Arc;

use crossterm::event::{Event, KeyEventKind};

use crate::console::action::Action;
use crate::console::keymap::{KeyName, Keymap};
use crate::key_stages::{self, Stage};
use crate::link::talos::{AheadOutcome, StopAhead};

/// Which release has the stop set written ahead, and where.
pub struct ReleaseStop {
    ahead: StopAhead,
    keymap: Arc<Keymap>,
    armed: Option<Action>,
}

impl ReleaseStop {
    /// `keymap` must be the app's: a release is matched to jog actions as the app matches it.
    pub fn new(ahead: StopAhead, keymap: Arc<Keymap>) -> ReleaseStop {
        ReleaseStop {
            ahead,
            keymap,
            armed: None,
        }
    }

    /// The jog action whose key's release writes the stop set (`None`: no release does).
    pub fn arm(&mut self, action: Option<Action>) {
        self.armed = action;
    }

    pub fn armed(&self) -> Option<Action> {
        self.armed
    }

    /// A decoded terminal event, in the order read: the armed key's release writes the stop
    /// set now. Returns what the write did, if one was tried.
    pub fn on_event(&mut self, event: &Event) -> Option<AheadOutcome> {
        let action = self.armed?;
        let Event::Key(key) = event else {
            return None;
        };
        if key.kind != KeyEventKind::Release {
            return None;
        }
        let name = KeyName::from_event(key)?;
        if !self.keymap.release_candidates(&name).contains(&action) {
            return None;
        }
        self.armed = None;
        key_stages::mark(Stage::Encoded);
        let outcome = self.ahead.write_now();
        key_stages::mark(Stage::Written);
        tracing::debug!("{action:?} released: stop set written ahead: {outcome:?}");
        Some(outcome)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};

    fn key(c: char, modifiers: KeyModifiers, kind: KeyEventKind) -> Event {
        let mut event = KeyEvent::new(KeyCode::Char(c), modifiers);
        event.kind = kind;
        Event::Key(event)
    }

    fn release_stop() -> ReleaseStop {
        let keymap = Keymap::builtin("default").expect("the default keymap");
        ReleaseStop::new(StopAhead::new(), Arc::new(keymap))
    }

    #[test]
    fn only_the_armed_keys_release_fires_and_only_once() {
        let mut stop = release_stop();
        let w = Action::JogXPlus;
        let release_w = key('w', KeyModifiers::NONE, KeyEventKind::Release);
        assert_eq!(stop.on_event(&release_w), None, "nothing armed");
        stop.arm(Some(w));
        for other in [
            key('w', KeyModifiers::NONE, KeyEventKind::Press),
            key('w', KeyModifiers::NONE, KeyEventKind::Repeat),
            key('s', KeyModifiers::NONE, KeyEventKind::Release),
            Event::FocusGained,
        ] {
            assert_eq!(stop.on_event(&other), None, "{other:?}");
            assert_eq!(stop.armed(), Some(w));
        }
        // No link attached: the write is tried, and says so.
        assert_eq!(stop.on_event(&release_w), Some(AheadOutcome::NoLink));
        assert_eq!(stop.armed(), None);
        assert_eq!(stop.on_event(&release_w), None, "once");
    }

    #[test]
    fn a_release_carrying_shift_still_fires_as_the_app_would_release_it() {
        let mut stop = release_stop();
        stop.arm(Some(Action::JogXPlus));
        let shifted = key('W', KeyModifiers::SHIFT, KeyEventKind::Release);
        assert_eq!(stop.on_event(&shifted), Some(AheadOutcome::NoLink));
    }
}
