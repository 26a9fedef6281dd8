//! The console: its state machine, jog engine, keymaps, panels (insta snapshots) and end-to-end
//! runs against the simulator, in a terminal (tmux) and without.
//!
//! One test binary for several former ones (linking one binary per file cost most of a CI
//! run): each module is one former `tests/<name>.rs`, so test paths read `<name>::<test>`.
//! Helpers shared with other binaries stay in `tests/<helper>/` and come in by path.

#[path = "../app_support/mod.rs"]
mod app_support;
#[path = "../common/mod.rs"]
mod common;

mod event_loop;

mod arm_view_ui;
mod cap_e2e;
mod cap_watch;
mod console_app;
mod console_audit;
mod console_book_load;
mod console_e2e;
mod console_help;
mod console_jog_keys;
mod console_logs_e2e;
mod console_messages;
mod console_truth;
mod console_truth_e2e;
mod console_truth_ui;
mod console_ui;
mod form_keys;
mod history;
mod hostile_text_ui;
mod jog_engine;
mod keymap;
mod long_names_ui;
mod motion_gate;
mod near_limit_e2e;
mod nonsense_ui;
mod orientation_e2e;
mod orientation_jog;
mod other_client;
mod other_client_default_e2e;
mod other_client_e2e;
mod other_client_rules;
mod pastes;
mod position_edits;
mod positions_e2e;
mod positions_pose;
mod positions_resave;
mod positions_unsaved;
mod profile_console_e2e;
mod readme_keys;
mod screen_sizes;
mod simulated_arm_ui;
mod singularity;
mod singularity_e2e;
mod speed_settings;
mod terminal_input;
mod tmux_console;
mod tmux_paste;
