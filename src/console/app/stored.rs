//! Stored actions and sequences by id: the key opens the form (or says why it cannot work on
//! this link), the submitted form asks before it moves, a yes starts it, and any key stops a
//! stored run (home among them) while it runs. The run is watched to its end as home is
//! (`motion_truth/actions.rs`).

use std::time::Instant;

use super::{App, Effect, KeyInput, Overlay, Severity};
use crate::console::form::{Confirm, Form};
use crate::console::jog::KeyKind;
use crate::kortex::Stored;
use crate::link::interface::ArmCommand;

/// Why the stored action key does nothing on a link without Modbus.
pub const STORED_REFUSAL: &str = "stored actions and sequences by id need a Modbus link: over \
     Talos only home (h) runs; add --modbus";

impl App {
    /// Why a stored action or sequence by id cannot start on this link, or `None` when it can.
    /// Until the driver has said which link it has, it is offered (as the turn keys are).
    pub fn stored_refusal(&self) -> Option<&'static str> {
        self.without_modbus().then_some(STORED_REFUSAL)
    }

    /// Whether this link can run a stored action or sequence by id (the footer offers the key).
    pub fn can_run_stored(&self) -> bool {
        self.stored_refusal().is_none()
    }

    /// The stored action key: the form, or why not (the link, or the motion gate).
    pub(super) fn open_stored_form(&mut self, now: Instant) {
        if let Some(why) = self.stored_refusal() {
            self.say(why, Severity::Warning, now);
            return;
        }
        if !self.refuse_motion(now) {
            self.screen.show(Overlay::Form(Form::stored()));
        }
    }

    /// The form was submitted: ask before it moves.
    pub(super) fn ask_stored(&mut self, stored: Stored) {
        self.screen.show(Overlay::Confirm(Confirm::Stored(stored)));
    }

    /// Yes to "Run action 5 on the arm?" (the motion gate has just let it through).
    pub(super) fn run_stored(&mut self, stored: Stored, now: Instant, effects: &mut Vec<Effect>) {
        match self.stored_refusal() {
            Some(why) => self.say(why, Severity::Warning, now),
            None => effects.push(Effect::Arm(ArmCommand::StartStored(stored))),
        }
    }

    /// A key pressed while a stored run (home among them) is running stops it and does nothing
    /// else; returns whether it did.
    pub(super) fn key_stops_stored_run(
        &mut self,
        key: &KeyInput,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) -> bool {
        let running = self
            .truth
            .action()
            .is_some_and(|action| action.kind.stops_on_any_key());
        if key.kind != KeyKind::Press || !running {
            return false;
        }
        // The truth says "<run> stopped" as the STOP goes out; the key is latched like any key
        // that stops, so a held jog key moves only when pressed anew.
        self.stop_everything(now, effects);
        self.latch_jog_key(key, now, effects);
        true
    }
}
