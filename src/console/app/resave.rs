//! Names a Talos operator has lost: a go-to must not send the doomed Go To. The console offers
//! to re-save the name from the coordinates it remembers (Set Cartesian Position) and, once the
//! operator has taken them, goes there, as the technician confirmed.
//!
//! The go-to after a re-save is part of the one confirmation: it is dropped if anything else
//! happens first (any key, focus loss, the link going down, a signal), or if the operator takes
//! longer than [`RESAVE_GO_WITHIN`] to accept the coordinates. The arm never starts moving
//! without a fresh press.

use std::time::{Duration, Instant};

use super::{App, Effect, Input, Overlay, Severity};
use crate::console::form::Confirm;
use crate::link::interface::{ArmCommand, ArmError, ArmEvent, CommandKind, LinkStatus};
use crate::talos::ReturnCode;

/// How long after the technician's "yes" a re-saved position is still gone to.
pub const RESAVE_GO_WITHIN: Duration = Duration::from_secs(3);

/// The re-save offer's state.
#[derive(Debug, Clone, Default)]
pub(super) struct Resave {
    /// The position of the last Go To sent to the operator: its failure names no position.
    goto_sent: Option<String>,
    /// A confirmed re-save: go to the name when the operator accepts it, if in time.
    then_go: Option<(String, Instant)>,
}

impl App {
    /// The go-to key on `name`: the usual question, or the re-save offer for a name the operator
    /// is known to have lost.
    pub(super) fn ask_go_to(&mut self, name: String, now: Instant) {
        // Not asked when the answer could only be that it cannot work.
        if let Some(why) = self.go_to_refusal(&name) {
            self.say(why, Severity::Warning, now);
            return;
        }
        if self.refuse_motion(now) {
            return;
        }
        let lost = self.config.positions_on_operator
            && self
                .book
                .positions()
                .get(&name)
                .is_some_and(|e| e.unknown_to_operator);
        if !lost {
            self.screen.show(Overlay::Confirm(Confirm::GoTo(name)));
        } else if self.remembered_cartesian(&name).is_some() {
            self.screen.show(Overlay::Confirm(Confirm::Resave(name)));
        } else {
            self.say(
                format!("'{name}' is unknown to the operator and no coordinates are remembered"),
                Severity::Warning,
                now,
            );
        }
    }

    fn remembered_cartesian(&self, name: &str) -> Option<[i32; 3]> {
        self.book.positions().get(name).and_then(|e| e.cartesian)
    }

    /// The technician said yes to re-saving `name`.
    pub(super) fn resave_confirmed(
        &mut self,
        name: String,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) {
        let Some([x, y, z]) = self.remembered_cartesian(&name) else {
            self.say(
                format!("'{name}' has no coordinates remembered"),
                Severity::Warning,
                now,
            );
            return;
        };
        effects.push(Effect::Arm(ArmCommand::SetCartesianPosition {
            name: name.clone(),
            x,
            y,
            z,
        }));
        self.say(
            format!("re-saving '{name}' on the operator"),
            Severity::Info,
            now,
        );
        self.book.resave_mut().then_go = Some((name, now));
    }

    /// A Go To is being sent for `name`.
    pub(super) fn going_to(&mut self, name: &str) {
        self.book.resave_mut().goto_sent = Some(name.to_string());
    }

    /// The operator accepted Set Cartesian Position for `name`: the go-to a re-save was for.
    pub(super) fn after_resave(&mut self, name: &str, now: Instant, effects: &mut Vec<Effect>) {
        let Some((pending, asked)) = self
            .book
            .resave_mut()
            .then_go
            .take_if(|(n, _)| n.as_str() == name)
        else {
            return;
        };
        if now.saturating_duration_since(asked) > RESAVE_GO_WITHIN {
            self.say(
                format!("re-saved '{pending}' (too late to move there unasked: go to it again)"),
                Severity::Info,
                now,
            );
            return;
        }
        self.going_to(&pending);
        self.say(
            format!("re-saved '{pending}': moving there"),
            Severity::Info,
            now,
        );
        effects.push(Effect::Arm(ArmCommand::GoToPosition { name: pending }));
    }

    /// Anything but the operator's answer drops a pending go-to: only the technician's "yes",
    /// with nothing in between, moves the arm.
    pub(super) fn resave_watch(&mut self, input: &Input) {
        let interrupts = match input {
            Input::Key(key) => key.kind != crate::console::jog::KeyKind::Release,
            Input::FocusLost | Input::Signal(_) => true,
            Input::Arm(ArmEvent::Status(status)) => !matches!(status, LinkStatus::Up { .. }),
            _ => false,
        };
        if interrupts {
            self.book.resave_mut().then_go = None;
        }
    }

    /// A failed position command. Go To failing with UNKNOWN_POSITION offers the re-save;
    /// returns whether the failure was told here.
    pub(super) fn position_failed(
        &mut self,
        command: CommandKind,
        error: &ArmError,
        now: Instant,
    ) -> bool {
        match command {
            CommandKind::SetCartesianPosition => {
                self.book.resave_mut().then_go = None;
                false
            }
            CommandKind::GoToPosition
                if *error == ArmError::ReturnCode(ReturnCode::UNKNOWN_POSITION) =>
            {
                let Some(name) = self.book.resave_mut().goto_sent.take() else {
                    return false;
                };
                if let Some(entry) = self.book.positions_mut().get_mut(&name) {
                    entry.unknown_to_operator = true;
                }
                let can_offer = self.remembered_cartesian(&name).is_some();
                if can_offer && self.screen.overlay_is_none() && !self.keys.jog().is_jogging() {
                    self.screen
                        .show(Overlay::Confirm(Confirm::Resave(name.clone())));
                    self.say(
                        format!("the operator does not know '{name}'"),
                        Severity::Warning,
                        now,
                    );
                } else if can_offer {
                    self.say(
                        format!(
                            "the operator does not know '{name}': go to it again to re-save it \
                             from the remembered coordinates"
                        ),
                        Severity::Warning,
                        now,
                    );
                } else {
                    self.say(
                        format!(
                            "the operator does not know '{name}' and no coordinates are remembered"
                        ),
                        Severity::Warning,
                        now,
                    );
                }
                true
            }
            _ => false,
        }
    }
}
