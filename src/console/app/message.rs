//! The bottom line's message, tied to what raised it: a notice times out, a state message stays
//! while its state holds, so the line never contradicts the status bar. A newer message hides an
//! older state message, which shows again if its state still holds.

use std::time::{Duration, Instant};

use super::{Severity, fault_reason};
use crate::link::interface::{ArmCommand, ArmError, ArmEvent, CommandKind};
use crate::talos::ReturnCode;

/// How long a notice stays.
pub(super) const MESSAGE_TIME: Duration = Duration::from_secs(6);

/// What ends a message.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) enum Until {
    /// A notice: gone after [`MESSAGE_TIME`], or once a command of this kind goes through.
    TimeOut { done: Option<CommandKind> },
    /// The link is down or not up yet: ends when it is up.
    LinkUp,
    /// The link is stale: ends when the arm is heard from again.
    LinkFresh,
    /// The arm in fault: ends when telemetry shows it gone, or a reset or the command goes through.
    FaultCleared {
        failed: Option<CommandKind>,
        reset_done: bool,
        fault_seen: bool,
    },
    /// The stop guard is down: ends when it is ready.
    GuardReady,
    /// A STOP did not get through: ends when a STOP is confirmed.
    StopConfirmed,
    /// Positions could not be written: ends when a write holds them.
    BookSaved,
    /// A save is being written ("saving 'pick'…"): ends when the writer reports it.
    BookWritten,
    /// The arm's own report refused a motion: ends when the report would let it start.
    ArmReady,
}

impl Until {
    /// A fault's message, waiting for the fault to clear.
    pub(super) fn fault(failed: Option<CommandKind>, fault_seen: bool) -> Until {
        Until::FaultCleared {
            failed,
            reset_done: false,
            fault_seen,
        }
    }

    /// What ends the message of a command that failed with `error`.
    pub(super) fn failure(command: CommandKind, error: &ArmError) -> Until {
        match error {
            ArmError::ReturnCode(ReturnCode::ARM_FAULT) => Until::fault(Some(command), false),
            _ => Until::TimeOut {
                done: Some(command),
            },
        }
    }

    fn is_notice(&self) -> bool {
        matches!(self, Until::TimeOut { .. })
    }
}

#[derive(Debug, Clone)]
pub(super) struct Message {
    pub(super) text: String,
    pub(super) severity: Severity,
    pub(super) at: Instant,
    pub(super) until: Until,
}

/// The message shown and the state message a newer one hides.
#[derive(Debug, Clone, Default)]
pub(super) struct Messages {
    shown: Option<Message>,
    hidden: Option<Message>,
}

impl Messages {
    /// When the shown notice times out.
    pub(super) fn deadline(&self) -> Option<Instant> {
        self.shown
            .as_ref()
            .filter(|m| m.until.is_notice())
            .map(|m| m.at + MESSAGE_TIME)
    }

    pub(super) fn shown(&self) -> Option<&Message> {
        self.shown.as_ref()
    }

    fn slots(&mut self) -> impl Iterator<Item = &mut Option<Message>> {
        [&mut self.shown, &mut self.hidden].into_iter()
    }

    /// Shows a message that lasts while `until`'s state holds.
    pub(super) fn say(&mut self, text: String, severity: Severity, until: Until, now: Instant) {
        let message = Message {
            text,
            severity,
            at: now,
            until,
        };
        if let Some(older) = self.shown.take()
            && !older.until.is_notice()
        {
            self.hidden = Some(older);
        }
        // One message per state: a newer one about the same state replaces the older.
        self.hidden.take_if(|h| h.until == message.until);
        self.shown = Some(message);
    }

    /// Arm events that end a message: a command through, a fault reset, telemetry without fault.
    pub(super) fn on_arm(&mut self, event: &ArmEvent, telemetry_expected: bool) {
        for slot in self.slots() {
            slot.take_if(|m| message_ended(&mut m.until, event, telemetry_expected));
        }
    }

    /// Messages whose state no longer `holds` go; a hidden one shows again once on top.
    pub(super) fn settle(&mut self, holds: impl Fn(&Message) -> bool) {
        for slot in self.slots() {
            slot.take_if(|m| !holds(m));
        }
        if self.shown.is_none() {
            self.shown = self.hidden.take();
        }
    }
}

/// Whether `event` ends a message waiting for `until` (updating what a fault message has seen).
fn message_ended(until: &mut Until, event: &ArmEvent, telemetry_expected: bool) -> bool {
    match (until, event) {
        (Until::TimeOut { done: Some(kind) }, ArmEvent::Done { command }) => {
            command.kind() == *kind
        }
        (
            Until::FaultCleared {
                failed,
                reset_done,
                fault_seen,
            },
            event,
        ) => match event {
            ArmEvent::Done {
                command: ArmCommand::FaultReset,
            } => {
                *reset_done = true;
                !telemetry_expected
            }
            ArmEvent::Done { command } => Some(command.kind()) == *failed,
            ArmEvent::Telemetry(t) => {
                if fault_reason(t).is_some() {
                    *fault_seen = true;
                    false
                } else {
                    *fault_seen || *reset_done
                }
            }
            _ => false,
        },
        _ => false,
    }
}
