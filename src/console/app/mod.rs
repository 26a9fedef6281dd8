//! The console's state machine: an input goes in, the state changes, effects come out.
//!
//! Pure: no IO, no clock of its own (every input carries `now`). The runtime feeds it terminal
//! and arm events and carries out the effects; the panels draw from it.
//!
//! Safety rules it keeps: motion only starts from a jog key press; any other key, an overlay,
//! focus loss, a link problem, a terminal too small to show the status, a signal and quitting
//! all stop it.

mod arm_state;
mod book_load;
mod coords;
mod jog_keys;
mod motion_truth;
mod named;

pub use arm_state::{abort_reason, age_text, at_rest, fault_reason};
pub use book_load::{BookState, CHECKED_ON_CONNECT};
pub use coords::{cartesian_of, describe_motion, polar_of};
pub use jog_keys::TAP_STEP_LIMIT;
pub use motion_truth::{
    ACTION_TIMEOUT, ActionKind, MotionShown, MotionTruth, NO_TELEMETRY_ACTION_TIME, STALE_AFTER,
    STOP_GRACE, TrackedAction,
};

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use super::action::Action;
use super::form::{Confirm, Form, FormKind};
use super::jog::{JogEngine, KeyKind, MAX_ONSET, ReleaseMode};
use super::keymap::{BaseKey, KeyName, Keymap, NamedKey};
use super::positions::PositionBook;
use crate::kortex::{ReferenceFrame, Telemetry};
use crate::link::arm::{
    ArmCommand, ArmEvent, GuardStatus, LinkStatus, LogEntry, PositionCoordinates, StepMove,
    TelemetrySource,
};

/// Below this the status bar cannot be shown: motion stops and the screen says so.
pub const MIN_WIDTH: u16 = 40;
pub const MIN_HEIGHT: u16 = 10;
/// Command log lines kept.
const LOG_CAPACITY: usize = 500;
/// How long a status message stays.
const MESSAGE_TIME: Duration = Duration::from_secs(6);
/// Cartesian steps, tenths of millimetres; polar steps, degrees.
const CARTESIAN_STEPS: [i32; 6] = [1, 10, 50, 100, 500, 1000];
const POLAR_STEPS: [i32; 5] = [1, 2, 5, 10, 30];
const SPEED_STEP: u8 = 10;

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

/// One key event as the console needs it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct KeyInput {
    pub key: KeyName,
    /// The character typed, for forms.
    pub text: Option<char>,
    pub kind: KeyKind,
}

/// Everything that can happen to the console.
#[derive(Debug, Clone, PartialEq)]
pub enum Input {
    Key(KeyInput),
    FocusLost,
    FocusGained,
    Resize {
        width: u16,
        height: u16,
    },
    /// Time passed (the runtime wakes at [`App::next_deadline`]).
    Tick,
    Arm(ArmEvent),
    /// SIGINT, SIGTERM or SIGHUP.
    Signal(&'static str),
    /// The position book was read off the event loop, or could not be (the error names the file
    /// and what was wrong). See [`App::begin_loading_positions`].
    PositionsLoaded(Result<PositionBook, String>),
}

/// What the runtime must do.
#[derive(Debug, Clone, PartialEq)]
pub enum Effect {
    Arm(ArmCommand),
    /// Write the position book to its file.
    SavePositions(PositionBook),
    Quit,
}

/// How bad a status message is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Severity {
    Info,
    Warning,
    Error,
}

/// What is drawn over the panels.
#[derive(Debug, Clone, PartialEq)]
pub enum Overlay {
    None,
    Help,
    Confirm(Confirm),
    Form(Form),
    Position {
        name: String,
        coordinates: Option<PositionCoordinates>,
    },
}

/// Step mode settings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Step {
    pub enabled: bool,
    index: usize,
}

impl Step {
    /// Cartesian step in tenths of millimetres.
    pub fn cartesian(&self) -> i32 {
        CARTESIAN_STEPS[self.index.min(CARTESIAN_STEPS.len() - 1)]
    }

    /// Polar step in degrees.
    pub fn polar(&self) -> i32 {
        POLAR_STEPS[self.index.min(POLAR_STEPS.len() - 1)]
    }
}

/// Fixed facts about this console session.
#[derive(Debug, Clone)]
pub struct AppConfig {
    pub keymap: Keymap,
    pub release_mode: ReleaseMode,
    /// START re-send period while a jog key is held.
    pub refresh: Duration,
    /// Named positions live on a Talos operator (else only in the console's book, over Modbus).
    pub positions_on_operator: bool,
    /// Cartesian jog speed cap, m/s.
    pub max_jog_speed: f64,
    /// Reference frames apply (Modbus jogging).
    pub frames: bool,
}

/// The console's whole state.
#[derive(Debug, Clone)]
pub struct App {
    pub config: AppConfig,
    pub jog: JogEngine,
    pub overlay: Overlay,
    pub message: Option<(String, Severity, Instant)>,
    pub link: LinkStatus,
    pub telemetry: Option<Telemetry>,
    pub telemetry_source: TelemetrySource,
    pub latency: Option<Duration>,
    pub speed: Option<u8>,
    pub frame: ReferenceFrame,
    pub step: Step,
    pub positions: PositionBook,
    /// Whether the book is loaded, still loading, or could not be read.
    pub book_state: BookState,
    pub selected: usize,
    pub log: VecDeque<LogEntry>,
    pub hex: bool,
    pub size: (u16, u16),
    pub quitting: bool,
    /// The stop guard's state, once the driver says one is required (Modbus motion).
    pub guard: Option<GuardStatus>,
    /// Link health and motion evidence (LINK STALE, MAY BE MOVING, MOVING: HOME).
    pub truth: MotionTruth,
    /// The latest input's `now`: the panels draw ages against it.
    now: Option<Instant>,
    /// The key that closed an overlay and when it was last seen: its auto-repeat must not be
    /// taken for new presses (and start a jog) once the overlay is gone.
    swallowed: Option<(KeyName, Instant)>,
}

impl App {
    pub fn new(config: AppConfig, positions: PositionBook) -> App {
        let jog = JogEngine::new(config.release_mode, config.refresh);
        App {
            config,
            jog,
            overlay: Overlay::None,
            message: None,
            link: LinkStatus::Connecting,
            telemetry: None,
            telemetry_source: TelemetrySource::None,
            latency: None,
            speed: None,
            frame: ReferenceFrame::Base,
            step: Step {
                enabled: false,
                index: 2,
            },
            positions,
            book_state: BookState::Ready,
            selected: 0,
            log: VecDeque::new(),
            hex: false,
            size: (80, 24),
            quitting: false,
            guard: None,
            truth: MotionTruth::default(),
            now: None,
            swallowed: None,
        }
    }

    /// Whether the terminal is large enough to show the status.
    pub fn fits(&self) -> bool {
        self.size.0 >= MIN_WIDTH && self.size.1 >= MIN_HEIGHT
    }

    pub fn selected_name(&self) -> Option<&str> {
        self.positions.name_at(self.selected)
    }

    /// When the runtime must next send [`Input::Tick`].
    pub fn next_deadline(&self) -> Option<Instant> {
        let message = self.message.as_ref().map(|(_, _, at)| *at + MESSAGE_TIME);
        self.jog
            .next_deadline()
            .into_iter()
            .chain(message)
            .chain(self.truth_deadline())
            .min()
    }

    /// The state machine's one entry point.
    pub fn handle(&mut self, input: Input, now: Instant) -> Vec<Effect> {
        self.now = Some(now);
        let goto = self.goto_in_question();
        let mut effects = Vec::new();
        match input {
            Input::Key(key) => self.on_key(key, now, &mut effects),
            Input::FocusLost => self.stop_jog(now, &mut effects),
            Input::FocusGained => {}
            Input::Resize { width, height } => {
                self.size = (width, height);
                if !self.fits() {
                    self.stop_jog(now, &mut effects);
                }
            }
            Input::Tick => {
                let jog = self.jog.tick(now);
                self.apply_jog(jog, now, &mut effects);
                if self
                    .message
                    .as_ref()
                    .is_some_and(|(_, _, at)| now >= *at + MESSAGE_TIME)
                {
                    self.message = None;
                }
            }
            Input::Arm(event) => self.on_arm(event, now, &mut effects),
            Input::Signal(name) => {
                self.say(
                    format!("{name}: stopping and quitting"),
                    Severity::Warning,
                    now,
                );
                self.quit(now, &mut effects);
            }
            Input::PositionsLoaded(result) => self.on_positions_loaded(result, now, &mut effects),
        }
        self.truth_after(goto, now, &mut effects);
        self.hold_saves_until_loaded(now, &mut effects);
        effects
    }

    /// Shows a message on the bottom line (also used by the runtime, e.g. for file errors).
    pub fn say(&mut self, text: impl Into<String>, severity: Severity, now: Instant) {
        self.message = Some((text.into(), severity, now));
    }

    /// Stops a jog in progress; the jog keys still down stay latched until released.
    fn stop_jog(&mut self, now: Instant, effects: &mut Vec<Effect>) {
        let jog = self.jog.stop_all(now);
        self.apply_jog(jog, now, effects);
    }

    /// Stops everything, jog or not (space, quick paths): STOP is always sent.
    fn stop_everything(&mut self, now: Instant, effects: &mut Vec<Effect>) {
        self.jog.stop_all(now);
        effects.push(Effect::Arm(ArmCommand::Stop));
    }

    fn quit(&mut self, now: Instant, effects: &mut Vec<Effect>) {
        self.stop_everything(now, effects);
        self.quitting = true;
        effects.push(Effect::Quit);
    }

    fn on_key(&mut self, key: KeyInput, now: Instant, effects: &mut Vec<Effect>) {
        // Ctrl-C always stops and quits, whatever the keymap or overlay (raw mode turns it
        // into a key instead of SIGINT).
        if key.kind == KeyKind::Press && key.key == CTRL_C {
            self.quit(now, effects);
            return;
        }
        if key.kind == KeyKind::Release {
            self.release_jog_keys(&key, now, effects);
            return;
        }
        if !self.fits() {
            // Nothing is shown: every key only stops.
            if key.kind == KeyKind::Press {
                self.stop_jog(now, effects);
            }
            self.latch_jog_key(&key, now, effects);
            return;
        }
        if self.auto_repeat_of_overlay_key(&key, now) {
            // Keep still, but let the repeat neither answer the overlay nor start a jog.
            self.stop_jog(now, effects);
            self.latch_jog_key(&key, now, effects);
            return;
        }
        let overlay_was_open = self.overlay != Overlay::None;
        self.dispatch_key(key.clone(), now, effects);
        if key.kind == KeyKind::Press && overlay_was_open != (self.overlay != Overlay::None) {
            self.swallowed = Some((key.key, now));
        }
    }

    /// Whether `key` is the auto-repeat of the key that just opened or closed an overlay:
    /// holding `h` must not cancel the home question it opened, nor holding `w` to close the
    /// help start a jog. With reported key events a repeat says so itself.
    fn auto_repeat_of_overlay_key(&mut self, key: &KeyInput, now: Instant) -> bool {
        if key.kind == KeyKind::Repeat && self.overlay != Overlay::None {
            return true;
        }
        let Some((held, seen)) = self.swallowed else {
            return false;
        };
        let repeating = held == key.key
            && key.kind == KeyKind::Press
            && self.jog.mode() == ReleaseMode::AutoRepeat
            && now.saturating_duration_since(seen) < MAX_ONSET;
        self.swallowed = repeating.then_some((held, now));
        repeating
    }

    /// A press or repeat (releases are handled before this).
    fn dispatch_key(&mut self, key: KeyInput, now: Instant, effects: &mut Vec<Effect>) {
        if self.overlay != Overlay::None {
            self.stop_jog(now, effects);
            self.latch_jog_key(&key, now, effects);
            self.on_overlay_key(key, now, effects);
            return;
        }
        let action = self.config.keymap.action(&key.key);
        match (action, key.kind) {
            (Some(action), kind) if action.jog().is_some() => {
                if self.step.enabled {
                    // One step per press: a held key's auto-repeat steps no further.
                    let (fresh, jog) = self.jog.latch_press(action, kind, now);
                    self.apply_jog(jog, now, effects);
                    if fresh {
                        self.step_move(action, now, effects);
                    }
                } else if self.link_is_up() {
                    let jog = self.jog.key(action, kind, now);
                    self.apply_jog(jog, now, effects);
                } else {
                    self.latch_jog_key(&key, now, effects);
                    if kind == KeyKind::Press {
                        let text = match self.link_stale() {
                            Some(_) => "link stale: not moving",
                            None => "no link to the arm: not moving",
                        };
                        self.say(text, Severity::Warning, now);
                    }
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

    /// The jog actions bound to `key`, to the key without modifiers, and to the other case of
    /// a letter.
    fn release_candidates(&self, key: &KeyName) -> Vec<Action> {
        let bare = key.without_modifiers();
        let mut keys = vec![*key, bare];
        if let BaseKey::Char(c) = bare.base() {
            keys.extend(
                [single_char(c.to_lowercase()), single_char(c.to_uppercase())]
                    .into_iter()
                    .flatten()
                    .map(KeyName::char),
            );
        }
        let mut actions: Vec<Action> = keys
            .iter()
            .filter_map(|k| self.config.keymap.action(k))
            .filter(|a| a.jog().is_some())
            .collect();
        actions.sort();
        actions.dedup();
        actions
    }

    /// Up and heard from: a stale link starts no motion.
    fn link_is_up(&self) -> bool {
        matches!(self.link, LinkStatus::Up { .. }) && self.link_stale().is_none()
    }

    fn step_move(&mut self, action: Action, now: Instant, effects: &mut Vec<Effect>) {
        let Some((axis, sign)) = action.jog() else {
            return;
        };
        use super::action::JogAxis as A;
        let s = i32::from(sign.value());
        let (c, p) = (self.step.cartesian() * s, self.step.polar() * s);
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
        };
        effects.push(Effect::Arm(ArmCommand::Step(step)));
    }

    fn on_action(&mut self, action: Action, now: Instant, effects: &mut Vec<Effect>) {
        use Action as A;
        match action {
            A::Stop => {
                self.stop_everything(now, effects);
                self.say("stopped", Severity::Info, now);
            }
            A::QuickStop => {
                self.jog.stop_all(now);
                effects.push(Effect::Arm(ArmCommand::QuickStop));
                self.say(
                    "quick stop: reset the fault before moving again",
                    Severity::Warning,
                    now,
                );
            }
            A::FaultReset => effects.push(Effect::Arm(ArmCommand::FaultReset)),
            A::Home => self.overlay = Overlay::Confirm(Confirm::Home),
            A::StepMode => {
                self.step.enabled = !self.step.enabled;
                let text = if self.step.enabled {
                    "step mode: each press moves one step"
                } else {
                    "jog mode: hold a key to move"
                };
                self.say(text, Severity::Info, now);
            }
            A::StepBigger => self.step.index = (self.step.index + 1).min(CARTESIAN_STEPS.len() - 1),
            A::StepSmaller => self.step.index = self.step.index.saturating_sub(1),
            A::SpeedUp | A::SpeedDown => {
                let current = self.speed.unwrap_or(50);
                let speed = if action == A::SpeedUp {
                    current.saturating_add(SPEED_STEP).min(100)
                } else {
                    current.saturating_sub(SPEED_STEP).max(1)
                };
                effects.push(Effect::Arm(ArmCommand::SetSpeed(speed)));
            }
            A::FrameCycle => {
                if !self.config.frames {
                    self.say(
                        "the Talos link jogs in the base frame only",
                        Severity::Info,
                        now,
                    );
                    return;
                }
                self.frame = match self.frame {
                    ReferenceFrame::Base => ReferenceFrame::Tool,
                    ReferenceFrame::Tool => ReferenceFrame::Mixed,
                    ReferenceFrame::Mixed => ReferenceFrame::Base,
                };
                effects.push(Effect::Arm(ArmCommand::SetFrame(self.frame)));
            }
            A::JointNext | A::JointPrevious => {
                let j = self.jog.joint();
                let next = if action == A::JointNext {
                    j % 7 + 1
                } else {
                    (j + 5) % 7 + 1
                };
                let jog = self.jog.select_joint(next, now);
                self.apply_jog(jog, now, effects);
            }
            // Starts empty: a saved pose must not overwrite the selected one by accident.
            A::SavePosition => self.overlay = Overlay::Form(Form::new(FormKind::Save, "")),
            A::SetPolarPosition | A::SetCartesianPosition => {
                let kind = if action == A::SetPolarPosition {
                    FormKind::SetPolar
                } else {
                    FormKind::SetCartesian
                };
                let name = self.selected_name().unwrap_or("").to_string();
                self.overlay = Overlay::Form(Form::new(kind, &name));
            }
            A::GoToPosition | A::DeletePosition | A::ShowPosition => {
                let Some(name) = self.selected_name().map(str::to_string) else {
                    self.say("no position selected: save one first", Severity::Info, now);
                    return;
                };
                match action {
                    A::GoToPosition => self.overlay = Overlay::Confirm(Confirm::GoTo(name)),
                    A::DeletePosition => self.overlay = Overlay::Confirm(Confirm::Delete(name)),
                    _ => self.show_position(name, effects),
                }
            }
            A::PositionNext if !self.positions.is_empty() => {
                self.selected = (self.selected + 1) % self.positions.len();
            }
            A::PositionPrevious if !self.positions.is_empty() => {
                let n = self.positions.len();
                self.selected = (self.selected + n - 1) % n;
            }
            A::ToggleHex => self.hex = !self.hex,
            A::Help => self.overlay = Overlay::Help,
            A::Quit => self.quit(now, effects),
            // Jog actions are handled before this.
            _ => {}
        }
    }

    fn on_overlay_key(&mut self, key: KeyInput, now: Instant, effects: &mut Vec<Effect>) {
        match std::mem::replace(&mut self.overlay, Overlay::None) {
            Overlay::None => {}
            Overlay::Help | Overlay::Position { .. } => {}
            Overlay::Confirm(confirm) => {
                if matches!(key.key, YES | YES_SHIFTED | ENTER) {
                    self.confirmed(confirm, now, effects);
                } else {
                    self.say("cancelled", Severity::Info, now);
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
                            self.form_done(result, now, effects);
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
                self.overlay = Overlay::Form(form);
            }
        }
    }

    fn on_arm(&mut self, event: ArmEvent, now: Instant, effects: &mut Vec<Effect>) {
        self.truth_on_arm(&event, now);
        match event {
            ArmEvent::Status(status) => {
                if let LinkStatus::Down { reason } = &status {
                    // Stop through whatever link is left; the held keys stay latched so nothing
                    // restarts when the link comes back.
                    self.stop_jog(now, effects);
                    self.say(format!("link lost: {reason}"), Severity::Error, now);
                }
                let came_up = matches!(status, LinkStatus::Up { .. })
                    && !matches!(self.link, LinkStatus::Up { .. });
                self.link = status;
                if came_up && self.config.positions_on_operator {
                    // The ICD cannot list positions: ask about remembered names, so the panel
                    // marks the ones this operator does not know (and shows where the others
                    // are now).
                    self.check_names_on_operator(effects);
                }
            }
            ArmEvent::Telemetry(t) => self.telemetry = Some(*t),
            ArmEvent::TelemetrySource(source) => self.telemetry_source = source,
            ArmEvent::Latency(latency) => self.latency = Some(latency),
            ArmEvent::Speed(speed) => self.speed = Some(speed),
            ArmEvent::Log(entry) => {
                // Telemetry polls with the same outcome in a row share one counted line, so
                // they are logged without drowning the technician's own commands.
                if let Some(last) = self.log.back_mut()
                    && entry.poll
                    && last.poll
                    && last.name == entry.name
                    && last.outcome == entry.outcome
                {
                    let count = last.count.saturating_add(entry.count.max(1));
                    *last = LogEntry { count, ..entry };
                    return;
                }
                if self.log.len() >= LOG_CAPACITY {
                    self.log.pop_front();
                }
                self.log.push_back(LogEntry {
                    count: entry.count.max(1),
                    ..entry
                });
            }
            ArmEvent::Failed { command, reason } => {
                // A jog the arm did not take must not be left to the watchdog: stop and latch
                // the held keys, so only a new press moves again.
                if command == "jog" {
                    self.stop_jog(now, effects);
                }
                self.say(format!("{command} failed: {reason}"), Severity::Error, now);
            }
            ArmEvent::Position { name, coordinates } => {
                // A reply about a name no longer in the book (deleted meanwhile) adds nothing:
                // a new name would move the rows and the selection under the technician.
                if let Some(entry) = self.positions.get_mut(&name) {
                    entry.unknown_to_operator = false;
                    if let Some(c) = coordinates.cartesian {
                        entry.cartesian = Some(c);
                    }
                }
                if matches!(&self.overlay, Overlay::Position { name: shown, .. } if *shown == name)
                {
                    self.overlay = Overlay::Position {
                        name,
                        coordinates: Some(coordinates),
                    };
                }
            }
            ArmEvent::UnknownPosition { name } => {
                if let Some(entry) = self.positions.get_mut(&name) {
                    entry.unknown_to_operator = true;
                }
                // Said only when the technician is looking at it; otherwise the panel marks it.
                if matches!(&self.overlay, Overlay::Position { name: shown, .. } if *shown == name)
                {
                    self.overlay = Overlay::None;
                    self.say(
                        format!("the operator does not know '{name}'"),
                        Severity::Warning,
                        now,
                    );
                }
            }
            ArmEvent::Done { command } => self.on_done(command, now, effects),
            ArmEvent::Guard(status) => {
                // Without a ready guard the driver refuses Modbus motion and stops any: forget
                // the held keys so nothing restarts when the guard is back.
                if !matches!(status, GuardStatus::Ready { .. }) {
                    self.stop_jog(now, effects);
                }
                if let GuardStatus::Down { reason } = &status {
                    self.say(
                        format!("stop guard down, no motion until it is back: {reason}"),
                        Severity::Error,
                        now,
                    );
                }
                self.guard = Some(status);
            }
            // Evidence only: see `truth_on_arm`.
            ArmEvent::StopConfirmed | ArmEvent::StopUnconfirmed { .. } => {}
        }
    }
}

/// The one character of a case mapping, if it is one (not "SS" for "ß"): only that is a key.
fn single_char(mut chars: impl Iterator<Item = char>) -> Option<char> {
    let first = chars.next()?;
    chars.next().is_none().then_some(first)
}
