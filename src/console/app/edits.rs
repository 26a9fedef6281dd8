//! Changes to named positions beyond a plain save: overwrite (asked first), rename, undo delete. A
//! Talos operator has no rename: it is Set Cartesian Position under the new name, then Delete
//! Position of the old, stopping at the first step that fails; the book follows what the operator
//! accepted.

use std::time::Instant;

use super::{App, Effect, Overlay};
use crate::console::form::{Confirm, Form, FormResult, tour_list};
use crate::console::positions::BookEntry;
use crate::link::interface::{ArmCommand, ArmError, ArmEvent, CommandKind, LinkStatus};

/// A rename on the operator, between its steps.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Renaming {
    from: String,
    to: String,
    step: RenameStep,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum RenameStep {
    /// Asked where `from` is.
    Asking,
    /// Saving `to` at those coordinates.
    Saving,
    /// Deleting `from`.
    Deleting,
}

impl RenameStep {
    fn command(self) -> CommandKind {
        match self {
            RenameStep::Asking => CommandKind::GetPosition,
            RenameStep::Saving => CommandKind::SetCartesianPosition,
            RenameStep::Deleting => CommandKind::DeletePosition,
        }
    }
}

/// The last deleted position, which undo restores.
pub(super) type Deleted = (String, BookEntry);

impl App {
    /// A form was submitted: a name that exists is only replaced after a yes.
    pub(super) fn form_submitted(
        &mut self,
        result: FormResult,
        form: Form,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) {
        if matches!(
            result,
            FormResult::MakeTour { .. } | FormResult::PlayTour { .. }
        ) {
            self.tour_form_submitted(result, form, now, effects);
            return;
        }
        if self.book.positions().get(result.name()).is_some() {
            self.screen.show(Overlay::Confirm(Confirm::Overwrite {
                result,
                form: Box::new(form),
            }));
            return;
        }
        self.form_done(result, now, effects);
    }

    /// No to "overwrite?": the form comes back as typed, to change the name or cancel.
    pub(super) fn overwrite_declined(&mut self, result: &FormResult, mut form: Form, now: Instant) {
        form.focus = 0;
        form.error = Some(format!(
            "'{}' exists: change the name, or esc to cancel",
            result.name()
        ));
        self.screen.show(Overlay::Form(form));
        self.info("not overwritten", now);
    }

    pub(super) fn rename(
        &mut self,
        from: String,
        to: String,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) {
        let Some(entry) = self.book.positions().get(&from).cloned() else {
            self.warn(format!("'{from}' is gone: not renamed"), now);
            return;
        };
        if !self.config.positions_on_operator {
            self.book.positions_mut().remove(&from);
            *self.book.positions_mut().get_or_insert(&to) = entry;
            self.renamed(&from, &to, now, effects);
            return;
        }
        if let Some(renaming) = self.book.renaming() {
            let busy = format!("still renaming '{}': wait for it to finish", renaming.from);
            self.warn(busy, now);
            return;
        }
        if let (true, Some(parent)) = (entry.anchor, &entry.parent) {
            let text = format!(
                "'{from}' moves with '{parent}': the operator can only save it under a new name \
                 at fixed coordinates, so it is not renamed"
            );
            self.warn(text, now);
            return;
        }
        // Where the operator has it now (the book's copy may be old).
        effects.push(Effect::Arm(ArmCommand::GetPosition { name: from.clone() }));
        self.info(format!("renaming '{from}' to '{to}'…"), now);
        self.book.set_renaming(Some(Renaming {
            from,
            to,
            step: RenameStep::Asking,
        }));
    }

    pub(super) fn undo_delete(&mut self, now: Instant, effects: &mut Vec<Effect>) {
        let Some((name, entry)) = self.book.last_deleted().cloned() else {
            self.info("nothing deleted to restore", now);
            return;
        };
        if self.book.positions().get(&name).is_some() {
            self.warn(format!("'{name}' exists again: not restored over it"), now);
            return;
        }
        if !self.config.positions_on_operator {
            self.restored(name, entry, now, effects);
            return;
        }
        let Some([x, y, z]) = entry.cartesian else {
            let text = format!("'{name}' cannot be restored: its coordinates were never known");
            self.warn(text, now);
            return;
        };
        effects.push(Effect::Arm(ArmCommand::SetCartesianPosition {
            name: name.clone(),
            x,
            y,
            z,
        }));
        self.info(format!("restoring '{name}'…"), now);
        self.book.set_restoring(Some((name, entry)));
    }

    /// `entry` is back in the book under `name` (and, on an operator, saved there).
    fn restored(
        &mut self,
        name: String,
        entry: BookEntry,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) {
        let unanchored = match (&entry.anchor, &entry.parent) {
            (true, Some(parent)) if self.config.positions_on_operator => {
                format!(", no longer moving with '{parent}'")
            }
            _ => String::new(),
        };
        let at = entry
            .cartesian
            .map(|[x, y, z]| {
                let mm = |v: i32| f64::from(v) / 10.0;
                format!(" at {:.1} {:.1} {:.1} mm", mm(x), mm(y), mm(z))
            })
            .unwrap_or_default();
        let restored = self.book.positions_mut().get_or_insert(&name);
        *restored = entry;
        if self.config.positions_on_operator {
            // Saved by coordinates: the operator keeps no anchor for it.
            restored.anchor = false;
            restored.unknown_to_operator = false;
        }
        self.book.select(&name);
        self.book.forget_deleted();
        self.info(format!("restored '{name}'{at}{unanchored}"), now);
        self.save_book(&[&name], effects);
    }

    /// Drives a rename or restore on the operator; returns whether the event was one of its steps.
    pub(super) fn edits_on_arm(
        &mut self,
        event: &ArmEvent,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) -> bool {
        if let ArmEvent::Status(LinkStatus::Down { .. }) = event {
            // Nothing more will be answered; the link's own message says why.
            self.book.set_renaming(None);
            self.book.set_restoring(None);
            return false;
        }
        if let Some((name, entry)) = self.book.restoring().cloned() {
            match event {
                ArmEvent::Done {
                    command: ArmCommand::SetCartesianPosition { name: saved, .. },
                } if *saved == name => {
                    self.book.set_restoring(None);
                    self.restored(name, entry, now, effects);
                    return true;
                }
                ArmEvent::Failed {
                    command: CommandKind::SetCartesianPosition,
                    error,
                } => {
                    self.book.set_restoring(None);
                    let text = format!("restoring '{name}' failed: {error}; undo tries again");
                    self.error(text, now);
                    return true;
                }
                _ => {}
            }
        }
        self.rename_on_arm(event, now, effects)
    }

    fn rename_on_arm(&mut self, event: &ArmEvent, now: Instant, effects: &mut Vec<Effect>) -> bool {
        let Some(Renaming { from, to, step }) = self.book.renaming().cloned() else {
            return false;
        };
        match (step, event) {
            (RenameStep::Asking, ArmEvent::Position { name, coordinates }) if *name == from => {
                // An operator that answers without coordinates (ack dialect) leaves the book's.
                let known = self.book.positions().get(&from).and_then(|e| e.cartesian);
                let Some([x, y, z]) = coordinates.cartesian.or(known) else {
                    self.book.set_renaming(None);
                    let text = format!(
                        "not renamed: the operator did not say where '{from}' is, and the console \
                         does not know"
                    );
                    self.error(text, now);
                    return true;
                };
                effects.push(Effect::Arm(ArmCommand::SetCartesianPosition {
                    name: to.clone(),
                    x,
                    y,
                    z,
                }));
                self.set_rename_step(RenameStep::Saving);
                // The book notes where the old name is, as for any answer.
                false
            }
            (RenameStep::Asking, ArmEvent::UnknownPosition { name }) if *name == from => {
                self.book.set_renaming(None);
                let text = format!("not renamed: the operator does not know '{from}'");
                self.error(text, now);
                // The book marks the name, as for any answer.
                false
            }
            (
                RenameStep::Saving,
                ArmEvent::Done {
                    command: ArmCommand::SetCartesianPosition { name, x, y, z },
                },
            ) if *name == to => {
                let mut entry = self
                    .book
                    .positions()
                    .get(&from)
                    .cloned()
                    .unwrap_or_default();
                entry.cartesian = Some([*x, *y, *z]);
                entry.unknown_to_operator = false;
                *self.book.positions_mut().get_or_insert(&to) = entry;
                effects.push(Effect::Arm(ArmCommand::DeletePosition {
                    name: from.clone(),
                }));
                self.set_rename_step(RenameStep::Deleting);
                true
            }
            (
                RenameStep::Deleting,
                ArmEvent::Done {
                    command: ArmCommand::DeletePosition { name },
                },
            ) if *name == from => {
                self.book.set_renaming(None);
                self.book.positions_mut().remove(&from);
                self.renamed(&from, &to, now, effects);
                true
            }
            (step, ArmEvent::Failed { command, error }) if *command == step.command() => {
                self.book.set_renaming(None);
                self.rename_failed(step, &from, &to, error, now, effects);
                true
            }
            _ => false,
        }
    }

    /// `from` is now `to` in the book; tours visiting it follow and are named.
    fn renamed(&mut self, from: &str, to: &str, now: Instant, effects: &mut Vec<Effect>) {
        let tours = self.book.positions_mut().rename_in_tours(from, to);
        self.book.select(to);
        let text = if tours.is_empty() {
            format!("renamed '{from}' to '{to}'")
        } else {
            format!("renamed '{from}' to '{to}', in {} too", tour_list(&tours))
        };
        self.info(text, now);
        self.save_book(&[from, to], effects);
    }

    fn set_rename_step(&mut self, step: RenameStep) {
        if let Some(renaming) = self.book.renaming_mut() {
            renaming.step = step;
        }
    }

    fn rename_failed(
        &mut self,
        step: RenameStep,
        from: &str,
        to: &str,
        error: &ArmError,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) {
        let text = match step {
            RenameStep::Asking => {
                format!("not renamed: asking where '{from}' is failed: {error}")
            }
            RenameStep::Saving => {
                format!("not renamed: saving '{to}' failed: {error}; '{from}' is unchanged")
            }
            RenameStep::Deleting => {
                // Both names exist on the operator now: the book shows both.
                self.book.select(to);
                self.save_book(&[from, to], effects);
                format!(
                    "rename stopped: '{to}' is saved, but deleting '{from}' failed: {error}; \
                     both names exist"
                )
            }
        };
        self.error(text, now);
    }
}
