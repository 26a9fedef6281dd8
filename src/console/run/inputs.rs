//! What the terminal and the process's signals give, as the state machine's inputs.

use crossterm::event::{Event, KeyCode, KeyEvent, KeyEventKind, KeyModifiers};

use crate::console::app::{Input, KeyInput, Pasted};
use crate::console::input::TerminalEvent;
use crate::console::jog::KeyKind;
use crate::console::keymap::{KeyName, shifted_letter};

/// Maps a crossterm key event to the state machine's input.
pub fn key_input(event: &KeyEvent) -> Option<KeyInput> {
    let key = KeyName::from_event(event)?;
    let text = match event.code {
        KeyCode::Char(c)
            if !event
                .modifiers
                .intersects(KeyModifiers::CONTROL | KeyModifiers::ALT) =>
        {
            // Some kitty-protocol terminals send shift+a as 'a' with SHIFT: the text is the
            // character the key is named for.
            if event.modifiers.contains(KeyModifiers::SHIFT) {
                Some(shifted_letter(c))
            } else {
                Some(c)
            }
        }
        _ => None,
    };
    let kind = match event.kind {
        KeyEventKind::Press => KeyKind::Press,
        KeyEventKind::Repeat => KeyKind::Repeat,
        KeyEventKind::Release => KeyKind::Release,
    };
    Some(KeyInput { key, text, kind })
}

/// What the terminal's event stream gave, as the state machine's input.
pub(super) fn terminal_event(event: Option<std::io::Result<TerminalEvent>>) -> Option<Input> {
    match event {
        Some(Ok(TerminalEvent::Event(event))) => terminal_input(event),
        Some(Ok(TerminalEvent::Paste(text))) => Some(Input::Paste(Pasted::Text(text))),
        Some(Ok(TerminalEvent::Refused(why))) => {
            Some(Input::Paste(Pasted::Refused(why.to_string())))
        }
        Some(Err(e)) => {
            tracing::error!("terminal input failed: {e}");
            Some(Input::Signal("terminal input error"))
        }
        None => Some(Input::Signal("terminal closed")),
    }
}

fn terminal_input(event: Event) -> Option<Input> {
    match event {
        Event::Key(key) => key_input(&key).map(Input::Key),
        Event::FocusLost => Some(Input::FocusLost),
        Event::FocusGained => Some(Input::FocusGained),
        Event::Resize(width, height) => Some(Input::Resize { width, height }),
        _ => None,
    }
}

/// SIGINT, SIGTERM and SIGHUP as one stream (see [`crate::console::signals`]).
pub(super) struct Signals {
    received: tokio::sync::mpsc::UnboundedReceiver<&'static str>,
}

impl Signals {
    pub(super) fn new() -> std::io::Result<Signals> {
        use tokio::signal::unix::SignalKind;
        let received = crate::console::signals::forward(&[
            (SignalKind::interrupt(), "SIGINT"),
            (SignalKind::terminate(), "SIGTERM"),
            (SignalKind::hangup(), "SIGHUP"),
        ])?;
        Ok(Signals { received })
    }

    /// The next signal. Never ends: the tasks that send them run as long as the runtime.
    pub(super) async fn next(&mut self) -> &'static str {
        match self.received.recv().await {
            Some(name) => name,
            None => std::future::pending().await,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crossterm::event::KeyEventState;

    fn event(code: KeyCode, modifiers: KeyModifiers, kind: KeyEventKind) -> KeyEvent {
        KeyEvent {
            code,
            modifiers,
            kind,
            state: KeyEventState::NONE,
        }
    }

    #[test]
    fn key_events_keep_their_kind_and_typed_text() {
        let press = key_input(&event(
            KeyCode::Char('w'),
            KeyModifiers::NONE,
            KeyEventKind::Press,
        ));
        let press = press.expect("w");
        assert_eq!(
            (press.key.to_string(), press.text, press.kind),
            ("w".into(), Some('w'), KeyKind::Press)
        );
        let release = key_input(&event(
            KeyCode::Char('w'),
            KeyModifiers::NONE,
            KeyEventKind::Release,
        ));
        assert_eq!(release.map(|k| k.kind), Some(KeyKind::Release));
        let shifted = key_input(&event(
            KeyCode::Char('a'),
            KeyModifiers::SHIFT,
            KeyEventKind::Press,
        ));
        assert_eq!(
            shifted.map(|k| (k.key.to_string(), k.text)),
            Some(("A".into(), Some('A')))
        );
        // A letter whose capital is two characters types itself, and is named for itself.
        for letter in ['ß', 'ŉ'] {
            let shifted = key_input(&event(
                KeyCode::Char(letter),
                KeyModifiers::SHIFT,
                KeyEventKind::Press,
            ));
            assert_eq!(
                shifted.map(|k| (k.key.to_string(), k.text)),
                Some((letter.to_string(), Some(letter)))
            );
        }
        let ctrl = key_input(&event(
            KeyCode::Char('c'),
            KeyModifiers::CONTROL,
            KeyEventKind::Press,
        ));
        assert_eq!(
            ctrl.map(|k| (k.key.to_string(), k.text)),
            Some(("ctrl+c".into(), None))
        );
    }
}
