//! Terminal input, read and decoded by the console itself.
//!
//! crossterm's reader cannot be made to drain: it waits on an edge-triggered epoll, reads one
//! 1024-byte block, and returns as soon as that block makes one event, leaving the rest of the
//! backlog in the terminal until new bytes make a new edge (the next key press). After a paste
//! every key then read one more block, and waited behind it. It also keeps a whole bracketed
//! paste in memory, however large, and an unended one swallows every later key. So the
//! console reads the terminal itself, on its own file description, on the runtime's thread
//! ([`reader`]), decodes keys with a port of crossterm's key parser ([`keys`]) and pastes with
//! a bounded decoder ([`decoder`]), and drops floods of keys ([`burst`]).

pub mod burst;
pub mod decoder;
pub mod keys;
pub mod reader;

pub use reader::{Refusal, TerminalEvent, TerminalInput, open};
