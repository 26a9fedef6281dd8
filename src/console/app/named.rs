//! Named positions in the state machine: showing, confirming, saving through forms, and
//! keeping the book in step with what the operator accepted.

use std::time::Instant;

use super::{App, Effect, Overlay, Severity, cartesian_of, polar_of};
use crate::console::form::{Confirm, FormResult};
use crate::kortex::Pose;
use crate::link::interface::{ArmCommand, PositionCoordinates};

impl App {
    pub(super) fn show_position(&mut self, name: String, effects: &mut Vec<Effect>) {
        if self.config.positions_on_operator {
            effects.push(Effect::Arm(ArmCommand::GetPosition { name: name.clone() }));
            self.overlay = Overlay::Position {
                name,
                coordinates: None,
            };
        } else {
            let coordinates = self.positions.get(&name).map(|e| PositionCoordinates {
                cartesian: e.cartesian,
                polar: e.cartesian.map(polar_of),
            });
            self.overlay = Overlay::Position { name, coordinates };
        }
    }

    pub(super) fn confirmed(&mut self, confirm: Confirm, now: Instant, effects: &mut Vec<Effect>) {
        match confirm {
            Confirm::Home => effects.push(Effect::Arm(ArmCommand::Home)),
            Confirm::GoTo(name) => {
                if self.config.positions_on_operator {
                    effects.push(Effect::Arm(ArmCommand::GoToPosition { name }));
                } else {
                    match self.stored_pose(&name) {
                        Some(pose) => effects.push(Effect::Arm(ArmCommand::MoveToPose(pose))),
                        None => self.say(
                            format!("'{name}' has no coordinates stored"),
                            Severity::Warning,
                            now,
                        ),
                    }
                }
            }
            Confirm::Delete(name) => {
                if self.config.positions_on_operator {
                    effects.push(Effect::Arm(ArmCommand::DeletePosition { name }));
                } else {
                    self.deleted(name, now, effects);
                }
            }
            Confirm::Overwrite { result, .. } => self.form_done(result, now, effects),
        }
    }

    /// A stored pose for a local (Modbus) go-to: position plus orientation (the current tool
    /// orientation when none was stored).
    pub(super) fn stored_pose(&self, name: &str) -> Option<Pose> {
        let entry = self.positions.get(name)?;
        let [x, y, z] = entry.cartesian?;
        let current = self.telemetry.as_ref().map(|t| t.tcp.pose);
        let theta = entry
            .orientation
            .or(current.map(|p| [p.theta_x, p.theta_y, p.theta_z]))?;
        Some(Pose {
            x: x as f32 / 10_000.0,
            y: y as f32 / 10_000.0,
            z: z as f32 / 10_000.0,
            theta_x: theta[0],
            theta_y: theta[1],
            theta_z: theta[2],
        })
    }

    pub(super) fn form_done(
        &mut self,
        result: FormResult,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) {
        if let FormResult::Rename { from, to } = result {
            self.rename(from, to, now, effects);
            return;
        }
        if self.config.positions_on_operator {
            let command = match result {
                FormResult::Save {
                    name,
                    anchor,
                    parent,
                } => ArmCommand::SavePosition {
                    name,
                    anchor,
                    parent,
                },
                FormResult::SetPolar {
                    name,
                    delta,
                    azimuth,
                    radius,
                } => ArmCommand::SetPolarPosition {
                    name,
                    delta,
                    azimuth,
                    radius,
                },
                FormResult::SetCartesian { name, x, y, z } => {
                    ArmCommand::SetCartesianPosition { name, x, y, z }
                }
                FormResult::Rename { .. } => return,
            };
            effects.push(Effect::Arm(command));
            return;
        }
        // Over Modbus the book is the only store.
        let pose = self.telemetry.as_ref().map(|t| t.tcp.pose);
        let (name, cartesian, orientation, anchor, parent) = match result {
            FormResult::Save {
                name,
                anchor,
                parent,
            } => {
                let Some(p) = pose else {
                    self.say(
                        "no telemetry yet: cannot save the pose",
                        Severity::Warning,
                        now,
                    );
                    return;
                };
                let c = [p.x, p.y, p.z].map(|v| (f64::from(v) * 10_000.0).round() as i32);
                (
                    name,
                    c,
                    Some([p.theta_x, p.theta_y, p.theta_z]),
                    anchor,
                    parent,
                )
            }
            FormResult::SetCartesian { name, x, y, z } => (name, [x, y, z], None, false, None),
            FormResult::Rename { .. } => return,
            FormResult::SetPolar {
                name,
                delta,
                azimuth,
                radius,
            } => (
                name,
                cartesian_of([delta, azimuth, radius]),
                None,
                false,
                None,
            ),
        };
        if anchor {
            self.say(
                "anchored positions need a Talos operator: saved without anchor",
                Severity::Warning,
                now,
            );
        }
        let entry = self.positions.get_or_insert(&name);
        entry.cartesian = Some(cartesian);
        entry.orientation = orientation.or(entry.orientation);
        entry.anchor = false;
        entry.parent = parent;
        self.select(&name);
        self.say(format!("saved '{name}'"), Severity::Info, now);
        effects.push(Effect::SavePositions(self.positions.clone()));
    }

    /// `name` is deleted: out of the book, kept for undo.
    fn deleted(&mut self, name: String, now: Instant, effects: &mut Vec<Effect>) {
        if let Some(entry) = self.positions.remove(&name) {
            self.last_deleted = Some((name.clone(), entry));
        }
        self.clamp_selection();
        self.say(
            format!("deleted '{name}' (undo restores it)"),
            Severity::Info,
            now,
        );
        effects.push(Effect::SavePositions(self.positions.clone()));
    }

    pub(super) fn select(&mut self, name: &str) {
        if let Some(i) = self.positions.index_of(name) {
            self.selected = i;
        }
    }

    pub(super) fn clamp_selection(&mut self) {
        self.selected = self.selected.min(self.positions.len().saturating_sub(1));
    }

    /// Keeps the book in step with what the operator accepted.
    pub(super) fn on_done(&mut self, command: ArmCommand, now: Instant, effects: &mut Vec<Effect>) {
        let name = match &command {
            ArmCommand::SavePosition {
                name,
                anchor,
                parent,
            } => {
                let pose = self.telemetry.as_ref().map(|t| t.tcp.pose);
                let entry = self.positions.get_or_insert(name);
                entry.anchor = *anchor;
                entry.parent = parent.clone();
                entry.unknown_to_operator = false;
                if let Some(p) = pose {
                    entry.cartesian =
                        Some([p.x, p.y, p.z].map(|v| (f64::from(v) * 10_000.0).round() as i32));
                }
                name.clone()
            }
            ArmCommand::SetCartesianPosition { name, x, y, z } => {
                let entry = self.positions.get_or_insert(name);
                entry.cartesian = Some([*x, *y, *z]);
                entry.unknown_to_operator = false;
                name.clone()
            }
            ArmCommand::SetPolarPosition {
                name,
                delta,
                azimuth,
                radius,
            } => {
                let entry = self.positions.get_or_insert(name);
                entry.cartesian = Some(cartesian_of([*delta, *azimuth, *radius]));
                entry.unknown_to_operator = false;
                name.clone()
            }
            ArmCommand::DeletePosition { name } => {
                self.deleted(name.clone(), now, effects);
                return;
            }
            _ => return,
        };
        self.select(&name);
        self.say(format!("saved '{name}'"), Severity::Info, now);
        effects.push(Effect::SavePositions(self.positions.clone()));
    }
}
