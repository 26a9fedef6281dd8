//! The screen in the state machine: the view of one frame, the session's offers, the message line
//! (`message`), the overlays and their keys (a question's guard: `question`), pastes (text, never
//! keys: a form takes them, and refused input stops the arm), and read access for the runtime and
//! tests (fields stay private, so only inputs change them).

use std::collections::VecDeque;
use std::time::Instant;

use super::fence_teach::{self, FenceScreen, Taught};
use super::link_actions::{LinkActions, SessionView};
use super::message::{MESSAGE_TIME, Message, Until};
use super::parts::{ArmView, FenceScreenView};
use super::{
    App, AppConfig, BookState, Effect, FenceChange, KeyInput, MotionTruth, Overlay, Pasted,
    Severity, Step,
};
use crate::console::form::{Confirm, Form, FormKind, FormPaste};
use crate::console::jog::JogEngine;
use crate::console::keymap::{KeyName, NamedKey};
use crate::console::positions::PositionBook;
use crate::console::view::View;
use crate::kortex::{ReferenceFrame, Telemetry};
use crate::link::interface::{LinkStatus, LogEntry, TelemetrySource};

/// The keys dialogs and forms answer whatever the keymap.
const YES: KeyName = KeyName::char('y');
const YES_SHIFTED: KeyName = KeyName::char('Y');
const ENTER: KeyName = KeyName::named(NamedKey::Enter);
const ESC: KeyName = KeyName::named(NamedKey::Esc);
const TAB: KeyName = KeyName::named(NamedKey::Tab);
const BACKTAB: KeyName = KeyName::named(NamedKey::Tab).with_shift();
const UP: KeyName = KeyName::named(NamedKey::Up);
const DOWN: KeyName = KeyName::named(NamedKey::Down);
const BACKSPACE: KeyName = KeyName::named(NamedKey::Backspace);

/// A joint faster than this (deg/s) counts as moving; below, noise or idle-rate motion.
pub const MOVING_JOINT_DEG_S: f32 = 0.5;

impl App {
    /// What one frame shows, assembled from the parts' own views.
    pub fn view(&self) -> View {
        // No panel is taller than the terminal: the book's and the log's views are cut to it.
        let rows = usize::from(self.screen.size().1);
        View {
            session: self.session_view(),
            keys: self.keys.view(),
            arm: ArmView {
                fence: self.fence.text(),
                fence_nearest: self.fence_nearest(),
                fence_screen: self.fence_screen_view(),
                ..self.arm.view(self.now)
            },
            motion_status: self.motion_status_view(),
            book: self.book.view(rows),
            screen: self.screen.view(rows),
            tour: self.tours.view(),
        }
    }

    /// The fence's barrier nearest the tool sphere and its clearance, mm.
    fn fence_nearest(&self) -> Option<(String, f64)> {
        let fence = self.fence.kept.as_ref()?;
        let pose = self.arm.telemetry()?.tcp.pose;
        let tool = [pose.x, pose.y, pose.z].map(|m| f64::from(m) * 1000.0);
        if !tool.iter().all(|v| v.is_finite()) {
            return None;
        }
        let (name, clearance) = fence.nearest(tool)?;
        Some((name.to_string(), clearance))
    }

    /// The arm moves, or may: draw at the full rate.
    pub fn arm_in_motion(&self) -> bool {
        !matches!(self.motion_shown(), super::MotionShown::Idle)
            || self.telemetry().is_some_and(|t| {
                t.joints
                    .iter()
                    .any(|j| j.velocity.abs() > MOVING_JOINT_DEG_S)
            })
    }

    pub fn config(&self) -> &AppConfig {
        &self.config
    }

    pub fn jog(&self) -> &JogEngine {
        self.keys.jog()
    }

    pub fn overlay(&self) -> &Overlay {
        self.screen.overlay()
    }

    /// What the fence says of the tool (`SLOWED: table 34 mm`), if anything.
    pub fn fence_text(&self) -> Option<String> {
        self.fence.text()
    }

    pub fn message(&self) -> Option<(&str, Severity)> {
        self.screen.message()
    }

    pub fn link(&self) -> &LinkStatus {
        self.arm.link()
    }

    pub fn telemetry(&self) -> Option<&Telemetry> {
        self.arm.telemetry()
    }

    /// The reference frame the console selected (the audit names it on each jog).
    pub fn frame(&self) -> ReferenceFrame {
        self.arm.frame()
    }

    pub fn telemetry_source(&self) -> TelemetrySource {
        self.motion_truth
            .expected_telemetry()
            .unwrap_or(TelemetrySource::None)
    }

    pub fn speed(&self) -> Option<u8> {
        self.arm.speed()
    }

    pub fn step(&self) -> Step {
        self.keys.step()
    }

    pub fn positions(&self) -> &PositionBook {
        self.book.positions()
    }

    pub fn book_state(&self) -> &BookState {
        self.book.state()
    }

    pub fn selected(&self) -> usize {
        self.book.selected()
    }

    pub fn log(&self) -> &VecDeque<std::sync::Arc<LogEntry>> {
        self.screen.log()
    }

    pub fn history(&self) -> &super::History {
        self.arm.history()
    }

    pub fn hex(&self) -> bool {
        self.screen.hex()
    }

    pub fn size(&self) -> (u16, u16) {
        self.screen.size()
    }

    pub fn quitting(&self) -> bool {
        self.quitting
    }

    pub fn motion_truth(&self) -> &MotionTruth {
        &self.motion_truth
    }

    /// Shows a message that lasts while `until`'s state holds.
    pub(super) fn say_until(
        &mut self,
        text: impl Into<String>,
        severity: Severity,
        until: Until,
        now: Instant,
    ) {
        self.screen.say_until(text.into(), severity, until, now);
    }

    /// After every input: ended state messages and expired notices go.
    pub(super) fn settle_messages(&mut self, now: Instant) {
        let link_up = self.arm.link_up();
        let stale = self.link_stale().is_some();
        let guard_ready = self.arm.guard_ready();
        let stop_unconfirmed = self.motion_truth.stop_unconfirmed();
        let unsaved = self.unsaved_positions() > 0;
        let writing = self.book.writing();
        let arm_refuses = self.arm.refusal().is_some();
        self.screen.settle_messages(|m: &Message| match m.until {
            Until::TimeOut { .. } => now < m.at + MESSAGE_TIME,
            Until::LinkUp => !link_up,
            Until::LinkFresh => stale,
            Until::FaultCleared { .. } => true,
            Until::GuardReady => !guard_ready,
            Until::StopConfirmed => stop_unconfirmed,
            Until::BookSaved => unsaved,
            Until::BookWritten => writing,
            Until::ArmReady => arm_refuses,
        });
    }

    pub(super) fn session_view(&self) -> SessionView {
        let config = &self.config;
        SessionView {
            keymap: config.keymap.clone(),
            cap: self.cap,
            frames: config.frames,
            simulated: config.simulated,
            positions_on_operator: config.positions_on_operator,
            link_actions: self.link_actions(),
            arm_name: config.arm_name.clone(),
            fence: self.fence.kept.clone(),
            recording_off: config.recording_off,
            replay: None,
        }
    }

    /// Which of the actions that only some links carry this session's links carry.
    pub fn link_actions(&self) -> LinkActions {
        LinkActions {
            save: self.can_save_position(),
            turn: self.can_turn(),
            joint: self.can_jog_joints(),
            go_to: self.can_go_to(),
            stored: self.can_run_stored(),
            frames: self.config.frames,
        }
    }

    /// Whether a link carries a single-joint jog: only a Talos operator in the ICD dialect (Modbus
    /// and the ack dialect cannot). That is exactly when the positions live on the operator
    /// (`DriverConfig::positions_on_operator`).
    pub fn can_jog_joints(&self) -> bool {
        self.config.positions_on_operator
    }

    /// Why saving the current pose cannot work on this link, or `None`. An ICD operator saves it
    /// itself; otherwise the console needs telemetry's pose. Offered until the driver has said
    /// which telemetry to expect.
    pub fn save_refusal(&self) -> Option<&'static str> {
        let no_telemetry = self.motion_truth.expected_telemetry() == Some(TelemetrySource::None);
        (!self.config.positions_on_operator && no_telemetry).then_some(
            "cannot save here: this operator (ack dialect) keeps no positions and sends no \
             telemetry to read the pose from; add --modbus for telemetry",
        )
    }

    /// Whether saving the current pose can work on this link (see [`App::save_refusal`]).
    pub fn can_save_position(&self) -> bool {
        self.save_refusal().is_none()
    }

    /// Only Modbus turns the tool; offered until the driver has said which link it has.
    pub fn can_turn(&self) -> bool {
        !self.without_modbus()
    }

    /// Why going to `name` cannot work here: without an ICD operator it needs Modbus.
    pub fn go_to_refusal(&self, name: &str) -> Option<String> {
        if self.config.positions_on_operator {
            return None;
        }
        if self.without_modbus() {
            return Some(format!(
                "cannot go to '{name}': the console keeps this position, and only a Modbus link \
                 moves the arm to its coordinates (this operator, ack dialect, keeps no \
                 positions); add --modbus"
            ));
        }
        let entry = self.book.positions().get(name)?;
        if entry.cartesian.is_none() {
            return Some(format!("'{name}' has no coordinates stored"));
        }
        (entry.orientation.is_none() && self.arm.telemetry().is_none()).then(|| {
            format!(
                "cannot go to '{name}' yet: it has no orientation stored, and no telemetry \
                 has given the tool's"
            )
        })
    }

    /// Whether any go-to can work on this link (see [`App::go_to_refusal`]).
    pub fn can_go_to(&self) -> bool {
        self.config.positions_on_operator || !self.without_modbus()
    }

    /// No Modbus link: Modbus telemetry is expected exactly when there is one.
    pub(super) fn without_modbus(&self) -> bool {
        matches!(
            self.motion_truth.expected_telemetry(),
            Some(TelemetrySource::TalosHardware | TelemetrySource::None)
        )
    }

    /// The save form on this link: no anchor toggle over the console's own book.
    pub(super) fn save_form(&self) -> Form {
        if self.config.positions_on_operator {
            Form::new(FormKind::Save, "")
        } else {
            Form::save_to_own_book()
        }
    }

    /// A key with an overlay open: the overlay takes it.
    pub(super) fn on_overlay_key(
        &mut self,
        key: KeyInput,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) {
        match self.screen.take_overlay() {
            // A scrolling key scrolls the help and leaves it open.
            Overlay::Help if self.screen.on_help_key(&key.key, &self.config.keymap) => {
                self.screen.show(Overlay::Help)
            }
            Overlay::None | Overlay::Help | Overlay::Position { .. } => {}
            Overlay::Fence(fence_screen) => self.on_fence_key(fence_screen, &key, now, effects),
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
                        self.info(text, now);
                    }
                    _ => self.info("cancelled", now),
                }
            }
            Overlay::Form(mut form) => {
                match key.key {
                    ESC => {
                        self.info("cancelled", now);
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

    pub fn help_scroll(&self) -> usize {
        self.screen.help_scroll()
    }

    pub(super) fn on_paste(&mut self, pasted: Pasted, now: Instant, effects: &mut Vec<Effect>) {
        let text = match pasted {
            Pasted::Refused(why) => {
                self.stop_everything(now, effects);
                self.warn(format!("{why}; stopped"), now);
                return;
            }
            Pasted::Text(text) => text,
        };
        let Some(form) = self.screen.form_mut() else {
            self.info("paste ignored: pasted text is never keys", now);
            return;
        };
        match form.paste(&text) {
            FormPaste::Inserted => {}
            FormPaste::Cut { limit } => self.warn(
                format!("pasted text cut to the field's {limit}-byte limit"),
                now,
            ),
            FormPaste::Toggle => self.info("paste ignored: this field is a yes/no toggle", now),
        }
    }

    /// Whether `key` was kept from answering; it stops a jog like any key in an overlay.
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
        self.warn(why, now);
        true
    }

    /// The fence screen's rows and state, while it is open.
    fn fence_screen_view(&self) -> Option<FenceScreenView> {
        let Overlay::Fence(_) = self.screen.overlay() else {
            return None;
        };
        let fence = self.fence.kept.as_deref().cloned().unwrap_or_default();
        Some(FenceScreenView {
            rows: fence_teach::rows(&fence, self.tool_mm()),
            corner: self.fence.corner,
            unwritten: self.fence.unwritten.clone(),
        })
    }

    /// The tool point the telemetry reports, mm; `None` without fresh telemetry or a number.
    fn tool_mm(&self) -> Option<[f64; 3]> {
        if self.telemetry_stale().is_some() {
            return None;
        }
        let pose = self.arm.telemetry()?.tcp.pose;
        let tool = [pose.x, pose.y, pose.z].map(|m| f64::from(m) * 1000.0);
        tool.iter().all(|v| v.is_finite()).then_some(tool)
    }

    /// A key on the fence screen (`fence_teach`): what it changed is kept at once and written.
    fn on_fence_key(
        &mut self,
        open: FenceScreen,
        key: &KeyInput,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) {
        let tool = self.tool_mm();
        let named = self.config.arm_name.is_some();
        let (open, taught) = self.fence.on_key(open, key, tool, named);
        for taught in taught {
            match taught {
                Taught::Say(text, severity) => self.say(text, severity, now),
                Taught::Write(change) => self.write_fence(change, now, effects),
            }
        }
        if let Some(open) = open {
            self.screen.show(Overlay::Fence(open));
        }
    }

    /// The fence kept, written into its profile off the event loop (`Input::FenceSaved`).
    fn write_fence(&mut self, change: String, now: Instant, effects: &mut Vec<Effect>) {
        let Some(fence) = self.fence.kept.as_deref().cloned() else {
            return;
        };
        let arm = self.config.arm_name.clone().or(self.fence.profile.clone());
        let (Some(file), Some(arm)) = (self.config.config_file.clone(), arm) else {
            let why = "no config file to write it to: kept for this session only";
            self.fence.unwritten = Some(why.to_string());
            self.warn(format!("{change}; {why}"), now);
            return;
        };
        self.info(format!("{change}: writing {}", file.display()), now);
        effects.push(Effect::SaveFence(Box::new(FenceChange {
            file,
            arm,
            fence,
            change,
            new_profile: self.config.new_profile.clone(),
        })));
    }

    /// The writer's word on the last fence written.
    pub(super) fn on_fence_saved(&mut self, result: Result<(), String>, now: Instant) {
        match result {
            Ok(()) => {
                self.fence.unwritten = None;
                self.info("fence written to the profile", now);
            }
            Err(why) => {
                let text = format!("fence NOT written: {why}; kept for this session");
                self.fence.unwritten = Some(why);
                self.error(text, now);
            }
        }
    }
}
