//! Terminal input, read and decoded by the console itself ([`reader`], [`keys`], [`decoder`],
//! [`burst`]): crossterm's reader leaves a backlog unread until the next key and keeps a whole
//! bracketed paste, however large, in memory.

pub mod burst;
pub mod decoder;
pub mod keys;
pub mod reader;

pub use reader::{Refusal, TerminalEvent, TerminalInput, open};
