//! The arm interfaces the console drives. Each link owns its socket in a task; callers talk to
//! it over channels.

pub mod talos;

pub use talos::{Answer, Dialect, Exchange, TalosConfig, TalosError, TalosEvent, TalosLink};
