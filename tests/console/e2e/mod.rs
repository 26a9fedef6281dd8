//! The console's state machine and the real arm driver against the simulator (or a scripted
//! operator) over real sockets, driven through `crate::event_loop` as the runtime would. No
//! terminal.

mod cap;
mod fence;
mod jog;
mod motion_truth;
mod near_limit;
mod orientation;
mod other_client;
mod other_client_default;
mod positions;
mod singularity;
mod stored_actions;
mod tours;
