//! Keys in the state machine: ctrl+c, overlays and their auto-repeat, jog keys, actions,
//! dialogs and forms; the help's scroll keys; a question's refusal of keys too soon or too fast
//! (the guard: `question`); a paste, which is text, never keys: an open form takes it (cut to
//! the field's limit), anything else ignores it with one message, and input the reader refused
//! stops the arm (keys, a release or a STOP, may have been among what was dropped).

use std::time::Instant;

use super::message::Until;
use super::{App, Effect, KeyInput, Overlay, Pasted, Severity};
use crate::console::action::Action;
use crate::console::form::{Confirm, Form, FormKind, FormPaste};
use crate::console::jog::KeyKind;
use crate::console::keymap::{KeyName, NamedKey};
use crate::link::interface::{ArmCommand, StepMove};

/// The keys the console knows whatever the keymap: ctrl+c quits, and dialogs and forms answer
/// these.
const CTRL_C: KeyName = KeyName::char('c').with_ctrl();
const YES: KeyName = KeyName::char('y');
const YES_SHIFTED: KeyName = KeyName::char('Y');
const ENTER: KeyName = KeyName::named(NamedKey::Enter);
const ESC: KeyName = KeyName::named(NamedKey::Esc);
const TAB: KeyName = KeyName::named(NamedKey::Tab);
const BACKTAB: KeyName = KeyName::named(NamedKey::Tab).with_shift();
const UP: KeyName = KeyName::named(NamedKey::Up);
const DOWN: KeyName = KeyName::named(NamedKey::Down);
const BACKSPACE: KeyName = KeyName::named(NamedKey::Backspace);

impl App {
    pub(super) fn on_key(&mut self, key: KeyInput, now: Instant, effects: &mut Vec<Effect>) {
        // Ctrl-C always stops and quits, whatever the keymap or overlay (raw mode turns it
        // into a key instead of SIGINT).
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
                // A held non-jog key (a repeat): keep everything stopped, do not repeat the
                // action.
                self.stop_jog(now, effects);
            }
            (None, _) => {
                self.stop_jog(now, effects);
                self.say(
                    format!("'{}' is not bound: press ? for help", key.key),
                    Severity::Info,
                    now,
                );
            }
        }
    }

    fn step_move(&mut self, action: Action, now: Instant, effects: &mut Vec<Effect>) {
        let Some((axis, sign)) = action.jog() else {
            return;
        };
        use crate::console::action::JogAxis as A;
        let s = i32::from(sign.value());
        let (c, p) = (
            self.keys.step().cartesian() * s,
            self.keys.step().polar() * s,
        );
        let step = match axis {
            A::X => StepMove::Cartesian {
                dx: c,
                dy: 0,
                dz: 0,
            },
            A::Y => StepMove::Cartesian {
                dx: 0,
                dy: c,
                dz: 0,
            },
            A::Z => StepMove::Cartesian {
                dx: 0,
                dy: 0,
                dz: c,
            },
            A::Azimuth => StepMove::Polar {
                azimuth: p,
                altitude: 0,
            },
            A::Altitude => StepMove::Polar {
                azimuth: 0,
                altitude: p,
            },
            A::Joint => {
                self.say(
                    "step mode has no joint steps: hold to jog a joint",
                    Severity::Info,
                    now,
                );
                return;
            }
            A::Rx | A::Ry | A::Rz => {
                self.say(
                    "step mode has no turn steps: leave it and hold to turn the tool",
                    Severity::Info,
                    now,
                );
                return;
            }
        };
        if self.refuse_motion(now) {
            return;
        }
        effects.push(Effect::Arm(ArmCommand::Step(step)));
    }

    fn on_action(&mut self, action: Action, now: Instant, effects: &mut Vec<Effect>) {
        use Action as A;
        match action {
            A::Stop => {
                self.stop_everything(now, effects);
                self.hold_stop(now);
                self.say("stopped", Severity::Info, now);
            }
            A::QuickStop => {
                self.keys.jog_mut().stop_all(now);
                effects.push(Effect::Arm(ArmCommand::QuickStop));
                self.hold_stop(now);
                self.say_until(
                    "quick stop: reset the fault before moving again",
                    Severity::Warning,
                    Until::fault(None, false),
                    now,
                );
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
                self.say(text, Severity::Info, now);
            }
            A::StepBigger | A::StepSmaller => self.keys.on_step_size(action == A::StepBigger),
            A::SpeedUp | A::SpeedDown => {
                let current = self
                    .arm
                    .speed()
                    .unwrap_or(crate::link::speed::INITIAL_SPEED);
                let speed = super::next_speed(current, action == A::SpeedUp);
                effects.push(Effect::Arm(ArmCommand::SetSpeed(speed)));
            }
            A::FrameCycle => {
                if !self.offers().carries(A::FrameCycle) {
                    self.say(
                        "the Talos link jogs in the base frame only",
                        Severity::Info,
                        now,
                    );
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
                Some(why) => self.say(why, Severity::Warning, now),
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
                    self.say("no position selected: save one first", Severity::Info, now);
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
            A::Help => self.open_help(),
            A::Quit => self.ask_quit(now, effects),
            A::MakeTour | A::PlayTour | A::TourLeg => self.on_tour_action(action, now),
            A::StoredAction => self.open_stored_form(now),
            // Jog actions are handled before this.
            _ => {}
        }
    }

    fn on_overlay_key(&mut self, key: KeyInput, now: Instant, effects: &mut Vec<Effect>) {
        match self.screen.take_overlay() {
            Overlay::None => {}
            Overlay::Help => {
                if self.scroll_help(&key.key) {
                    self.screen.show(Overlay::Help);
                }
            }
            Overlay::Position { .. } => {}
            Overlay::Confirm(confirm) => {
                let yes = match confirm {
                    // Enter just submitted the form: only y replaces a position.
                    Confirm::Overwrite { .. }
                    | Confirm::QuitUnsaved { .. }
                    | Confirm::BothChanged { .. } => matches!(key.key, YES | YES_SHIFTED),
                    _ => matches!(key.key, YES | YES_SHIFTED | ENTER),
                };
                match confirm {
                    confirm if yes => self.confirmed(confirm, now, effects),
                    Confirm::Overwrite { result, form } => {
                        self.overwrite_declined(&result, *form, now);
                    }
                    Confirm::BothChanged { name, copy } => {
                        let text =
                            format!("both kept: theirs as '{name}', this console's as '{copy}'");
                        self.say(text, Severity::Info, now);
                    }
                    _ => self.say("cancelled", Severity::Info, now),
                }
            }
            Overlay::Form(mut form) => {
                match key.key {
                    ESC => {
                        self.say("cancelled", Severity::Info, now);
                        return;
                    }
                    ENTER => {
                        if let Some(result) = form.submit() {
                            self.form_submitted(result, form, now, effects);
                            return;
                        }
                    }
                    TAB | DOWN => form.next_field(),
                    BACKTAB | UP => form.previous_field(),
                    BACKSPACE => form.backspace(),
                    _ => {
                        if let Some(c) = key.text.filter(|c| !c.is_control()) {
                            form.type_char(c);
                        }
                    }
                }
                self.screen.show(Overlay::Form(form));
            }
        }
    }

    /// The help overlay's first shown line.
    pub fn help_scroll(&self) -> usize {
        self.screen.help_scroll()
    }

    pub(super) fn open_help(&mut self) {
        self.screen.open_help();
    }

    /// Scrolls the help for a scrolling key and says whether it was one (the help stays open).
    pub(super) fn scroll_help(&mut self, key: &KeyName) -> bool {
        self.screen.on_help_key(key, &self.config.keymap)
    }

    pub(super) fn on_paste(&mut self, pasted: Pasted, now: Instant, effects: &mut Vec<Effect>) {
        let text = match pasted {
            Pasted::Refused(why) => {
                self.stop_everything(now, effects);
                self.say(format!("{why}; stopped"), Severity::Warning, now);
                return;
            }
            Pasted::Text(text) => text,
        };
        let Some(form) = self.screen.form_mut() else {
            self.say(
                "paste ignored: pasted text is never keys",
                Severity::Info,
                now,
            );
            return;
        };
        match form.paste(&text) {
            FormPaste::Inserted => {}
            FormPaste::Cut { limit } => self.say(
                format!("pasted text cut to the field's {limit}-byte limit"),
                Severity::Warning,
                now,
            ),
            FormPaste::Toggle => self.say(
                "paste ignored: this field is a yes/no toggle",
                Severity::Info,
                now,
            ),
        }
    }

    /// Whether `key` (a press or repeat) was kept from answering the question; it stops a jog
    /// like any key in an overlay.
    pub(super) fn question_refuses(
        &mut self,
        key: &KeyInput,
        burst: bool,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) -> bool {
        let Some(why) = self.keys.question_refusal(burst, now) else {
            return false;
        };
        self.stop_jog(now, effects);
        self.latch_jog_key(key, now, effects);
        self.say(why, Severity::Warning, now);
        true
    }
}
