//! What the screen may say about the link and the arm's motion (`LINK STALE`, `STOPPING`, `MAY BE
//! MOVING`, `MOVING: HOME`/`GOTO`, telemetry age). Never stopped when it may not be: commanded
//! motion is unsettled until a confirmed STOP (with telemetry at rest after it, where there is
//! telemetry) or a tracked action seen to end at rest. Staleness: telemetry every 500 ms (or three
//! of the link's shortest recent intervals), answers within 500 ms; an idle ack link is never
//! stale. Without telemetry an action shows `MAY BE MOVING` until a STOP is confirmed or
//! [`NO_TELEMETRY_ACTION_TIME`] passes.
//!
//! This file holds the evidence; `evidence` keeps it up, by the rules of `actions` (what ends an
//! action), `target` (whether a go-to's end is ours) and `staleness`.

mod actions;
mod evidence;
mod staleness;
mod target;

pub use target::{ARRIVED_DEG, ARRIVED_MM, GoToTarget};

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use crate::console::jog::JogMotion;
use crate::kortex::{ActionState, OurMove, Stored, StoredRun};
use crate::link::interface::{ArmCommand, CommandKind, TelemetrySource};

/// Silence after which a link is stale and telemetry is drawn as old.
pub const STALE_AFTER: Duration = Duration::from_millis(500);
/// How long a STOP may take to be confirmed before `STOPPING` becomes `MAY BE MOVING`.
pub const STOP_GRACE: Duration = Duration::from_millis(500);
/// An action status read this soon after the start may predate it.
const ACTION_GRACE: Duration = Duration::from_millis(500);
/// Without an action status: at rest this long after the start means it had nothing to do.
const NO_MOTION_GRACE: Duration = Duration::from_secs(1);
/// A tracked action not seen to end by then is no longer tracked (and stays unsettled).
pub const ACTION_TIMEOUT: Duration = Duration::from_secs(60);
/// Without telemetry, how long an action is assumed to take at most.
pub const NO_TELEMETRY_ACTION_TIME: Duration = Duration::from_secs(30);
/// A joint this far from where it was when an action started has moved.
const MOVED_DEG: f32 = 0.5;
/// Telemetry intervals kept to estimate the link's period.
const INTERVALS_KEPT: usize = 8;

/// An action the console started and watches until it ends.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ActionKind {
    /// A stored action or sequence the arm runs: home, or one started by id.
    Stored(StoredAction),
    GoTo(String),
    Step,
}

/// Which stored run: home has its own key and words; others are named by kind and id.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StoredAction {
    /// Talos Home, or the Modbus home action (`AppConfig::home_action`), followed by id.
    Home,
    ById(Stored),
}

impl ActionKind {
    /// Home, as the tracked action.
    pub const HOME: ActionKind = ActionKind::Stored(StoredAction::Home);

    /// For the status bar: `HOME`, `ACTION 5`, `SEQUENCE 1`, `GOTO bench`, `STEP`.
    pub fn label(&self) -> String {
        match self {
            ActionKind::Stored(StoredAction::Home) => "HOME".into(),
            ActionKind::Stored(StoredAction::ById(stored)) => stored.to_string().to_uppercase(),
            ActionKind::GoTo(name) => format!("GOTO {name}"),
            ActionKind::Step => "STEP".into(),
        }
    }

    /// For messages: `home`, `action 5`, `go to 'bench'`, `step`.
    pub fn verb(&self) -> String {
        match self {
            ActionKind::Stored(StoredAction::Home) => "home".into(),
            ActionKind::Stored(StoredAction::ById(stored)) => stored.to_string(),
            ActionKind::GoTo(name) => format!("go to '{name}'"),
            ActionKind::Step => "step".into(),
        }
    }

    /// Whether a `kind` command is this action's (its failure is the action's, its answer too).
    fn failed_by(&self, kind: CommandKind) -> bool {
        matches!(
            (self, kind),
            (ActionKind::Stored(StoredAction::Home), CommandKind::Home)
                | (
                    ActionKind::Stored(StoredAction::ById(_)),
                    CommandKind::StartStored
                )
                | (
                    ActionKind::GoTo(_),
                    CommandKind::GoToPosition | CommandKind::MoveToPose
                )
                | (ActionKind::Step, CommandKind::Step)
        )
    }

    /// Whether `command` going through is this action's (a stored run's of its id).
    fn answers(&self, command: &ArmCommand) -> bool {
        match (self, command) {
            (ActionKind::Stored(StoredAction::ById(ours)), ArmCommand::StartStored(done)) => {
                ours == done
            }
            _ => self.failed_by(command.kind()),
        }
    }

    /// A stored action or sequence runs until it ends on its own: any key stops it.
    pub(in crate::console::app) fn stops_on_any_key(&self) -> bool {
        matches!(self, ActionKind::Stored(_))
    }
}

/// A home, stored action, go-to or step in progress.
#[derive(Debug, Clone, PartialEq)]
pub struct TrackedAction {
    pub kind: ActionKind,
    /// A stored run of known id: its progress is the action status ([`crate::kortex::StoredRun`]).
    run: Option<StoredRun>,
    sent: Instant,
    /// When the link reported the command taken.
    accepted: Option<Instant>,
    /// Where a go-to must end: done only at rest there (see `target`).
    target: Option<GoToTarget>,
    /// Our go-to as the action status shows it; another move is another client's.
    move_type: Option<OurMove>,
    /// The status has shown `move_type` started since it was sent.
    seen_ours: bool,
    /// For a Talos Go To: what the status named when it was sent, to spot a stored run since.
    status_before: Option<ActionState>,
    /// Joint positions when it was sent, to see it moved even between two polls.
    from: Option<[f32; 7]>,
    /// A joint-fault warning was already raised when it was sent.
    warned_before: bool,
    seen_motion: bool,
    seen_started: bool,
}

/// What the status bar says about motion.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum MotionShown {
    Jog(JogMotion),
    /// A tracked action; `confirmed` is false without telemetry to watch it.
    Action {
        label: String,
        confirmed: bool,
    },
    /// A STOP was sent and its confirmation (or rest) is still within the grace time.
    Stopping,
    /// The arm may be moving although nothing is commanded; why.
    MayBeMoving(String),
    /// Telemetry shows motion the console did not command: another client moves the arm.
    MovedByAnotherClient,
    Idle,
}

/// What the status bar and the panels show of the motion truth, worked out once per frame.
#[derive(Debug, Clone, PartialEq)]
pub struct MotionStatusView {
    pub motion: MotionShown,
    /// How long the link has been silent, when that makes it stale.
    pub link_stale: Option<Duration>,
    pub telemetry_source: TelemetrySource,
    /// The telemetry's age, when it is old enough to be drawn as stale.
    pub telemetry_stale: Option<Duration>,
    /// Whether the telemetry lets the console watch the cap (`None` until the driver says).
    pub cap_watched: Option<bool>,
}

/// The evidence the console has about the link and the arm's motion.
#[derive(Debug, Clone, Default)]
pub struct MotionTruth {
    /// The telemetry the driver said to expect; until it says, nothing is stale.
    expect: Option<TelemetrySource>,
    link_up_at: Option<Instant>,
    telemetry_at: Option<Instant>,
    intervals: VecDeque<Duration>,
    telemetry_moving: bool,
    /// The oldest command sent since the link last answered one.
    waiting_since: Option<Instant>,
    /// Motion was commanded and is not yet shown to have ended.
    unsettled: bool,
    /// Motion was commanded after the last STOP.
    motion_since_stop: bool,
    /// A STOP sent and not yet answered.
    stop_sent: Option<Instant>,
    /// A confirmed STOP after the last motion, waiting for telemetry at rest.
    stop_confirmed_at: Option<Instant>,
    /// The last STOP outcome: it did not get through.
    stop_failure: Option<String>,
    /// A tracked action failed: send a STOP after this input, so its end gets confirmed.
    stop_needed: bool,
    action: Option<TrackedAction>,
}

impl MotionTruth {
    pub fn action(&self) -> Option<&TrackedAction> {
        self.action.as_ref()
    }

    /// The watched action ends here (said once by the caller, not also as "home stopped").
    pub(in crate::console::app) fn forget_action(&mut self) {
        self.action = None;
    }

    /// The last STOP did not get through and none has been confirmed since.
    pub(super) fn stop_unconfirmed(&self) -> bool {
        self.stop_failure.is_some()
    }

    pub(in crate::console::app) fn is_unsettled(&self) -> bool {
        self.unsettled
    }

    pub fn expected_telemetry(&self) -> Option<TelemetrySource> {
        self.expect
    }

    /// Whether the driver said telemetry comes: the one answer to "is telemetry expected".
    pub(in crate::console::app) fn expects_telemetry(&self) -> bool {
        matches!(
            self.expect,
            Some(TelemetrySource::Modbus | TelemetrySource::TalosHardware)
        )
    }
}
