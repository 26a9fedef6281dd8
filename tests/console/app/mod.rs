//! The console's state machine (`armjog::console::app`) on a fake clock: inputs in, effects and
//! view out. No terminal, no sockets.

mod book_load;
mod cap_watch;
mod fence;
mod form_keys;
mod goto_end;
mod guard_stops;
mod history;
mod jog_keys;
mod messages;
mod motion_gate;
mod motion_truth;
mod orientation_keys;
mod other_client;
mod other_client_rules;
mod pastes;
mod position_edits;
mod positions_pose;
mod positions_resave;
mod positions_shared;
mod positions_unsaved;
mod singularity;
mod state_machine;
pub(crate) mod stored_actions;
mod stored_not_ours;
mod tour_ends;
mod tour_position_edits;
pub(crate) mod tours;
