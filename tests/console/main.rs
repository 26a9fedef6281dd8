//! The console: its state machine (`app/`), panels (`ui/`, insta snapshots), end-to-end runs
//! against the simulator (`e2e/`) and the real binary in tmux (`tmux/`); beside them the jog
//! engine, keymaps, the audit deriver, the terminal reader and the fence's writer.
//!
//! One test binary per folder (linking one binary per file cost most of a CI run): each module
//! is named for what it tests, so test paths read `<module>::<test>`. Helpers shared with other
//! binaries stay in `tests/<helper>/` and come in by path.

#[path = "../app_support/mod.rs"]
mod app_support;
#[path = "../common/mod.rs"]
mod common;
#[path = "../log_files/mod.rs"]
mod log_files;

mod event_loop;

mod app;
mod audit;
mod e2e;
mod fence_file;
mod jog_engine;
mod keymap;
mod mcap_spec;
mod readme_keys;
mod recorder;
mod recording_readback;
mod replay;
mod terminal_input;
mod tmux;
mod ui;
