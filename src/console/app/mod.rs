//! The console's state machine: an input (carrying `now`) goes in, the state changes, effects come
//! out. Pure: the runtime feeds it and carries out the effects; the panels draw from it. Motion
//! only starts from a jog key press; anything else stops it.

mod age;
mod arm;
mod book;
mod book_load;
mod cap_watch;
mod edits;
mod fence_teach;
mod fence_watch;
mod history;
mod jog_evidence;
mod keys;
mod limits;
mod link_actions;
mod message;
mod motion_truth;
mod other_client;
mod parts;
mod question;
mod resave;
mod saved_positions;
mod saving;
mod screen;
mod singularity;
mod speed_steps;
mod stop_hold;
mod tour;
mod trail;

pub use age::age_text;
pub use book_load::{BookState, CHECKED_ON_CONNECT};
pub use cap_watch::{CAP_TOLERANCE, CapWatch, OVER_CAP_SAMPLES};
// Re-exported for the console's tests and panels; their homes are below the app.
pub use crate::console::coords::{cartesian_of, describe_motion, polar_of};
pub use crate::kortex::arm_state::{abort_reason, at_rest, fault_reason};
pub use arm::STORED_REFUSAL;
pub use fence_teach::{FenceRow, FenceScreen, Naming};
pub use history::{BUCKET, BUCKETS, History, HistorySeries, JointQuantity};
pub use jog_evidence::{
    ALONG_FRACTION, Contradiction, OTHER_MOTION_JOINT_DEG_S, OTHER_MOTION_M_S, SLOW_FRACTION,
};
pub use keys::TAP_STEP_LIMIT;
pub use limits::{LIMIT_WARNING_DEG, NearLimit, near_limits};
pub use link_actions::{LinkActions, SessionView};
pub use motion_truth::{
    ACTION_TIMEOUT, ARRIVED_DEG, ARRIVED_MM, ActionKind, GoToTarget, MotionShown, MotionStatusView,
    MotionTruth, NO_TELEMETRY_ACTION_TIME, STALE_AFTER, STOP_GRACE, StoredAction, TrackedAction,
};
pub use other_client::{
    CONTRADICTED_FOR, OTHER_CLIENT_GRACE, OTHER_CLIENT_SAMPLES, OtherClients, REFRESH_SAMPLES,
    REFRESH_WAIT,
};
pub use parts::arm_refusal;
pub use parts::{ArmView, BookView, FenceScreenView, KeysView, ScreenView, TourView};
pub use question::{BURST_KEY_GAP, QUESTION_QUIET};
pub use resave::RESAVE_GO_WITHIN;
pub use saved_positions::tool_position;
pub use singularity::{AT_SINGULARITY, SINGULARITY_WARNING, near_singularity, singularity_text};
pub use speed_steps::{SPEED_STEPS, next_speed};
pub use stop_hold::{RESEND_EVERY, SLOWING_DOWN, STOP_HOLD, StopHold};
pub use trail::{TRAIL_CAPACITY, TRAIL_SPACING, TRAIL_SPAN, ToolTrail, TrailPoint, TrailShade};

use std::sync::Arc;
use std::time::{Duration, Instant};

use super::book_io::{BookSave, Loaded, SaveOutcome};
use super::form::{Confirm, Form};
use super::jog::{KeyKind, ReleaseMode};
use super::keymap::{KeyName, Keymap};
use super::positions::PositionBook;

use crate::kortex::Stored;
use crate::link::fence::Fence;
use crate::link::interface::{ArmCommand, ArmEvent, PositionCoordinates};
use crate::link::speed::SpeedCap;

/// Below this the status bar cannot be shown: motion stops and the screen says so.
pub const MIN_WIDTH: u16 = 40;
pub const MIN_HEIGHT: u16 = 10;
/// Cartesian steps, tenths of millimetres; polar steps, degrees.
const CARTESIAN_STEPS: [i32; 6] = [1, 10, 50, 100, 500, 1000];
const POLAR_STEPS: [i32; 5] = [1, 2, 5, 10, 30];

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct KeyInput {
    pub key: KeyName,
    /// The character typed, for forms.
    pub text: Option<char>,
    pub kind: KeyKind,
}

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
    /// A bracketed paste, or input the reader dropped.
    Paste(Pasted),
    /// The book read off the event loop, or why not. See [`App::begin_loading_positions`].
    PositionsLoaded(Loaded),
    /// The writer's outcome for the saves asked for so far (see `saving`).
    PositionsSaved(SaveOutcome),
    /// The fence written into the profile, or why not (see `fence_teach`).
    FenceSaved(Result<(), String>),
}

/// A bracketed paste, or input dropped unread: text, never keys (see `keys`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Pasted {
    Text(String),
    /// Why it was dropped, in words (`paste ignored: …`).
    Refused(String),
}

/// What the runtime must do.
#[derive(Debug, Clone, PartialEq)]
pub enum Effect {
    Arm(ArmCommand),
    /// Write the book, merged with what another writer put in the file since.
    SavePositions(BookSave),
    /// Write the taught fence into the profile (see `fence_teach`).
    SaveFence(Box<FenceChange>),
    Quit,
}

/// A taught fence to write: `arm`'s fence in `file`, and the change in words (for the audit).
#[derive(Debug, Clone, PartialEq)]
pub struct FenceChange {
    pub file: std::path::PathBuf,
    pub arm: String,
    pub fence: Fence,
    pub change: String,
    /// A new profile's settings (`AppConfig::new_profile`).
    pub new_profile: Vec<(String, String)>,
}

impl Effect {
    /// Whether this is a command that stops the arm ([`ArmCommand::class`]).
    pub fn is_stop(&self) -> bool {
        matches!(self, Effect::Arm(command) if command.is_stop())
    }
}

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
    /// The fence screen: its faces and zones, taught here.
    Fence(FenceScreen),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Step {
    pub enabled: bool,
    index: usize,
}

impl Default for Step {
    /// Off, at the middle step.
    fn default() -> Step {
        Step {
            enabled: false,
            index: 2,
        }
    }
}

impl Step {
    fn resize(&mut self, bigger: bool) {
        self.index = if bigger {
            (self.index + 1).min(CARTESIAN_STEPS.len() - 1)
        } else {
            self.index.saturating_sub(1)
        };
    }

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
    /// Shared with each frame's view: it never changes during a session.
    pub keymap: Arc<Keymap>,
    pub release_mode: ReleaseMode,
    /// START re-send period while a jog key is held.
    pub refresh: Duration,
    /// Named positions live on a Talos operator (else only in the console's book, over Modbus).
    pub positions_on_operator: bool,
    /// The tool speed cap at 100 %, m/s: the app's [`SpeedCap`] is made of it.
    pub max_jog_speed: f64,
    /// Single-joint jog speed at 100 %, deg/s: a joint jog's rate is watched against it.
    pub joint_jog_speed: f32,
    /// Reference frames apply (Modbus jogging).
    pub frames: bool,
    /// The arm is the console's built-in simulator, not hardware: the status bar says so.
    pub simulated: bool,
    /// The arm profile (`--arm NAME`) the console was opened with, for the status bar.
    pub arm_name: Option<String>,
    /// Home's Modbus stored action (`DriverConfig::modbus_home`), followed by id; `None` on Talos.
    pub home_action: Option<Stored>,
    /// The arm profile's fence, kept on every motion; `None`: no fence (until one is taught).
    pub fence: Option<Arc<Fence>>,
    /// The file profiles are read from (`--config`, `ARMJOG_CONFIG` or the default): a taught
    /// fence is written there. `None`: kept for the session only.
    pub config_file: Option<std::path::PathBuf>,
    /// The settings a profile made by teaching a fence gets: the link options this console was
    /// started with (`talos`, `modbus`, the cap...), none on the built-in simulator.
    pub new_profile: Vec<(String, String)>,
    /// The session is not recorded (`--no-record`, or the recording could not start).
    pub recording_off: bool,
}

#[cfg(test)]
impl AppConfig {
    /// The built-in keymap, key releases reported, a Talos operator keeping the positions, the
    /// default cap: what the crate's unit tests start from.
    pub(crate) fn for_tests() -> AppConfig {
        AppConfig {
            keymap: crate::console::keymap::Keymap::builtin("default")
                .expect("keymap")
                .into(),
            release_mode: crate::console::jog::ReleaseMode::Reported,
            refresh: Duration::from_millis(100),
            positions_on_operator: true,
            max_jog_speed: 0.25,
            joint_jog_speed: crate::link::speed::JOINT_JOG_SPEED,
            frames: false,
            simulated: false,
            arm_name: None,
            home_action: None,
            fence: None,

            config_file: None,

            new_profile: Vec::new(),

            recording_off: false,
        }
    }
}

/// The console's whole state. Private: only inputs change it; [`App`]'s accessors read it.
/// It routes each input to its parts (see `parts`).
#[derive(Debug, Clone)]
pub struct App {
    config: AppConfig,
    /// The speed cap, made once from `config.max_jog_speed`: what every speed here is of.
    cap: SpeedCap,
    keys: parts::Keys,
    book: parts::Book,
    arm: parts::Arm,
    /// Link health and motion evidence (LINK STALE, MAY BE MOVING, MOVING: HOME).
    motion_truth: MotionTruth,
    /// What is drawn over the panels and on the bottom line, and the terminal's size.
    screen: parts::Screen,
    tours: parts::Tours,
    quitting: bool,
    /// The latest input's `now`: the panels draw ages against it.
    now: Option<Instant>,
    /// What ran when the console was last seen frozen, and when it came back (see
    /// `note_freeze`).
    frozen_with: Option<(String, Instant)>,
    /// The fence kept (from `config.fence`, then as taught), what the app last put on the wire
    /// for it, its last verdict and the teaching in progress.
    fence: fence_watch::FenceWatch,
}

/// What [`App::handle`] takes from the state before an input changes it, for the follow-ups.
struct BeforeInput {
    /// The position a go-to question asked about.
    goto: Option<String>,
    /// What in the input ends a tour, in words.
    interrupted: Option<String>,
}

impl App {
    /// # Panics
    /// On a `max_jog_speed` [`SpeedCap::new`] refuses (the front ends refuse it first).
    pub fn new(config: AppConfig, positions: PositionBook) -> App {
        let keys = parts::Keys::new(config.release_mode, config.refresh);
        let config_fence = config.fence.clone();
        App {
            cap: SpeedCap::configured(config.max_jog_speed),
            config,
            keys,
            book: parts::Book::new(positions),
            arm: parts::Arm::default(),
            motion_truth: MotionTruth::default(),
            screen: parts::Screen::default(),
            tours: parts::Tours::default(),
            quitting: false,
            now: None,
            frozen_with: None,
            fence: fence_watch::FenceWatch::new(config_fence),
        }
    }

    pub fn fits(&self) -> bool {
        self.screen.fits()
    }

    pub fn selected_name(&self) -> Option<&str> {
        self.book.selected_name()
    }

    /// When the runtime must next send [`Input::Tick`].
    pub fn next_deadline(&self) -> Option<Instant> {
        let message = self.screen.message_deadline();
        self.keys
            .jog()
            .next_deadline()
            .into_iter()
            .chain(message)
            .chain(self.motion_truth_deadline())
            .chain(self.other_clients_deadline())
            .min()
    }

    /// The state machine's one entry point.
    pub fn handle(&mut self, input: Input, now: Instant) -> Vec<Effect> {
        self.note_freeze(now);
        self.now = Some(now);
        let before = self.before_input(&input);
        let mut effects = Vec::new();
        match input {
            Input::Key(key) => self.on_key(key, now, &mut effects),
            Input::FocusLost => self.stop_jog(now, &mut effects),
            Input::FocusGained => {}
            Input::Resize { width, height } => {
                self.screen.on_resize(width, height);
                if !self.fits() {
                    self.stop_jog(now, &mut effects);
                }
            }
            Input::Tick => {
                let before = self.keys.jog().active();
                let mut jog = self.keys.jog_mut().tick(now);
                self.hold_refresh(before, &mut jog, now);
                self.apply_jog(jog, now, &mut effects);
                self.other_clients_on_tick(now, &mut effects);
            }
            Input::Arm(event) => self.on_arm(event, now, &mut effects),
            Input::Signal(name) => {
                self.warn(format!("{name}: stopping and quitting"), now);
                self.quit(now, &mut effects);
            }
            Input::PositionsLoaded(result) => self.on_positions_loaded(result, now, &mut effects),
            Input::PositionsSaved(outcome) => self.on_positions_saved(outcome, now),
            Input::FenceSaved(result) => self.on_fence_saved(result, now),
            Input::Paste(pasted) => self.on_paste(pasted, now, &mut effects),
        }
        self.follow_ups(before, now, &mut effects);
        effects
    }

    /// What must be done or read before the input is handled, in this order.
    fn before_input(&mut self, input: &Input) -> BeforeInput {
        // Before: a key, focus lost, a signal or a link down drops a re-save's pending go-to;
        // the key that answers the re-save question sets it afresh as it is handled.
        self.resave_watch(input);
        BeforeInput {
            // Before: the answer closes the question, and the move it sends is tracked under
            // the position's name.
            goto: self.screen.goto_in_question(),
            // Before: handling takes the input. Order with the two above not known to matter.
            interrupted: tour::interruption(input),
        }
    }

    /// The follow-ups after every input, in this order; each reads what the ones above left.
    /// A new follow-up goes here, with its reason.
    fn follow_ups(&mut self, before: BeforeInput, now: Instant, effects: &mut Vec<Effect>) {
        // 1. Before the motion truth notes what goes out: the tour ends on an interruption or a
        //    refusing gate (its STOP then goes out and is noted), or starts its next leg (a
        //    go-to the gate and the motion truth must see; `tests/console/app/tours.rs` fails if not).
        self.tour_before_motion_truth(before.interrupted, now, effects);
        // 2. After 1: a go-to the tour just emitted is tracked under its leg's name.
        let goto = before.goto.or_else(|| self.tours.starting_leg());
        // 3. After every emitter (the input, the tour): the gate drops motion it refuses, a
        //    stale link stops the jog, and each command going out is noted as evidence awaited.
        self.motion_truth_after(goto, now, effects);
        // 4. After 3: a leg the motion truth now tracks is moving; one the gate dropped ends the tour.
        self.tour_after_motion_truth(now);
        // 5. Saves asked while the book loads or could not be read are held back (and said).
        //    Before 6; with the steps above, order not known to matter (they emit no saves).
        self.hold_saves_until_loaded(now, effects);
        // 6. After 5: only saves that go out are awaited; a held one on an unreadable book is
        //    marked not saved at once (`tests/console/app/book_load.rs`).
        self.count_saves(effects);
        // 7. Messages whose state has ended go. After the steps above so that it reads the state
        //    they leave (a jog stopped on a stale link, not-saved marks); no test shows the order
        //    to matter.
        self.settle_messages(now);
        // 8. The question guard notes the overlay as the input left it; no step above opens or
        //    closes one, so its order with them is not known to matter.
        self.keys.note_overlay(self.screen.overlay(), now);
    }

    /// Shows a notice on the bottom line for a while (also used by the runtime, e.g. for file
    /// errors). A message about a state uses `say_until` instead.
    pub fn say(&mut self, text: impl Into<String>, severity: Severity, now: Instant) {
        let until = message::Until::TimeOut { done: None };
        self.say_until(text, severity, until, now);
    }

    fn info(&mut self, text: impl Into<String>, now: Instant) {
        self.say(text, Severity::Info, now);
    }

    fn warn(&mut self, text: impl Into<String>, now: Instant) {
        self.say(text, Severity::Warning, now);
    }

    fn error(&mut self, text: impl Into<String>, now: Instant) {
        self.say(text, Severity::Error, now);
    }

    /// Stops a jog in progress; the jog keys still down stay latched until released.
    fn stop_jog(&mut self, now: Instant, effects: &mut Vec<Effect>) {
        let jog = self.keys.jog_mut().stop_all(now);
        self.apply_jog(jog, now, effects);
    }

    /// Stops everything, jog or not (space, quick paths): STOP is always sent.
    fn stop_everything(&mut self, now: Instant, effects: &mut Vec<Effect>) {
        self.keys.jog_mut().stop_all(now);
        effects.push(Effect::Arm(ArmCommand::Stop));
    }

    fn quit(&mut self, now: Instant, effects: &mut Vec<Effect>) {
        self.stop_everything(now, effects);
        self.retry_save_at_quit(effects);
        self.quitting = true;
        effects.push(Effect::Quit);
    }

    /// Up and heard from: a stale link starts no motion.
    fn link_is_up(&self) -> bool {
        self.arm.link_up() && self.link_stale().is_none()
    }
}
