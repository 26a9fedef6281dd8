//! The terminal's bytes as events: key sequences (see [`super::keys`]) and bracketed pastes
//! (`ESC [200~ … ESC [201~`), a paste kept only up to [`PASTE_LIMIT`] bytes however long it is.

use crossterm::event::Event;

use super::keys::{self, Parsed};

/// The most of a paste that is kept: far above any field, far below a memory worry.
pub const PASTE_LIMIT: usize = 64 * 1024;
/// A sequence still incomplete at this length is garbage.
const MAX_SEQUENCE: usize = 64;
const PASTE_START: &[u8] = b"\x1b[200~";
const PASTE_END: &[u8] = b"\x1b[201~";

/// What the bytes made.
#[derive(Debug, Clone, PartialEq)]
pub enum Decoded {
    Event(Event),
    /// A whole paste within [`PASTE_LIMIT`] (invalid UTF-8 replaced).
    Paste(String),
    /// A paste over the limit (`finished`), or one whose end never came: its text was dropped.
    PasteRefused {
        bytes: usize,
        finished: bool,
    },
}

/// A streaming decoder: bytes go in as they are read, in any pieces.
#[derive(Debug, Default)]
pub struct Decoder {
    /// The sequence begun and not yet complete.
    pending: Vec<u8>,
    paste: Option<Paste>,
    /// Bytes taken outside pastes, ever: the reader counts a burst of keys with it.
    key_bytes: usize,
}

#[derive(Debug, Default)]
struct Paste {
    text: Vec<u8>,
    /// Every byte of the paste, kept or not.
    bytes: usize,
    /// How much of [`PASTE_END`] the latest bytes match.
    matched: usize,
}

impl Paste {
    fn take(&mut self, bytes: &[u8]) {
        self.bytes += bytes.len();
        let room = PASTE_LIMIT.saturating_sub(self.text.len());
        self.text.extend_from_slice(&bytes[..bytes.len().min(room)]);
    }

    /// Takes bytes of the paste up to its end; returns how many were used and whether the end
    /// was among them.
    fn feed(&mut self, bytes: &[u8]) -> (usize, bool) {
        let mut start = 0;
        for (i, &byte) in bytes.iter().enumerate() {
            if byte == PASTE_END[self.matched] {
                if self.matched == 0 {
                    self.take(&bytes[start..i]);
                }
                self.matched += 1;
                if self.matched == PASTE_END.len() {
                    return (i + 1, true);
                }
                continue;
            }
            if self.matched > 0 {
                // Not the end after all: what looked like it is text.
                let partial = self.matched;
                self.matched = 0;
                self.take(&PASTE_END[..partial]);
                start = i;
                if byte == PASTE_END[0] {
                    self.matched = 1;
                }
            }
        }
        if self.matched == 0 {
            self.take(&bytes[start..]);
        }
        (bytes.len(), false)
    }

    fn decoded(self, finished: bool) -> Decoded {
        if finished && self.bytes <= PASTE_LIMIT {
            Decoded::Paste(String::from_utf8_lossy(&self.text).into_owned())
        } else {
            Decoded::PasteRefused {
                bytes: self.bytes,
                finished,
            }
        }
    }
}

impl Decoder {
    /// Decodes `bytes`; a sequence cut at the end of them waits for the next.
    pub fn feed(&mut self, mut bytes: &[u8], out: &mut Vec<Decoded>) {
        while !bytes.is_empty() {
            if let Some(paste) = &mut self.paste {
                let (used, ended) = paste.feed(bytes);
                bytes = &bytes[used..];
                if ended && let Some(paste) = self.paste.take() {
                    out.push(paste.decoded(true));
                }
                continue;
            }
            self.key_bytes += 1;
            self.pending.push(bytes[0]);
            bytes = &bytes[1..];
            self.advance(true, out);
        }
    }

    /// No more input is readable now: a lone ESC is the Esc key.
    pub fn end_of_input(&mut self, out: &mut Vec<Decoded>) {
        if self.pending == [0x1b] {
            self.advance(false, out);
        }
    }

    /// Input stopped inside a paste or a sequence: the paste is refused, the sequence dropped.
    pub fn stalled(&mut self, out: &mut Vec<Decoded>) {
        self.pending.clear();
        if let Some(mut paste) = self.paste.take() {
            // What looked like the start of its end is its text.
            paste.take(&PASTE_END[..paste.matched]);
            out.push(paste.decoded(false));
        }
    }

    /// Inside a paste or a sequence: the rest should come at once.
    pub fn waiting(&self) -> bool {
        self.paste.is_some() || !self.pending.is_empty()
    }

    /// Bytes taken outside pastes so far.
    pub fn key_bytes(&self) -> usize {
        self.key_bytes
    }

    fn advance(&mut self, more_may_come: bool, out: &mut Vec<Decoded>) {
        if self.pending.starts_with(PASTE_START) {
            self.pending.clear();
            self.paste = Some(Paste::default());
            return;
        }
        if PASTE_START.starts_with(&self.pending) && more_may_come {
            return;
        }
        match keys::parse(&self.pending, more_may_come) {
            Parsed::More if self.pending.len() < MAX_SEQUENCE => {}
            Parsed::More | Parsed::Invalid | Parsed::Done(None) => self.pending.clear(),
            Parsed::Done(Some(event)) => {
                self.pending.clear();
                out.push(Decoded::Event(event));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crossterm::event::{KeyCode, KeyEvent, KeyEventKind, KeyEventState, KeyModifiers};

    fn decode(pieces: &[&[u8]]) -> Vec<Decoded> {
        let mut decoder = Decoder::default();
        let mut out = Vec::new();
        for piece in pieces {
            decoder.feed(piece, &mut out);
        }
        decoder.end_of_input(&mut out);
        out
    }

    fn key(code: KeyCode, modifiers: KeyModifiers) -> Decoded {
        Decoded::Event(Event::Key(KeyEvent::new(code, modifiers)))
    }

    fn char_key(c: char) -> Decoded {
        key(KeyCode::Char(c), KeyModifiers::NONE)
    }

    #[test]
    fn a_bracketed_paste_is_text_whatever_it_holds_and_keys_around_it_stay_keys() {
        // Written by hand from xterm's bracketed-paste mode: ESC [ 200 ~ text ESC [ 201 ~.
        let bytes = b"a\x1b[200~why \x1b[A\r\x1b[20 q\x1b[201~ ";
        assert_eq!(
            decode(&[bytes]),
            [
                char_key('a'),
                Decoded::Paste("why \x1b[A\r\x1b[20 q".into()),
                char_key(' '),
            ]
        );
        // In any pieces, cut anywhere, even inside the markers.
        for cut in 1..bytes.len() {
            let (first, second) = bytes.split_at(cut);
            assert_eq!(decode(&[first, second]), decode(&[bytes]), "cut at {cut}");
        }
    }

    #[test]
    fn a_paste_over_the_limit_is_refused_and_never_kept_and_a_key_after_it_is_a_key() {
        let mut decoder = Decoder::default();
        let mut out = Vec::new();
        decoder.feed(b"\x1b[200~", &mut out);
        let chunk = vec![b'y'; 1024 * 1024];
        for _ in 0..100 {
            decoder.feed(&chunk, &mut out);
        }
        assert!(out.is_empty(), "nothing before the end");
        let kept = decoder.paste.as_ref().map(|p| p.text.capacity());
        assert!(kept.is_some_and(|c| c <= 2 * PASTE_LIMIT), "{kept:?}");
        decoder.feed(b"\x1b[201~ ", &mut out);
        assert_eq!(
            out,
            [
                Decoded::PasteRefused {
                    bytes: 100 * 1024 * 1024,
                    finished: true
                },
                char_key(' ')
            ]
        );
    }

    #[test]
    fn a_paste_whose_end_never_comes_is_refused_when_it_stalls() {
        let mut decoder = Decoder::default();
        let mut out = Vec::new();
        decoder.feed(b"\x1b[200~hy \x1b[201", &mut out);
        assert!(decoder.waiting());
        decoder.stalled(&mut out);
        assert_eq!(
            out,
            [Decoded::PasteRefused {
                bytes: 8,
                finished: false
            }]
        );
        decoder.feed(b" ", &mut out);
        assert_eq!(out.last(), Some(&char_key(' ')), "keys again after it");
    }

    #[test]
    fn keys_decode_as_crossterm_reports_them() {
        // Legacy xterm sequences and the kitty keyboard protocol, by hand from their specs.
        let kitty_release = Decoded::Event(Event::Key(KeyEvent::new_with_kind(
            KeyCode::Char('w'),
            KeyModifiers::NONE,
            KeyEventKind::Release,
        )));
        let keypad_5 = Decoded::Event(Event::Key(KeyEvent::new_with_kind_and_state(
            KeyCode::Char('5'),
            KeyModifiers::NONE,
            KeyEventKind::Press,
            KeyEventState::KEYPAD,
        )));
        let cases: [(&[u8], Vec<Decoded>); 13] = [
            (b"W", vec![key(KeyCode::Char('W'), KeyModifiers::SHIFT)]),
            ("é".as_bytes(), vec![char_key('é')]),
            (b"\x1b", vec![key(KeyCode::Esc, KeyModifiers::NONE)]),
            (b"\x1bx", vec![key(KeyCode::Char('x'), KeyModifiers::ALT)]),
            (
                b"\x03",
                vec![key(KeyCode::Char('c'), KeyModifiers::CONTROL)],
            ),
            (b"\x1b[1;5A", vec![key(KeyCode::Up, KeyModifiers::CONTROL)]),
            (b"\x1bOP", vec![key(KeyCode::F(1), KeyModifiers::NONE)]),
            (b"\x1b[5~", vec![key(KeyCode::PageUp, KeyModifiers::NONE)]),
            (b"\x1b[Z", vec![key(KeyCode::BackTab, KeyModifiers::SHIFT)]),
            (b"\x1b[119;1:3u", vec![kitty_release]),
            (
                b"\x1b[97:65;2u",
                vec![key(KeyCode::Char('A'), KeyModifiers::NONE)],
            ),
            (b"\x1b[57404u", vec![keypad_5]),
            (
                b"\x1b[O\x1b[?1u\x1b[12;40R",
                vec![Decoded::Event(Event::FocusLost)],
            ),
        ];
        for (bytes, want) in cases {
            assert_eq!(decode(&[bytes]), want, "{bytes:?}");
        }
    }

    #[test]
    fn kittys_keypad_and_function_key_codepoints_are_their_keys() {
        // By hand from the kitty keyboard protocol's table of functional key codes.
        let keypad = |code| {
            Decoded::Event(Event::Key(KeyEvent::new_with_kind_and_state(
                code,
                KeyModifiers::NONE,
                KeyEventKind::Press,
                KeyEventState::KEYPAD,
            )))
        };
        let cases: [(&[u8], Decoded); 8] = [
            (b"\x1b[57399u", keypad(KeyCode::Char('0'))),
            (b"\x1b[57413u", keypad(KeyCode::Char('+'))),
            (b"\x1b[57414u", keypad(KeyCode::Enter)),
            (b"\x1b[57417u", keypad(KeyCode::Left)),
            (b"\x1b[57426u", keypad(KeyCode::Delete)),
            (b"\x1b[57427u", keypad(KeyCode::KeypadBegin)),
            (b"\x1b[57376u", key(KeyCode::F(13), KeyModifiers::NONE)),
            (b"\x1b[57398u", key(KeyCode::F(35), KeyModifiers::NONE)),
        ];
        for (bytes, want) in cases {
            assert_eq!(decode(&[bytes]), vec![want], "{bytes:?}");
        }
        // Past the keypad's last key: a private-use codepoint, no key.
        assert_eq!(decode(&[b"\x1b[57428u"]), vec![]);
    }

    #[test]
    fn garbage_is_dropped_and_the_next_key_still_comes() {
        let mut garbage = b"\x1b[".to_vec();
        garbage.extend(std::iter::repeat_n(b'1', 200));
        garbage.extend(b"\xff\xfe ");
        assert_eq!(decode(&[&garbage]).last(), Some(&char_key(' ')));
    }
}
