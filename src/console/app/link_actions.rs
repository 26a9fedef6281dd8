//! The one rule of which actions the session's links carry ([`LinkActions`]).

use std::sync::Arc;

use crate::link::fence::Fence;

use crate::console::action::{Action, JogFamily};
use crate::console::keymap::Keymap;
use crate::link::speed::SpeedCap;

/// Which of the actions that only some links carry this session's links carry.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LinkActions {
    /// Saving the current pose ([`super::App::save_refusal`]).
    pub save: bool,
    /// The orientation jog: a Modbus link ([`super::App::can_turn`]).
    pub turn: bool,
    /// The single-joint jog: a Talos operator in the ICD dialect ([`super::App::can_jog_joints`]).
    pub joint: bool,
    /// Going to a saved position ([`super::App::go_to_refusal`]).
    pub go_to: bool,
    /// A stored action or sequence by id: a Modbus link ([`super::App::stored_refusal`]).
    pub stored: bool,
    /// Choosing the frame cartesian jogs are in: jogs over Modbus alone.
    pub frames: bool,
}

impl LinkActions {
    /// Everything, as on links that carry every action.
    pub const ALL: LinkActions = LinkActions {
        save: true,
        turn: true,
        joint: true,
        go_to: true,
        stored: true,
        frames: true,
    };

    /// Whether the links carry `action` (every action not named here, they all do).
    pub fn carries(&self, action: Action) -> bool {
        match action.jog().map(|(axis, _)| axis.family()) {
            Some(JogFamily::Joint) => return self.joint,
            Some(JogFamily::Orientation) => return self.turn,
            _ => {}
        }
        match action {
            Action::JointNext | Action::JointPrevious => self.joint,
            Action::SavePosition => self.save,
            Action::GoToPosition => self.go_to,
            Action::StoredAction => self.stored,
            Action::FrameCycle => self.frames,
            _ => true,
        }
    }
}

/// The session's fixed facts and what this link offers, as the status bar and footer show them.
#[derive(Debug, Clone, PartialEq)]
pub struct SessionView {
    /// Shared with the app: the keymap never changes during a session.
    pub keymap: Arc<Keymap>,
    /// The speed cap: the tool speed and the turn rate at the speed in force.
    pub cap: SpeedCap,
    /// Reference frames apply (Modbus jogging).
    pub frames: bool,
    /// The arm is the built-in simulator.
    pub simulated: bool,
    pub positions_on_operator: bool,
    /// Which actions the links carry: the footer offers keys for those only.
    pub link_actions: LinkActions,
    /// The arm profile the console was opened with (`--arm cell3`).
    pub arm_name: Option<String>,
    /// The arm profile's fence: the arm view draws it.
    pub fence: Option<Arc<Fence>>,
    /// The session is not recorded: the status bar says so.
    pub recording_off: bool,
    /// A recording played back (`REPLAY 12:03:41.250 ×1`): the status bar says so first.
    pub replay: Option<String>,
}
