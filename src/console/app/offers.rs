//! What the console offers on this link: a key whose action cannot work here is not shown in
//! the footer, and pressing it says why instead of opening a form.

use crate::console::form::{Form, FormKind};
use crate::link::interface::TelemetrySource;

use super::App;

impl App {
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
}

impl App {
    /// Whether this link carries an orientation jog (the footer offers the turn keys).
    ///
    /// Only a Modbus link turns the tool (Talos has no orientation jog; the driver refuses it
    /// with `ORIENTATION_NEEDS_MODBUS`). The driver expects Modbus telemetry exactly when it has
    /// a Modbus link, so a link that expects other telemetry (or none) cannot turn. Until the
    /// driver has said, the turn is offered, as saving is.
    pub fn can_turn(&self) -> bool {
        !matches!(
            self.truth.expected_telemetry(),
            Some(TelemetrySource::TalosHardware | TelemetrySource::None)
        )
    }
}

impl App {
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
