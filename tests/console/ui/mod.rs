//! The panels and the whole screen (`armjog::console::ui`) drawn on ratatui's `TestBackend` from
//! a `View`; insta snapshots in `snapshots/`.

mod arm_view;
mod fence;
mod help;
mod hostile_text;
mod long_names;
mod motion_truth;
mod nonsense;
mod panels;
mod questions;
mod screen_sizes;
mod simulated_arm;
mod tours;
