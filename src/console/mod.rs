//! The console: app state machine, jog engine, keymaps and the panels under `ui/`.

pub mod action;
pub mod app;
pub mod arm_geometry;
pub mod audit;
pub mod book_io;
pub mod coords;
pub mod fence_file;
pub mod form;
pub mod input;
pub mod input_first;
pub mod jog;
pub mod keymap;
pub mod pacing;
pub mod painter;
pub mod positions;
pub mod recorder;
pub mod replay;
pub mod run;
pub mod signals;
pub mod terminal;
pub mod ui;
pub mod view;
