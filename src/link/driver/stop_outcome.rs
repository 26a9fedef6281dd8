//! One outcome per STOP: [`ArmEvent::StopConfirmed`] once every link that carried motion answered
//! it, [`ArmEvent::StopUnconfirmed`] if any could not (a link that carried motion and is down is
//! unconfirmed at once). Each side reports one `Done` or `Failed` per command.

use std::collections::VecDeque;

use crate::link::interface::{ArmCommand, ArmError, ArmEvent};

/// The two links the driver may have.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    Talos = 0,
    Modbus = 1,
}

impl Side {
    fn name(self) -> &'static str {
        match self {
            Side::Talos => "the Talos operator",
            Side::Modbus => "the Modbus arm",
        }
    }
}

/// A STOP still waiting for some link's answer.
#[derive(Debug)]
struct Pending {
    owed: [bool; 2],
    failure: Option<String>,
}

#[derive(Debug, Default)]
pub struct StopOutcomes {
    /// Links that carried motion since they last answered a STOP.
    carried: [bool; 2],
    pending: VecDeque<Pending>,
}

impl StopOutcomes {
    /// `side` was given a command that moves the arm.
    pub fn motion(&mut self, command: &ArmCommand, side: Side) {
        if command.starts_motion() {
            self.carried[side as usize] = true;
        }
    }

    /// A STOP went to `sent`; `down` had no connection. The outcome at once when nothing is owed.
    pub fn stop(&mut self, sent: &[Side], down: &[Side]) -> Option<ArmEvent> {
        let failure = down
            .iter()
            .find(|side| self.carried[**side as usize])
            .map(|side| format!("no link to {}: the STOP could not be sent", side.name()));
        let mut owed = [false; 2];
        for side in sent {
            owed[*side as usize] = true;
        }
        let pending = Pending { owed, failure };
        if owed == [false; 2] {
            return Some(pending.outcome());
        }
        self.pending.push_back(pending);
        None
    }

    /// `side`'s answer to the oldest STOP it owes; that STOP's outcome once nothing more is owed.
    pub fn answer(&mut self, side: Side, result: Result<(), &ArmError>) -> Option<ArmEvent> {
        let index = self.pending.iter().position(|p| p.owed[side as usize])?;
        let pending = &mut self.pending[index];
        pending.owed[side as usize] = false;
        match result {
            Ok(()) => self.carried[side as usize] = false,
            Err(reason) => {
                let reason = format!("{}: {reason}", side.name());
                pending.failure.get_or_insert(reason);
            }
        }
        if pending.owed != [false; 2] {
            return None;
        }
        self.pending.remove(index).map(Pending::outcome)
    }
}

impl Pending {
    fn outcome(self) -> ArmEvent {
        match self.failure {
            None => ArmEvent::StopConfirmed,
            Some(reason) => ArmEvent::StopUnconfirmed { reason },
        }
    }
}

/// The stop outcome an event from one link's side carries, if it answers a STOP.
pub fn stop_answer(event: &ArmEvent) -> Option<Result<(), &ArmError>> {
    match event {
        ArmEvent::Done { command } if command.is_stop() => Some(Ok(())),
        ArmEvent::Failed { command, error } if command.is_stop() => Some(Err(error)),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::link::interface::{CommandKind, StepMove};

    const STEP: ArmCommand = ArmCommand::Step(StepMove::Polar {
        azimuth: 1,
        altitude: 0,
    });

    #[test]
    fn a_stop_is_confirmed_once_every_link_given_it_answered() {
        let mut outcomes = StopOutcomes::default();
        outcomes.motion(&STEP, Side::Talos);
        assert_eq!(outcomes.stop(&[Side::Talos, Side::Modbus], &[]), None);
        assert_eq!(outcomes.answer(Side::Modbus, Ok(())), None);
        assert_eq!(
            outcomes.answer(Side::Talos, Ok(())),
            Some(ArmEvent::StopConfirmed)
        );
        assert_eq!(outcomes.answer(Side::Talos, Ok(())), None, "nothing owed");
    }

    #[test]
    fn one_failed_link_makes_the_stop_unconfirmed() {
        let mut outcomes = StopOutcomes::default();
        outcomes.stop(&[Side::Talos, Side::Modbus], &[]);
        let no_reply = ArmError::StopNotWritten("no reply within 500 ms".into());
        outcomes.answer(Side::Talos, Err(&no_reply));
        let Some(ArmEvent::StopUnconfirmed { reason }) = outcomes.answer(Side::Modbus, Ok(()))
        else {
            panic!("expected an unconfirmed stop");
        };
        assert!(
            reason.contains("Talos") && reason.contains("500 ms"),
            "{reason}"
        );
    }

    #[test]
    fn a_link_that_carried_motion_and_is_down_cannot_confirm() {
        let mut outcomes = StopOutcomes::default();
        outcomes.motion(&STEP, Side::Talos);
        assert!(matches!(
            outcomes.stop(&[], &[Side::Talos]),
            Some(ArmEvent::StopUnconfirmed { .. })
        ));
        // A link that moved nothing owes nothing.
        let mut idle = StopOutcomes::default();
        assert_eq!(
            idle.stop(&[], &[Side::Talos]),
            Some(ArmEvent::StopConfirmed)
        );
    }

    #[test]
    fn only_a_stop_kind_failure_answers_a_stop() {
        let failed = |command| ArmEvent::Failed {
            command,
            error: ArmError::StopNotWritten("timeout".into()),
        };
        assert_eq!(
            stop_answer(&failed(CommandKind::QuickStop)).map(|r| r.map_err(|e| e.to_string())),
            Some(Err("STOP COULD NOT BE WRITTEN: timeout".into()))
        );
        assert!(matches!(
            stop_answer(&failed(CommandKind::Stop)),
            Some(Err(_))
        ));
        assert_eq!(stop_answer(&failed(CommandKind::Jog)), None);
    }

    #[test]
    fn answers_go_to_the_oldest_stop_each_link_owes() {
        let mut outcomes = StopOutcomes::default();
        outcomes.stop(&[Side::Modbus], &[]);
        outcomes.stop(&[Side::Modbus], &[]);
        assert!(matches!(
            outcomes.answer(
                Side::Modbus,
                Err(&ArmError::StopNotWritten("timeout".into()))
            ),
            Some(ArmEvent::StopUnconfirmed { .. })
        ));
        assert_eq!(
            outcomes.answer(Side::Modbus, Ok(())),
            Some(ArmEvent::StopConfirmed)
        );
    }
}
