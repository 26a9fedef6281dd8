//! The console: app state machine, jog engine, keymaps and the panels under `ui/`.

pub mod action;
pub mod jog;
