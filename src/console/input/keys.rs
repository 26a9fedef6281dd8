//! One key sequence from the terminal's bytes, as crossterm's `KeyEvent`: a compact port of
//! crossterm 0.29's private `event/sys/unix/parse.rs` (keys, kitty `CSI … u`, focus reports);
//! mouse reports and protocol answers are recognised and dropped.
//!
//! The ported parts: Copyright (c) 2019 Timon, crossterm, under the MIT License, whose
//! permission notice is `licenses/crossterm-MIT.txt` and applies to them.

use crossterm::event::{Event, KeyCode, KeyEvent, KeyEventKind, KeyEventState, KeyModifiers};

/// What the bytes so far make.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Parsed {
    /// A sequence that has begun but is not complete.
    More,
    /// A complete sequence: an event, or one the console has no use for.
    Done(Option<Event>),
    /// Not a sequence: the bytes are dropped.
    Invalid,
}

/// Parses `bytes`, which start a sequence. `more_may_come`: a lone ESC may begin a sequence.
pub fn parse(bytes: &[u8], more_may_come: bool) -> Parsed {
    match bytes {
        [] => Parsed::More,
        [0x1b] if more_may_come => Parsed::More,
        [0x1b] | [0x1b, 0x1b] => key(KeyCode::Esc, KeyModifiers::NONE),
        [0x1b, b'O'] => Parsed::More,
        [0x1b, b'O', last] => match ss3_key(*last) {
            Some(code) => key(code, KeyModifiers::NONE),
            None => Parsed::Invalid,
        },
        [0x1b, b'[', ..] => csi(bytes),
        [0x1b, rest @ ..] => match parse(rest, more_may_come) {
            Parsed::Done(Some(Event::Key(mut event))) => {
                event.modifiers |= KeyModifiers::ALT;
                Parsed::Done(Some(Event::Key(event)))
            }
            other => other,
        },
        [b'\r', ..] => key(KeyCode::Enter, KeyModifiers::NONE),
        [b'\t', ..] => key(KeyCode::Tab, KeyModifiers::NONE),
        [0x7f, ..] => key(KeyCode::Backspace, KeyModifiers::NONE),
        // Raw mode: '\n' is ctrl+j, as in crossterm.
        [c @ 0x01..=0x1a, ..] => key(KeyCode::Char((c - 1 + b'a') as char), KeyModifiers::CONTROL),
        [c @ 0x1c..=0x1f, ..] => key(
            KeyCode::Char((c - 0x1c + b'4') as char),
            KeyModifiers::CONTROL,
        ),
        [0, ..] => key(KeyCode::Char(' '), KeyModifiers::CONTROL),
        _ => utf8_char(bytes),
    }
}

fn key(code: KeyCode, modifiers: KeyModifiers) -> Parsed {
    Parsed::Done(Some(Event::Key(KeyEvent::new(code, modifiers))))
}

fn ss3_key(last: u8) -> Option<KeyCode> {
    Some(match last {
        b'A' => KeyCode::Up,
        b'B' => KeyCode::Down,
        b'C' => KeyCode::Right,
        b'D' => KeyCode::Left,
        b'H' => KeyCode::Home,
        b'F' => KeyCode::End,
        b'P'..=b'S' => KeyCode::F(1 + last - b'P'),
        _ => return None,
    })
}

fn utf8_char(bytes: &[u8]) -> Parsed {
    let needed = match bytes[0] {
        0x00..=0x7f => 1,
        0xc0..=0xdf => 2,
        0xe0..=0xef => 3,
        0xf0..=0xf7 => 4,
        _ => return Parsed::Invalid,
    };
    if bytes[1..].iter().any(|b| b & 0b1100_0000 != 0b1000_0000) {
        return Parsed::Invalid;
    }
    if bytes.len() < needed {
        return Parsed::More;
    }
    match std::str::from_utf8(bytes)
        .ok()
        .and_then(|s| s.chars().next())
    {
        Some(c) => {
            // Uppercase letters carry shift, as crossterm reports them.
            let modifiers = if c.is_uppercase() {
                KeyModifiers::SHIFT
            } else {
                KeyModifiers::NONE
            };
            key(KeyCode::Char(c), modifiers)
        }
        None => Parsed::Invalid,
    }
}

/// `ESC [ …`: complete once a final byte (0x40..=0x7e) follows the parameters.
fn csi(bytes: &[u8]) -> Parsed {
    let body = &bytes[2..];
    // The Linux console's F1 to F5: `ESC [ [ A` to `ESC [ [ E`.
    if let [b'[', rest @ ..] = body {
        return match rest.first() {
            None => Parsed::More,
            Some(c @ b'A'..=b'E') => key(KeyCode::F(1 + c - b'A'), KeyModifiers::NONE),
            Some(_) => Parsed::Invalid,
        };
    }
    let Some((&last, params)) = body.split_last() else {
        return Parsed::More;
    };
    if !(0x40..=0x7e).contains(&last) {
        // Parameter and intermediate bytes; anything else breaks the sequence.
        return if (0x20..=0x3f).contains(&last) {
            Parsed::More
        } else {
            Parsed::Invalid
        };
    }
    // Private answers (keyboard flags, device attributes), mouse reports: not keys.
    if params
        .first()
        .is_some_and(|b| matches!(b, b'?' | b'<' | b'>'))
    {
        return Parsed::Done(None);
    }
    if params.is_empty() && last == b'M' {
        // X10 mouse: three more bytes follow.
        return Parsed::Done(None);
    }
    let Ok(params) = std::str::from_utf8(params) else {
        return Parsed::Invalid;
    };
    match last {
        b'I' if params.is_empty() => Parsed::Done(Some(Event::FocusGained)),
        b'O' if params.is_empty() => Parsed::Done(Some(Event::FocusLost)),
        b'Z' => Parsed::Done(Some(Event::Key(KeyEvent::new(
            KeyCode::BackTab,
            KeyModifiers::SHIFT,
        )))),
        b'~' => special_key(params),
        b'u' => kitty_key(params),
        _ => match ss3_key(last) {
            // Cursor position reports end in R too; only `CSI 1;m R` is F3.
            Some(code) if last != b'R' || params.starts_with("1;") => {
                let (modifiers, kind, state) = modifiers_and_kind(params.split(';').nth(1));
                Parsed::Done(Some(Event::Key(KeyEvent::new_with_kind_and_state(
                    code, modifiers, kind, state,
                ))))
            }
            _ => Parsed::Done(None),
        },
    }
}

/// `modifiers[:event-type]` (kitty; 1 + a bit mask).
fn modifiers_and_kind(field: Option<&str>) -> (KeyModifiers, KeyEventKind, KeyEventState) {
    let mut parts = field.unwrap_or("").split(':');
    let mask = parts
        .next()
        .and_then(|m| m.parse::<u8>().ok())
        .unwrap_or(1)
        .saturating_sub(1);
    let kind = match parts.next().and_then(|k| k.parse::<u8>().ok()) {
        Some(2) => KeyEventKind::Repeat,
        Some(3) => KeyEventKind::Release,
        _ => KeyEventKind::Press,
    };
    let mut modifiers = KeyModifiers::empty();
    for (bit, modifier) in [
        (1, KeyModifiers::SHIFT),
        (2, KeyModifiers::ALT),
        (4, KeyModifiers::CONTROL),
        (8, KeyModifiers::SUPER),
        (16, KeyModifiers::HYPER),
        (32, KeyModifiers::META),
    ] {
        if mask & bit != 0 {
            modifiers |= modifier;
        }
    }
    let mut state = KeyEventState::empty();
    if mask & 64 != 0 {
        state |= KeyEventState::CAPS_LOCK;
    }
    if mask & 128 != 0 {
        state |= KeyEventState::NUM_LOCK;
    }
    (modifiers, kind, state)
}

/// `CSI number[;modifiers[:type]] ~`.
fn special_key(params: &str) -> Parsed {
    let mut fields = params.split(';');
    let Some(Ok(number)) = fields.next().map(str::parse::<u8>) else {
        return Parsed::Invalid;
    };
    let code = match number {
        1 | 7 => KeyCode::Home,
        2 => KeyCode::Insert,
        3 => KeyCode::Delete,
        4 | 8 => KeyCode::End,
        5 => KeyCode::PageUp,
        6 => KeyCode::PageDown,
        v @ 11..=15 => KeyCode::F(v - 10),
        v @ 17..=21 => KeyCode::F(v - 11),
        v @ 23..=26 => KeyCode::F(v - 12),
        v @ 28..=29 => KeyCode::F(v - 15),
        v @ 31..=34 => KeyCode::F(v - 17),
        _ => return Parsed::Done(None),
    };
    let (modifiers, kind, state) = modifiers_and_kind(fields.next());
    Parsed::Done(Some(Event::Key(KeyEvent::new_with_kind_and_state(
        code, modifiers, kind, state,
    ))))
}

/// `CSI code[:shifted[:base]][;modifiers[:type][;text]] u` (kitty keyboard protocol).
fn kitty_key(params: &str) -> Parsed {
    let mut fields = params.split(';');
    let mut codes = fields.next().unwrap_or("").split(':');
    let Some(Ok(codepoint)) = codes.next().map(str::parse::<u32>) else {
        return Parsed::Invalid;
    };
    let (mut modifiers, kind, state) = modifiers_and_kind(fields.next());
    let (mut code, keypad) = match functional_key(codepoint) {
        Some(found) => found,
        None => match char::from_u32(codepoint) {
            Some('\x1b') => (KeyCode::Esc, false),
            Some('\r') => (KeyCode::Enter, false),
            Some('\t') if modifiers.contains(KeyModifiers::SHIFT) => (KeyCode::BackTab, false),
            Some('\t') => (KeyCode::Tab, false),
            Some('\x7f') => (KeyCode::Backspace, false),
            // Modifier keys, media keys and the like: no key the console knows.
            Some(_) if (57344..=63743).contains(&codepoint) => return Parsed::Done(None),
            Some(c) => (KeyCode::Char(c), false),
            None => return Parsed::Invalid,
        },
    };
    // With "report alternate keys", shift+key carries the shifted character: it is the key.
    if modifiers.contains(KeyModifiers::SHIFT)
        && let Some(shifted) = codes
            .next()
            .and_then(|c| c.parse::<u32>().ok())
            .and_then(char::from_u32)
    {
        code = KeyCode::Char(shifted);
        modifiers.remove(KeyModifiers::SHIFT);
    }
    let state = if keypad {
        state | KeyEventState::KEYPAD
    } else {
        state
    };
    Parsed::Done(Some(Event::Key(KeyEvent::new_with_kind_and_state(
        code, modifiers, kind, state,
    ))))
}

/// Kitty's private-use codepoints for keypad and function keys; `true` for the keypad.
fn functional_key(codepoint: u32) -> Option<(KeyCode, bool)> {
    use KeyCode::*;
    const KEYPAD_CHARS: &str = "0123456789./*-+";
    /// The keypad's other keys, 57414 to 57427 in order.
    #[rustfmt::skip]
    const KEYPAD_KEYS: [KeyCode; 14] = [
        Enter, Char('='), Char(','), Left, Right, Up, Down, PageUp, PageDown, Home, End, Insert,
        Delete, KeypadBegin,
    ];
    match codepoint {
        57399..=57413 => KEYPAD_CHARS
            .chars()
            .nth((codepoint - 57399) as usize)
            .map(|c| (Char(c), true)),
        57414..=57427 => Some((KEYPAD_KEYS[(codepoint - 57414) as usize], true)),
        57376..=57398 => Some((F((codepoint - 57376 + 13) as u8), false)),
        _ => None,
    }
}
