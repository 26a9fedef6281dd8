//! Keys in the state machine: ctrl+c, overlays (their keys: `screen`), jog keys and actions. Jog
//! engine effects become commands (a refresh held for telemetry: `other_client`), taps become
//! bounded steps, and held keys stay tracked while motion is not allowed.

use std::time::Instant;

use super::message::Until;
use super::{App, Effect, FenceScreen, KeyInput, Overlay, Severity};
use crate::console::action::Action;
use crate::console::form::{Confirm, Form, FormKind};
use crate::console::jog::{JogEffect, JogMotion, JogNotice, KeyKind, unit_motion};
use crate::console::keymap::KeyName;
use crate::link::interface::{ArmCommand, StepMove};
use crate::link::speed::INITIAL_SPEED;

/// Ctrl+c quits whatever the keymap (the keys dialogs and forms answer: `screen`).
const CTRL_C: KeyName = KeyName::char('c').with_ctrl();
/// The most a fallback tap moves, tenths of mm (5 mm): a tap may be a hold's start.
pub const TAP_STEP_LIMIT: i32 = 50;

impl App {
    pub(super) fn on_key(&mut self, key: KeyInput, now: Instant, effects: &mut Vec<Effect>) {
        // Ctrl-C always stops and quits (raw mode makes it a key, not SIGINT).
        if key.kind == KeyKind::Press && key.key == CTRL_C {
            self.quit(now, effects);
            return;
        }
        let repeating = self.keys.trace_key(&key, now);
        if key.kind == KeyKind::Release {
            self.release_jog_keys(&key, now, effects);
            return;
        }
        if self.key_stops_stored_run(&key, now, effects) {
            return;
        }
        let burst = self.keys.burst(now);
        if !self.fits() {
            // Nothing is shown: every key only stops.
            if key.kind == KeyKind::Press {
                self.stop_jog(now, effects);
            }
            self.latch_jog_key(&key, now, effects);
            return;
        }
        let form_open = self.screen.form_open();
        if self.keys.repeat_of_form_opener(&key, form_open, now)
            || self
                .keys
                .auto_repeat_of_overlay_key(&key, self.screen.overlay(), now)
        {
            // Keep still, but let the repeat neither answer the overlay nor start a jog.
            self.stop_jog(now, effects);
            self.latch_jog_key(&key, now, effects);
            return;
        }
        if self.screen.question_open() && self.question_refuses(&key, burst, now, effects) {
            return;
        }
        if self.tour_key(&key, now, effects) {
            return;
        }
        let overlay_before = std::mem::discriminant(self.screen.overlay());
        self.dispatch_key(key.clone(), now, effects);
        if key.kind == KeyKind::Press
            && overlay_before != std::mem::discriminant(self.screen.overlay())
        {
            if self.screen.form_open() {
                self.keys.form_opened_by(&key, repeating, now);
            } else {
                self.keys.swallow(&key, now);
            }
        }
    }

    /// A press or repeat (releases are handled before this).
    fn dispatch_key(&mut self, key: KeyInput, now: Instant, effects: &mut Vec<Effect>) {
        if !self.screen.overlay_is_none() {
            self.stop_jog(now, effects);
            self.latch_jog_key(&key, now, effects);
            self.on_overlay_key(key, now, effects);
            return;
        }
        let action = self.config.keymap.action(&key.key);
        match (action, key.kind) {
            (Some(action), kind) if action.jog().is_some() => {
                if self.keys.step().enabled {
                    // One step per press: a held key's auto-repeat steps no further.
                    let (fresh, jog) = self.keys.jog_mut().latch_press(action, kind, now);
                    self.apply_jog(jog, now, effects);
                    if fresh {
                        self.step_move(action, now, effects);
                    }
                } else if let Some((text, until)) = self.motion_refusal_until() {
                    self.latch_jog_key(&key, now, effects);
                    if kind == KeyKind::Press {
                        self.say_until(text, Severity::Warning, until, now);
                    }
                } else {
                    let jog = self.keys.jog_mut().key(action, kind, now);
                    self.apply_jog(jog, now, effects);
                }
            }
            (Some(action), KeyKind::Press) => {
                // Stop, quick stop and quit send their own stop.
                if !matches!(action, Action::Stop | Action::QuickStop | Action::Quit) {
                    self.stop_jog(now, effects);
                }
                self.on_action(action, now, effects);
            }
            (Some(_), _) => {
                // A held non-jog key repeating: keep everything stopped, do not repeat the action.
                self.stop_jog(now, effects);
            }
            (None, _) => {
                self.stop_jog(now, effects);
                self.info(format!("'{}' is not bound: press ? for help", key.key), now);
            }
        }
    }

    fn step_move(&mut self, action: Action, now: Instant, effects: &mut Vec<Effect>) {
        let Some((axis, sign)) = action.jog() else {
            return;
        };
        let step = self.keys.step();
        let step = match unit_motion(axis, sign.value(), 0) {
            JogMotion::Cartesian { x, y, z } => Ok(cartesian_step([x, y, z], step.cartesian())),
            JogMotion::Polar { azimuth, altitude } => Ok(StepMove::Polar {
                azimuth: i32::from(azimuth) * step.polar(),
                altitude: i32::from(altitude) * step.polar(),
            }),
            JogMotion::Joint { .. } => Err("step mode has no joint steps: hold to jog a joint"),
            JogMotion::Orientation { .. } => {
                Err("step mode has no turn steps: leave it and hold to turn the tool")
            }
        };
        match step {
            Err(why) => self.info(why, now),
            Ok(step) if !self.refuse_motion(now) => {
                effects.push(Effect::Arm(ArmCommand::Step(step)))
            }
            Ok(_) => {}
        }
    }

    fn on_action(&mut self, action: Action, now: Instant, effects: &mut Vec<Effect>) {
        use Action as A;
        match action {
            A::Stop => {
                self.stop_everything(now, effects);
                self.hold_stop(now);
                self.info("stopped", now);
            }
            A::QuickStop => {
                self.keys.jog_mut().stop_all(now);
                effects.push(Effect::Arm(ArmCommand::QuickStop));
                self.hold_stop(now);
                let text = "quick stop: reset the fault before moving again";
                self.say_until(text, Severity::Warning, Until::fault(None, false), now);
            }
            A::FaultReset => effects.push(Effect::Arm(ArmCommand::FaultReset)),
            A::Home if !self.refuse_motion(now) => {
                self.screen.show(Overlay::Confirm(Confirm::Home))
            }
            A::StepMode => {
                let text = if self.keys.on_toggle_step() {
                    "step mode: each press moves one step"
                } else {
                    "jog mode: hold a key to move"
                };
                self.info(text, now);
            }
            A::StepBigger | A::StepSmaller => self.keys.on_step_size(action == A::StepBigger),
            A::SpeedUp | A::SpeedDown => {
                let current = self.arm.speed().unwrap_or(INITIAL_SPEED);
                let speed = super::next_speed(current, action == A::SpeedUp);
                effects.push(Effect::Arm(ArmCommand::SetSpeed(speed)));
            }
            A::FrameCycle => {
                if !self.link_actions().carries(A::FrameCycle) {
                    self.info("the Talos link jogs in the base frame only", now);
                    return;
                }
                let frame = self.arm.on_frame_cycle();
                effects.push(Effect::Arm(ArmCommand::SetFrame(frame)));
            }
            A::JointNext | A::JointPrevious => {
                let j = self.keys.jog().joint();
                let next = if action == A::JointNext {
                    j % 7 + 1
                } else {
                    (j + 5) % 7 + 1
                };
                let jog = self.keys.jog_mut().select_joint(next, now);
                self.apply_jog(jog, now, effects);
            }
            // Starts empty: a saved pose must not overwrite the selected one by accident.
            A::SavePosition => match self.save_refusal() {
                Some(why) => self.warn(why, now),
                None => self.screen.show(Overlay::Form(self.save_form())),
            },
            A::SetPolarPosition | A::SetCartesianPosition => {
                let kind = if action == A::SetPolarPosition {
                    FormKind::SetPolar
                } else {
                    FormKind::SetCartesian
                };
                let name = self.selected_name().unwrap_or("").to_string();
                self.screen.show(Overlay::Form(Form::new(kind, &name)));
            }
            A::UndoDelete => self.undo_delete(now, effects),
            A::GoToPosition | A::DeletePosition | A::ShowPosition | A::RenamePosition => {
                let Some(name) = self.selected_name().map(str::to_string) else {
                    self.info("no position selected: save one first", now);
                    return;
                };
                match action {
                    A::GoToPosition => self.ask_go_to(name, now),
                    A::DeletePosition => {
                        let tours = self.book.positions().tours_using(&name);
                        self.screen
                            .show(Overlay::Confirm(Confirm::Delete { name, tours }));
                    }
                    A::RenamePosition => self.screen.show(Overlay::Form(Form::rename(&name))),
                    _ => self.show_position(name, effects),
                }
            }
            A::PositionNext | A::PositionPrevious => {
                self.book.on_select_next(action == A::PositionNext)
            }
            A::ToggleHex => self.screen.on_toggle_hex(),
            A::HistoryCycle => self.arm.on_history_cycle(),
            A::Help => self.screen.open_help(),
            A::Fence => self.screen.show(Overlay::Fence(FenceScreen::default())),
            A::Quit => self.ask_quit(now, effects),
            A::MakeTour | A::PlayTour | A::TourLeg => self.on_tour_action(action, now),
            A::StoredAction => self.open_stored_form(now),
            // Jog actions are handled before this.
            _ => {}
        }
    }

    /// A refresh made for `before`: past the grace, with telemetry, it waits for a sample.
    pub(super) fn hold_refresh(
        &mut self,
        before: Option<JogMotion>,
        jog: &mut Vec<JogEffect>,
        now: Instant,
    ) {
        if let Some(motion) = before {
            let watched = self.motion_truth.expects_telemetry();
            self.arm
                .others_mut()
                .hold_refresh(motion, watched, jog, now);
        }
    }

    /// Carries out what the jog engine asked for.
    pub(super) fn apply_jog(
        &mut self,
        jog: Vec<JogEffect>,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) {
        for effect in jog {
            match effect {
                JogEffect::Start(motion) => effects.push(Effect::Arm(ArmCommand::Jog(motion))),
                JogEffect::Stop => effects.push(Effect::Arm(ArmCommand::Stop)),
                JogEffect::Step(motion) => {
                    if let Some(step) = self.tap_step(motion) {
                        effects.push(Effect::Arm(ArmCommand::Step(step)));
                    }
                }
                JogEffect::Notice(notice) => {
                    let (text, severity) = notice_text(notice);
                    self.say(text, severity, now);
                }
            }
        }
    }

    /// A tap's step: the step mode's size, at most [`TAP_STEP_LIMIT`]. Only cartesian taps step.
    fn tap_step(&self, motion: JogMotion) -> Option<StepMove> {
        let JogMotion::Cartesian { x, y, z } = motion else {
            return None;
        };
        let size = self.keys.step().cartesian().clamp(0, TAP_STEP_LIMIT);
        Some(cartesian_step([x, y, z], size))
    }

    /// A key that may not move the arm: a jog key is latched until a new press.
    pub(super) fn latch_jog_key(
        &mut self,
        key: &KeyInput,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) {
        let Some(action) = self
            .config
            .keymap
            .action(&key.key)
            .filter(|a| a.jog().is_some())
        else {
            return;
        };
        let jog = self.keys.jog_mut().latch(action, key.kind, now);
        self.apply_jog(jog, now, effects);
    }

    /// A release ends every jog its key could mean (shift mid-hold turns "w" into "W").
    pub(super) fn release_jog_keys(
        &mut self,
        key: &KeyInput,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) {
        for action in self.config.keymap.release_candidates(&key.key) {
            let jog = self.keys.jog_mut().key(action, key.kind, now);
            self.apply_jog(jog, now, effects);
        }
    }
}

/// A cartesian step of `size` tenths of mm along each of `unit`'s directions.
fn cartesian_step([x, y, z]: [i8; 3], size: i32) -> StepMove {
    StepMove::Cartesian {
        dx: i32::from(x) * size,
        dy: i32::from(y) * size,
        dz: i32::from(z) * size,
    }
}

fn notice_text(notice: JogNotice) -> (String, Severity) {
    match notice {
        JogNotice::NoKeyEvents(silence) => (
            format!(
                "no key event for {}: stopped; does this terminal report key releases?",
                humane(silence)
            ),
            Severity::Warning,
        ),
        JogNotice::ReleasesMissing => (
            "a held key was pressed again with no release: this terminal does not report \
             releases; switched to the auto-repeat fallback (release and press again)"
                .into(),
            Severity::Warning,
        ),
        JogNotice::TapNeedsHold => (
            "arrows, joint and turn keys move only while held: a tap has no step".into(),
            Severity::Info,
        ),
    }
}

fn humane(d: std::time::Duration) -> String {
    if d.subsec_millis() == 0 {
        format!("{} s", d.as_secs())
    } else {
        format!("{} ms", d.as_millis())
    }
}
