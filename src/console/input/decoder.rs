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
        if let Some(paste) = self.paste.take() {
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
