//! What the console offers on this link: a key whose action cannot work here is not shown in
//! the footer, and pressing it says why instead of opening a form.
//!
//! [`Offers`] is the one rule of which actions the session's links carry: the footer shows a
//! key only for an action they carry, and the refusals below say why for the rest.

use std::sync::Arc;

use crate::console::action::{Action, JogFamily};
use crate::console::form::{Form, FormKind};
use crate::link::interface::TelemetrySource;
use crate::link::speed::SpeedCap;

use super::App;
use crate::console::keymap::Keymap;

/// Which of the actions that only some links carry this session's links carry.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Offers {
    /// Saving the current pose ([`App::save_refusal`]).
    pub save: bool,
    /// The orientation jog: a Modbus link ([`App::can_turn`]).
    pub turn: bool,
    /// The single-joint jog: a Talos operator in the ICD dialect ([`App::can_jog_joints`]).
    pub joint: bool,
    /// Going to a saved position ([`App::go_to_refusal`]).
    pub go_to: bool,
    /// A stored action or sequence by id: a Modbus link ([`App::stored_refusal`]).
    pub stored: bool,
    /// Choosing the frame cartesian jogs are in: jogs over Modbus alone.
    pub frames: bool,
}

impl Offers {
    /// Everything, as on links that carry every action.
    pub const ALL: Offers = Offers {
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
    pub offers: Offers,
    /// The arm profile the console was opened with (`--arm cell3`).
    pub arm_name: Option<String>,
}

impl App {
    /// The session's part of the view.
    pub(super) fn session_view(&self) -> SessionView {
        let config = &self.config;
        SessionView {
            keymap: config.keymap.clone(),
            cap: self.cap,
            frames: config.frames,
            simulated: config.simulated,
            positions_on_operator: config.positions_on_operator,
            offers: self.offers(),
            arm_name: config.arm_name.clone(),
        }
    }

    /// Which of the actions that only some links carry this session's links carry.
    pub fn offers(&self) -> Offers {
        Offers {
            save: self.can_save_position(),
            turn: self.can_turn(),
            joint: self.can_jog_joints(),
            go_to: self.can_go_to(),
            stored: self.can_run_stored(),
            frames: self.config.frames,
        }
    }

    /// Whether a link carries a single-joint jog (the footer offers the joint keys).
    ///
    /// Only a Talos operator in the ICD dialect moves one joint (its hardware companion
    /// commands the actuator): Modbus cannot command a joint, and the ack dialect has no joint
    /// jog (the driver refuses either). The positions live on the operator exactly when there
    /// is such a link (`DriverConfig::positions_on_operator`), known from the start.
    pub fn can_jog_joints(&self) -> bool {
        self.config.positions_on_operator
    }

    /// Why saving the current pose cannot work on this link, or `None` when it can.
    ///
    /// An operator in the ICD dialect saves the pose itself. Otherwise the console stores the
    /// pose it reads from telemetry, so a link that the driver says sends none (a Talos operator
    /// in the ack dialect, with no Modbus link beside it) has no pose to save. Until the driver
    /// has said which telemetry to expect, saving is offered (the form checks again on submit).
    pub fn save_refusal(&self) -> Option<&'static str> {
        let no_telemetry = self.truth.expected_telemetry() == Some(TelemetrySource::None);
        (!self.config.positions_on_operator && no_telemetry).then_some(
            "cannot save here: this operator (ack dialect) keeps no positions and sends no \
             telemetry to read the pose from; add --modbus for telemetry",
        )
    }

    /// Whether saving the current pose can work on this link (see [`App::save_refusal`]).
    pub fn can_save_position(&self) -> bool {
        self.save_refusal().is_none()
    }

    /// Whether this link carries an orientation jog (the footer offers the turn keys).
    ///
    /// Only a Modbus link turns the tool (Talos has no orientation jog; the driver refuses it
    /// with `ORIENTATION_NEEDS_MODBUS`). Until the driver has said which link it has, the turn
    /// is offered, as saving is.
    pub fn can_turn(&self) -> bool {
        !self.without_modbus()
    }

    /// Why going to the position `name` cannot work on this link, or `None` when it can.
    ///
    /// An operator in the ICD dialect goes to its positions itself. Otherwise the console keeps
    /// the positions and moves the arm to their pose over Modbus: without a Modbus link (a Talos
    /// operator in the ack dialect) nothing can carry that move, whatever the book holds.
    pub fn go_to_refusal(&self, name: &str) -> Option<String> {
        if self.config.positions_on_operator {
            return None;
        }
        if self.without_modbus() {
            return Some(format!(
                "cannot go to '{name}': the console keeps this position, and only a Modbus link \
                 moves the arm to its coordinates (this operator, ack dialect, keeps no \
                 positions); add --modbus"
            ));
        }
        let entry = self.book.positions().get(name)?;
        if entry.cartesian.is_none() {
            return Some(format!("'{name}' has no coordinates stored"));
        }
        (entry.orientation.is_none() && self.arm.telemetry().is_none()).then(|| {
            format!(
                "cannot go to '{name}' yet: it has no orientation stored, and no telemetry \
                 has given the tool's"
            )
        })
    }

    /// Whether going to a saved position can work on this link at all (the footer offers the
    /// go-to key; see [`App::go_to_refusal`]).
    pub fn can_go_to(&self) -> bool {
        self.config.positions_on_operator || !self.without_modbus()
    }

    /// The driver has said it has no Modbus link: it expects Modbus telemetry exactly when it
    /// has one.
    pub(super) fn without_modbus(&self) -> bool {
        matches!(
            self.truth.expected_telemetry(),
            Some(TelemetrySource::TalosHardware | TelemetrySource::None)
        )
    }

    /// The form that saves the current pose on this link: over the console's own book (no
    /// Talos operator keeps the positions) it has no anchor toggle, which would do nothing.
    pub(super) fn save_form(&self) -> Form {
        if self.config.positions_on_operator {
            Form::new(FormKind::Save, "")
        } else {
            Form::save_to_own_book()
        }
    }
}
