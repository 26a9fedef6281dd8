//! Named positions in the state machine: shown, confirmed, saved, kept in step with the operator.

use std::time::Instant;

use super::{App, Effect, Overlay, cartesian_of, polar_of};
use crate::console::form::{Confirm, FormResult, tour_list};
use crate::console::positions::{BookEntry, PoseFrame};
use crate::kortex::{Pose, Telemetry};
use crate::link::interface::{ArmCommand, PositionCoordinates};

impl App {
    pub(super) fn show_position(&mut self, name: String, effects: &mut Vec<Effect>) {
        let coordinates = if self.config.positions_on_operator {
            effects.push(Effect::Arm(ArmCommand::GetPosition { name: name.clone() }));
            None
        } else {
            self.book
                .positions()
                .get(&name)
                .map(|e| PositionCoordinates {
                    cartesian: e.cartesian,
                    polar: e.cartesian.map(polar_of),
                })
        };
        self.screen.show(Overlay::Position { name, coordinates });
    }

    pub(super) fn confirmed(&mut self, confirm: Confirm, now: Instant, effects: &mut Vec<Effect>) {
        // The arm may have faulted (or the link gone) while the question was open.
        let moves = matches!(
            confirm,
            Confirm::Home | Confirm::GoTo(_) | Confirm::Tour(_) | Confirm::Stored(_)
        );
        if moves && self.refuse_motion(now) {
            return;
        }
        match confirm {
            Confirm::Home => effects.push(Effect::Arm(ArmCommand::Home)),
            Confirm::Stored(stored) => self.run_stored(stored, now, effects),
            Confirm::Resave(name) => self.resave_confirmed(name, now, effects),
            Confirm::GoTo(name) => {
                if let Err(why) = self.go_to(name, effects) {
                    self.warn(why, now);
                }
            }
            Confirm::Tour(question) => self.tour_confirmed(question, now, effects),
            Confirm::Delete { name, .. } => {
                if self.config.positions_on_operator {
                    effects.push(Effect::Arm(ArmCommand::DeletePosition { name }));
                } else {
                    self.deleted(name, now, effects);
                }
            }
            Confirm::Overwrite { result, .. } => self.form_done(result, now, effects),
            Confirm::QuitUnsaved { .. } => self.quit(now, effects),
            Confirm::BothChanged { name, copy } => self.take_the_name(name, copy, now, effects),
        }
    }

    /// The one go-to path (a go-to, each tour leg): Go To to an operator that keeps positions, else
    /// a cartesian move to the book's pose. `Err` says why nothing was sent.
    pub(super) fn go_to(&mut self, name: String, effects: &mut Vec<Effect>) -> Result<(), String> {
        if self.config.positions_on_operator {
            self.going_to(&name);
            effects.push(Effect::Arm(ArmCommand::GoToPosition { name }));
            return Ok(());
        }
        match (self.go_to_refusal(&name), self.stored_pose(&name)) {
            (None, Some(pose)) => {
                effects.push(Effect::Arm(ArmCommand::MoveToPose(pose)));
                Ok(())
            }
            (refusal, _) => {
                Err(refusal.unwrap_or_else(|| format!("no position '{name}' is stored")))
            }
        }
    }

    /// A stored pose for a Modbus go-to (the current tool orientation when none was stored).
    pub(super) fn stored_pose(&self, name: &str) -> Option<Pose> {
        let entry = self.book.positions().get(name)?;
        let [x, y, z] = entry.cartesian?;
        let current = self.arm.telemetry().map(|t| t.tcp.pose);
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
        match result {
            FormResult::Rename { from, to } => return self.rename(from, to, now, effects),
            // Asked before it moves.
            FormResult::Stored(stored) => {
                return self.screen.show(Overlay::Confirm(Confirm::Stored(stored)));
            }
            _ => {}
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
                FormResult::Rename { .. }
                | FormResult::MakeTour { .. }
                | FormResult::PlayTour { .. }
                | FormResult::Stored(_) => return,
            };
            effects.push(Effect::Arm(command));
            return;
        }
        // Over Modbus the book is the only store.
        let (name, pose, anchor, parent) = match result {
            FormResult::Save {
                name,
                anchor,
                parent,
            } => {
                let Some(pose) = self.pose_now().filter(|p| p.cartesian.is_some()) else {
                    self.warn("no telemetry yet: cannot save the pose", now);
                    return;
                };
                (name, pose, anchor, parent)
            }
            FormResult::SetCartesian { name, x, y, z } => {
                (name, PoseNow::place([x, y, z]), false, None)
            }
            FormResult::Rename { .. }
            | FormResult::MakeTour { .. }
            | FormResult::PlayTour { .. }
            | FormResult::Stored(_) => return,
            FormResult::SetPolar {
                name,
                delta,
                azimuth,
                radius,
            } => (
                name,
                PoseNow::place(cartesian_of([delta, azimuth, radius])),
                false,
                None,
            ),
        };
        if anchor {
            let text = "anchored positions need a Talos operator: saved without anchor";
            self.warn(text, now);
        }
        let entry = self.book.positions_mut().get_or_insert(&name);
        pose.store(entry);
        entry.anchor = false;
        entry.parent = parent;
        self.book.select(&name);
        self.say_saved(&name, now);
        self.save_book(&[&name], effects);
    }

    /// The whole pose in telemetry now; non-finite is not known (and would not load back).
    fn pose_now(&self) -> Option<PoseNow> {
        let t = self.arm.telemetry()?;
        let p = t.tcp.pose;
        let orientation = [p.theta_x, p.theta_y, p.theta_z];
        let joints = t.joints.map(|j| j.position);
        Some(PoseNow {
            cartesian: tool_position(t),
            orientation: finite(&orientation).then_some(orientation),
            joints: finite(&joints).then_some(joints),
        })
    }

    /// `name` deleted, kept for undo; tours visiting it keep it, and are named.
    fn deleted(&mut self, name: String, now: Instant, effects: &mut Vec<Effect>) {
        self.book.on_delete(&name);
        let tours = self.book.positions().tours_using(&name);
        if tours.is_empty() {
            self.info(format!("deleted '{name}' (undo restores it)"), now);
        } else {
            let tours = tour_list(&tours);
            let text =
                format!("deleted '{name}': {tours} cannot be played without it (undo restores it)");
            self.warn(text, now);
        }
        self.save_book(&[&name], effects);
    }

    /// Keeps the book in step with what the operator accepted.
    pub(super) fn on_done(&mut self, command: ArmCommand, now: Instant, effects: &mut Vec<Effect>) {
        let name = match &command {
            ArmCommand::SavePosition {
                name,
                anchor,
                parent,
            } => {
                // The operator saved its current pose: telemetry's, else nothing known.
                let pose = self.pose_now().unwrap_or_default();
                let entry = self.book.positions_mut().get_or_insert(name);
                entry.anchor = *anchor;
                entry.parent = parent.clone();
                entry.unknown_to_operator = false;
                entry.cartesian = None;
                entry.orientation = None;
                entry.joints = None;
                pose.store(entry);
                name.clone()
            }
            ArmCommand::SetCartesianPosition { name, x, y, z } => {
                let entry = self.book.positions_mut().get_or_insert(name);
                entry.set_cartesian([*x, *y, *z]);
                entry.unknown_to_operator = false;
                name.clone()
            }
            ArmCommand::SetPolarPosition {
                name,
                delta,
                azimuth,
                radius,
            } => {
                let entry = self.book.positions_mut().get_or_insert(name);
                entry.set_cartesian(cartesian_of([*delta, *azimuth, *radius]));
                entry.unknown_to_operator = false;
                name.clone()
            }
            ArmCommand::DeletePosition { name } => {
                self.deleted(name.clone(), now, effects);
                return;
            }
            _ => return,
        };
        self.book.select(&name);
        self.say_saved(&name, now);
        self.save_book(&[&name], effects);
        if let ArmCommand::SetCartesianPosition { .. } = command {
            self.after_resave(&name, now, effects);
        }
    }
}

/// The tool's position, tenths of mm in the base frame as the book stores it; `None` if not finite.
pub fn tool_position(telemetry: &Telemetry) -> Option<[i32; 3]> {
    let p = telemetry.tcp.pose;
    let position = [p.x, p.y, p.z];
    finite(&position).then(|| position.map(|v| (f64::from(v) * 10_000.0).round() as i32))
}

fn finite(values: &[f32]) -> bool {
    values.iter().all(|v| v.is_finite())
}

/// A pose to remember: as much of it as is known.
#[derive(Debug, Clone, Copy, Default)]
struct PoseNow {
    /// Tenths of millimetres, base frame.
    cartesian: Option<[i32; 3]>,
    /// θx, θy, θz, degrees.
    orientation: Option<[f32; 3]>,
    /// J1-J7 as reported, degrees.
    joints: Option<[f32; 7]>,
}

impl PoseNow {
    /// A place typed in a form: no joint angles, the orientation left as it was.
    fn place(cartesian: [i32; 3]) -> PoseNow {
        PoseNow {
            cartesian: Some(cartesian),
            ..PoseNow::default()
        }
    }

    /// Writes what is known into `entry`, all of it in the base frame.
    fn store(self, entry: &mut BookEntry) {
        if let Some(c) = self.cartesian {
            entry.set_cartesian(c);
        }
        entry.orientation = self.orientation.or(entry.orientation);
        if self.joints.is_some() {
            entry.joints = self.joints;
        }
        entry.frame = PoseFrame::Base;
    }
}
