//! The parts the console's state is made of, each owning one concern's facts. [`App`] holds
//! one of each and routes inputs to them; their fields are seen only inside `app`.
//!
//! [`App`]: super::App

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use super::cap_watch::CapWatch;
use super::history::History;
use super::trail::ToolTrail;
use super::{BookState, Overlay, Step, edits, form_keys, message, other_client, question};
use super::{resave, saving};
use crate::console::jog::{JogEngine, ReleaseMode};
use crate::console::keymap::KeyName;
use crate::console::positions::PositionBook;
use crate::kortex::{ReferenceFrame, Telemetry};
use crate::link::interface::{GuardStatus, LinkStatus, LogEntry};

/// The keys: the jog engine, step mode, and the traces that keep auto-repeat and hasty keys
/// from being taken for new presses.
#[derive(Debug, Clone)]
pub(super) struct Keys {
    pub(super) jog: JogEngine,
    pub(super) step: Step,
    /// The key that closed an overlay and when it was last seen: its auto-repeat must not be
    /// taken for new presses (and start a jog) once the overlay is gone.
    pub(super) swallowed: Option<(KeyName, Instant)>,
    /// The latest key event, and the key that opened the open form while its auto-repeat may
    /// still come: see `form_keys`.
    pub(super) last_key: Option<form_keys::KeyTrace>,
    pub(super) form_opener: Option<form_keys::FormOpener>,
    /// Keeps pasted and hasty keys from answering a question.
    pub(super) question_guard: question::QuestionGuard,
}

impl Keys {
    pub(super) fn new(release_mode: ReleaseMode, refresh: Duration) -> Keys {
        Keys {
            jog: JogEngine::new(release_mode, refresh),
            step: Step::default(),
            swallowed: None,
            last_key: None,
            form_opener: None,
            question_guard: question::QuestionGuard::default(),
        }
    }
}

/// The position book: its entries, the selection, edits, undo, re-saves and saves.
#[derive(Debug, Clone)]
pub(super) struct Book {
    pub(super) positions: PositionBook,
    /// Whether the book is loaded, still loading, or could not be read.
    pub(super) book_state: BookState,
    pub(super) selected: usize,
    /// A rename on the operator between its steps, and a restore waiting for its answer.
    pub(super) renaming: Option<edits::Renaming>,
    pub(super) restoring: Option<edits::Deleted>,
    /// The last deleted position, for undo (one level).
    pub(super) last_deleted: Option<edits::Deleted>,
    /// Re-saving names the operator lost (see `resave`).
    pub(super) resave: resave::Resave,
    /// The book's writes and the positions they failed to write.
    pub(super) saving: saving::Saving,
}

impl Book {
    pub(super) fn new(positions: PositionBook) -> Book {
        Book {
            positions,
            book_state: BookState::Ready,
            selected: 0,
            renaming: None,
            restoring: None,
            last_deleted: None,
            resave: resave::Resave::default(),
            saving: saving::Saving::default(),
        }
    }
}

/// What the driver says about the link and the arm, and what the console keeps of it.
#[derive(Debug, Clone)]
pub(super) struct Arm {
    pub(super) link: LinkStatus,
    pub(super) telemetry: Option<Telemetry>,
    pub(super) latency: Option<Duration>,
    pub(super) speed: Option<u8>,
    pub(super) frame: ReferenceFrame,
    /// The stop guard's state, once the driver says one is required (Modbus motion).
    pub(super) guard: Option<GuardStatus>,
    /// The last 30 s of telemetry, for the history panel.
    pub(super) history: History,
    /// The tool point's recent path, for the arm view.
    pub(super) trail: ToolTrail,
    /// The speed cap as the telemetry shows it kept.
    pub(super) cap_watch: CapWatch,
    /// Other clients on the same arm: their stops and motions (see `other_client`).
    pub(super) others: other_client::OtherClients,
}

impl Default for Arm {
    fn default() -> Arm {
        Arm {
            link: LinkStatus::Connecting,
            telemetry: None,
            latency: None,
            speed: None,
            frame: ReferenceFrame::Base,
            guard: None,
            history: History::default(),
            trail: ToolTrail::default(),
            cap_watch: CapWatch::default(),
            others: other_client::OtherClients::default(),
        }
    }
}

/// The screen: what is drawn over the panels, the bottom line, the command log, the size.
#[derive(Debug, Clone)]
pub(super) struct Screen {
    pub(super) overlay: Overlay,
    /// The bottom line, each message tied to what ends it.
    pub(super) messages: message::Messages,
    pub(super) log: VecDeque<LogEntry>,
    pub(super) hex: bool,
    pub(super) size: (u16, u16),
    /// The help overlay's first shown line.
    pub(super) help_scroll: usize,
}

impl Default for Screen {
    fn default() -> Screen {
        Screen {
            overlay: Overlay::None,
            messages: message::Messages::default(),
            log: VecDeque::new(),
            hex: false,
            size: (80, 24),
            help_scroll: 0,
        }
    }
}
