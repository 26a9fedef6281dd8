//! What the screen may say about the link and the arm's motion: `LINK STALE`, `STOPPING`,
//! `MAY BE MOVING`, `MOVING: HOME` / `GOTO`, and how old the panels' telemetry is.
//!
//! The rule: the console never says stopped when it may not be. Motion commanded counts as
//! unsettled until there is evidence it ended: a confirmed STOP (and, where telemetry exists,
//! telemetry at rest received after it), or a tracked action (home, go-to, step) seen to
//! complete at rest. A STOP not confirmed, a stale or lost link after motion, or telemetry
//! showing velocity all say `MAY BE MOVING`.
//!
//! Staleness: links with telemetry must send it (every 500 ms at least, or three of their
//! shortest recent intervals when they poll slower); any link must answer what was sent to it
//! within 500 ms. A link in the ack dialect with no telemetry only answers what it is sent, so
//! while idle it is never stale. Nothing counts as stale until the driver has said which
//! telemetry to expect.
//!
//! Ends of actions without an action status (Talos hardware telemetry): joints at rest after
//! having moved, or at rest a second after the start (already there); a joint-fault warning
//! after motion is an abort. Without telemetry (ack dialect) an action shows `MAY BE MOVING:
//! HOME` until a STOP is confirmed or [`NO_TELEMETRY_ACTION_TIME`] has passed.

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use super::arm_state::{AGE_TENTHS_UNTIL, abort_reason, age_text, at_rest, fault_reason};
use super::message::Until;
use super::{App, Effect, Overlay, Severity};
use crate::console::form::Confirm;
use crate::console::jog::JogMotion;
use crate::kortex::{ActionStatus, Coded, Flag, Telemetry};
use crate::link::interface::{ArmCommand, ArmEvent, CommandKind, LinkStatus, TelemetrySource};

/// Silence after which a link is stale and telemetry is drawn as old.
pub const STALE_AFTER: Duration = Duration::from_millis(500);
/// How long a STOP may take to be confirmed (and the arm to be seen at rest) before
/// `STOPPING` turns into `MAY BE MOVING`.
pub const STOP_GRACE: Duration = Duration::from_millis(500);
/// An action status read this soon after the start may predate it.
const ACTION_GRACE: Duration = Duration::from_millis(500);
/// Without an action status: at rest this long after the start means it had nothing to do.
const NO_MOTION_GRACE: Duration = Duration::from_secs(1);
/// A tracked action with telemetry not seen to end within this long stops being tracked (and
/// stays unsettled: `MAY BE MOVING`).
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
    Home,
    GoTo(String),
    Step,
}

impl ActionKind {
    /// For the status bar: `HOME`, `GOTO bench`, `STEP`.
    pub fn label(&self) -> String {
        match self {
            ActionKind::Home => "HOME".into(),
            ActionKind::GoTo(name) => format!("GOTO {name}"),
            ActionKind::Step => "STEP".into(),
        }
    }

    /// For messages: `home`, `go to 'bench'`, `step`.
    pub fn verb(&self) -> String {
        match self {
            ActionKind::Home => "home".into(),
            ActionKind::GoTo(name) => format!("go to '{name}'"),
            ActionKind::Step => "step".into(),
        }
    }

    /// Whether a failure of a `kind` command is this action's.
    fn failed_by(&self, kind: CommandKind) -> bool {
        matches!(
            (self, kind),
            (ActionKind::Home, CommandKind::Home)
                | (
                    ActionKind::GoTo(_),
                    CommandKind::GoToPosition | CommandKind::MoveToPose
                )
                | (ActionKind::Step, CommandKind::Step)
        )
    }

    fn answers(&self, command: &ArmCommand) -> bool {
        matches!(
            (self, command),
            (ActionKind::Home, ArmCommand::Home)
                | (
                    ActionKind::GoTo(_),
                    ArmCommand::GoToPosition { .. } | ArmCommand::MoveToPose(_)
                )
                | (ActionKind::Step, ArmCommand::Step(_))
        )
    }
}

/// A home, go-to or step in progress.
#[derive(Debug, Clone, PartialEq)]
pub struct TrackedAction {
    pub kind: ActionKind,
    sent: Instant,
    /// When the link reported the command taken.
    accepted: Option<Instant>,
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
    Idle,
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
    pub action: Option<TrackedAction>,
}

impl MotionTruth {
    /// The silence after which telemetry is old: 500 ms, or three of the link's shortest recent
    /// intervals if it polls slower than that allows.
    pub fn stale_after(&self) -> Duration {
        let period = self.intervals.iter().min().copied().unwrap_or_default();
        STALE_AFTER.max(period * 3)
    }

    /// The last STOP did not get through and none has been confirmed since.
    pub(super) fn stop_unconfirmed(&self) -> bool {
        self.stop_failure.is_some()
    }

    /// The telemetry the driver said to expect, once it has said.
    pub fn expected_telemetry(&self) -> Option<TelemetrySource> {
        self.expect
    }

    fn expects_telemetry(&self) -> bool {
        matches!(
            self.expect,
            Some(TelemetrySource::Modbus | TelemetrySource::TalosHardware)
        )
    }

    /// How long the link has been silent past its limit, if it has.
    fn stale_for(&self, now: Instant) -> Option<Duration> {
        self.expect?;
        let mut age = None;
        if self.expects_telemetry()
            && let Some(since) = self.telemetry_at.max(self.link_up_at)
        {
            let silent = now.saturating_duration_since(since);
            age = (silent >= self.stale_after()).then_some(silent);
        }
        if let Some(since) = self.waiting_since {
            let silent = now.saturating_duration_since(since);
            if silent >= STALE_AFTER {
                age = age.max(Some(silent));
            }
        }
        age
    }

    /// The next instant something shown changes without any input.
    fn next_deadline(&self, now: Instant, link_up: bool) -> Option<Instant> {
        let mut candidates = Vec::new();
        if link_up && self.expect.is_some() {
            if self.expects_telemetry()
                && let Some(since) = self.telemetry_at.max(self.link_up_at)
            {
                candidates.push(since + self.stale_after());
            }
            candidates.extend(self.waiting_since.map(|since| since + STALE_AFTER));
        }
        // The shown ages count up while anything is old: in tenths, then whole seconds.
        let telemetry_age = self
            .telemetry_at
            .map(|at| now.saturating_duration_since(at))
            .filter(|age| *age >= self.stale_after());
        let link_age = self.stale_for(now).filter(|_| link_up);
        if let Some(age) = telemetry_age.max(link_age) {
            let step = if age < AGE_TENTHS_UNTIL {
                Duration::from_millis(100)
            } else {
                Duration::from_secs(1)
            };
            candidates.push(now + step);
        }
        candidates.extend(self.stop_sent.map(|at| at + STOP_GRACE));
        candidates.extend(self.stop_confirmed_at.map(|at| at + STOP_GRACE));
        if let Some(action) = &self.action {
            let limit = if self.expects_telemetry() {
                ACTION_TIMEOUT
            } else {
                NO_TELEMETRY_ACTION_TIME
            };
            candidates.push(action.sent + limit);
        }
        candidates.into_iter().filter(|at| *at > now).min()
    }
}

/// Whether `command` sets the arm moving.
fn starts_motion(command: &ArmCommand) -> bool {
    matches!(
        command,
        ArmCommand::Jog(_)
            | ArmCommand::Step(_)
            | ArmCommand::Home
            | ArmCommand::GoToPosition { .. }
            | ArmCommand::MoveToPose(_)
    )
}

impl App {
    /// The instant of the latest input: the clock the panels' ages are drawn with.
    pub fn now(&self) -> Option<Instant> {
        self.now
    }

    /// How long the link has been silent, when that makes it stale (only while it is up).
    pub fn link_stale(&self) -> Option<Duration> {
        let now = self.now?;
        match self.link {
            LinkStatus::Up { .. } => self.truth.stale_for(now),
            _ => None,
        }
    }

    /// The age of the telemetry shown, when it is old enough to be drawn as stale.
    pub fn telemetry_stale(&self) -> Option<Duration> {
        let (now, at) = (self.now?, self.truth.telemetry_at?);
        let age = now.saturating_duration_since(at);
        (age >= self.truth.stale_after()).then_some(age)
    }

    /// What the status bar says about motion, by precedence: a jog, a tracked action, a STOP
    /// being confirmed, any doubt, idle.
    pub fn motion_shown(&self) -> MotionShown {
        if let Some(motion) = self.jog.active() {
            return MotionShown::Jog(motion);
        }
        let truth = &self.truth;
        if let Some(action) = &truth.action {
            return MotionShown::Action {
                label: action.kind.label(),
                confirmed: truth.expects_telemetry(),
            };
        }
        let Some(now) = self.now else {
            return MotionShown::Idle;
        };
        if let Some(reason) = &truth.stop_failure {
            return MotionShown::MayBeMoving(format!("stop not confirmed: {reason}"));
        }
        if truth.unsettled {
            match &self.link {
                LinkStatus::Up { .. } => {}
                _ => return MotionShown::MayBeMoving("link lost after motion".into()),
            }
            if let Some(age) = self.link_stale() {
                return MotionShown::MayBeMoving(format!(
                    "no word from the arm for {}",
                    age_text(age)
                ));
            }
        }
        let within = |at: Option<Instant>| at.is_some_and(|at| now < at + STOP_GRACE);
        if within(truth.stop_sent) || (truth.unsettled && within(truth.stop_confirmed_at)) {
            return MotionShown::Stopping;
        }
        let telemetry_fresh = self.telemetry_stale().is_none() && truth.telemetry_at.is_some();
        if telemetry_fresh && truth.telemetry_moving {
            return MotionShown::MayBeMoving("telemetry shows motion".into());
        }
        if truth.stop_sent.is_some() {
            return MotionShown::MayBeMoving("stop not acknowledged".into());
        }
        if truth.unsettled {
            let why = if truth.stop_confirmed_at.is_some() {
                "no telemetry at rest since the stop"
            } else {
                "motion not shown to have ended: press stop"
            };
            return MotionShown::MayBeMoving(why.into());
        }
        MotionShown::Idle
    }

    /// The name of the position a go-to question asks about, taken before the answer.
    pub(super) fn goto_in_question(&self) -> Option<String> {
        match &self.overlay {
            Overlay::Confirm(Confirm::GoTo(name)) => Some(name.clone()),
            _ => None,
        }
    }

    /// Evidence from the driver, before the event is otherwise handled.
    pub(super) fn truth_on_arm(&mut self, event: &ArmEvent, now: Instant) {
        let truth = &mut self.truth;
        match event {
            ArmEvent::Status(status) => {
                let came_up = matches!(status, LinkStatus::Up { .. })
                    && !matches!(self.link, LinkStatus::Up { .. });
                if came_up {
                    truth.link_up_at = Some(now);
                    truth.waiting_since = None;
                    // Back after a loss with motion unaccounted for: a STOP is always safe, and
                    // its confirmation (with telemetry at rest) is the evidence that clears
                    // MAY BE MOVING.
                    if truth.unsettled || truth.action.is_some() {
                        truth.stop_needed = true;
                    }
                }
            }
            ArmEvent::TelemetrySource(source) => truth.expect = Some(*source),
            ArmEvent::Telemetry(t) => {
                if let Some(last) = truth.telemetry_at {
                    let interval = now.saturating_duration_since(last);
                    if truth.intervals.len() >= INTERVALS_KEPT {
                        truth.intervals.pop_front();
                    }
                    truth.intervals.push_back(interval);
                }
                truth.telemetry_at = Some(now);
                truth.telemetry_moving = !at_rest(t);
                if !truth.telemetry_moving
                    && truth
                        .stop_confirmed_at
                        .is_some_and(|confirmed| now >= confirmed)
                {
                    truth.unsettled = false;
                    truth.stop_confirmed_at = None;
                }
            }
            // Sent for polls as well as replies: no answer to a command.
            ArmEvent::Latency(_) => {}
            // The console's own guard process speaks, not the arm.
            ArmEvent::Guard(_) => {}
            ArmEvent::Log(entry) if entry.poll => {}
            ArmEvent::Log(_)
            | ArmEvent::Speed(_)
            | ArmEvent::Done { .. }
            | ArmEvent::Failed { .. }
            | ArmEvent::Position { .. }
            | ArmEvent::UnknownPosition { .. } => truth.waiting_since = None,
            ArmEvent::StopConfirmed => {
                truth.waiting_since = None;
                truth.stop_sent = None;
                if !truth.motion_since_stop {
                    truth.stop_failure = None;
                    if truth.expects_telemetry() {
                        truth.stop_confirmed_at = Some(now);
                    } else {
                        truth.unsettled = false;
                    }
                }
            }
            ArmEvent::StopUnconfirmed { reason } => {
                truth.waiting_since = None;
                truth.stop_sent = None;
                truth.stop_failure = Some(reason.clone());
                truth.stop_confirmed_at = None;
            }
        }
        match event {
            ArmEvent::Telemetry(t) => self.watch_action(t, now),
            ArmEvent::Done { command } => {
                if let Some(action) = self.truth.action.as_mut()
                    && action.kind.answers(command)
                {
                    action.accepted.get_or_insert(now);
                }
            }
            ArmEvent::Failed { command, .. }
                if self
                    .truth
                    .action
                    .as_ref()
                    .is_some_and(|a| a.kind.failed_by(*command)) =>
            {
                // The failure itself is said by the caller; a STOP settles the doubt.
                self.truth.action = None;
                self.truth.stop_needed = true;
            }
            ArmEvent::StopUnconfirmed { reason } => {
                self.say_until(
                    format!(
                        "STOP NOT CONFIRMED: {reason}. The arm may still be moving: use its e-stop"
                    ),
                    Severity::Error,
                    Until::StopConfirmed,
                    now,
                );
            }
            _ => {}
        }
    }

    /// Watches a tracked action's end in fresh telemetry.
    fn watch_action(&mut self, t: &Telemetry, now: Instant) {
        let Some(action) = self.truth.action.as_mut() else {
            return;
        };
        let Some(accepted) = action.accepted else {
            return;
        };
        let rest = at_rest(t);
        let moved = action.from.is_some_and(|from| {
            from.iter().zip(&t.joints).any(|(a, j)| {
                let d = (j.position - a).rem_euclid(360.0);
                d.min(360.0 - d) > MOVED_DEG
            })
        });
        action.seen_motion |= !rest || moved;
        if t.action.status == Coded::Known(ActionStatus::Started) {
            action.seen_started = true;
        }
        // A status read before the command took effect may belong to an earlier action.
        let status_current =
            action.seen_started || action.seen_motion || now >= accepted + ACTION_GRACE;
        let verb = action.kind.verb();
        // A joint-fault warning raised since the start: the arm stopped at a limit.
        let joint_fault =
            t.warnings.contains(Flag::JointFault) && (action.seen_motion || !action.warned_before);
        let aborted = (status_current && t.action.status == Coded::Known(ActionStatus::Aborted))
            || (rest && joint_fault);
        let fault = fault_reason(t);
        // A fault's message stays until the fault is gone; an abort's is a notice.
        let until = match fault {
            Some(_) => Until::fault(None, true),
            None => Until::TimeOut { done: None },
        };
        let failure = fault.or_else(|| aborted.then(|| abort_reason(t)));
        if let Some(reason) = failure {
            self.truth.action = None;
            self.truth.stop_needed = true;
            let text = format!("{verb} failed: {reason}");
            self.say_until(text, Severity::Error, until, now);
            return;
        }
        let done = rest
            && match t.action.status {
                Coded::Known(ActionStatus::Completed) => status_current,
                Coded::Known(ActionStatus::Started) => false,
                _ => action.seen_motion || now >= accepted + NO_MOTION_GRACE,
            };
        if done {
            // The arm reported the end and telemetry shows it at rest: settled.
            self.truth.action = None;
            self.truth.unsettled = false;
            self.say(format!("{verb} done"), Severity::Info, now);
        }
    }

    /// After every input: a stale link starts no motion (a command held up in a frozen network
    /// could run whenever it thaws) and stops the jog; tracked actions time out; the commands
    /// just emitted are noted.
    pub(super) fn truth_after(
        &mut self,
        goto: Option<String>,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) {
        if let Some(age) = self.link_stale() {
            let asked = effects.len();
            effects.retain(|e| !matches!(e, Effect::Arm(command) if starts_motion(command)));
            if effects.len() != asked {
                let text = "link stale: not moving";
                self.say_until(text, Severity::Warning, Until::LinkFresh, now);
            }
            // An action the console can no longer watch is stopped like a jog: the arm must
            // not go on moving unseen.
            if self.truth.action.is_some() {
                self.truth.stop_needed = true;
            }
            if self.jog.is_jogging() {
                self.stop_jog(now, effects);
                self.say_until(
                    format!(
                        "link stale: no word from the arm for {}: jog stopped",
                        age_text(age)
                    ),
                    Severity::Error,
                    Until::LinkFresh,
                    now,
                );
            }
        }
        self.time_out_action(now);
        if std::mem::take(&mut self.truth.stop_needed)
            && !effects
                .iter()
                .any(|e| matches!(e, Effect::Arm(c) if c.is_stop()))
        {
            effects.push(Effect::Arm(ArmCommand::Stop));
        }
        for effect in effects.iter() {
            let Effect::Arm(command) = effect else {
                continue;
            };
            self.note_sent(command, goto.clone(), now);
        }
    }

    fn time_out_action(&mut self, now: Instant) {
        let Some(action) = &self.truth.action else {
            return;
        };
        let with_telemetry = self.truth.expects_telemetry();
        let limit = if with_telemetry {
            ACTION_TIMEOUT
        } else {
            NO_TELEMETRY_ACTION_TIME
        };
        if now < action.sent + limit {
            return;
        }
        let verb = action.kind.verb();
        self.truth.action = None;
        if with_telemetry {
            self.say(
                format!("{verb}: no end seen within {} s", limit.as_secs()),
                Severity::Warning,
                now,
            );
        } else {
            // Documented choice: without telemetry an action is taken to have ended once its
            // longest expected time has passed.
            self.truth.unsettled = false;
            self.say(
                format!(
                    "{verb}: no telemetry; taken as ended after {} s",
                    limit.as_secs()
                ),
                Severity::Info,
                now,
            );
        }
    }

    fn note_sent(&mut self, command: &ArmCommand, goto: Option<String>, now: Instant) {
        let truth = &mut self.truth;
        truth.waiting_since.get_or_insert(now);
        if command.is_stop() {
            truth.stop_sent = Some(now);
            truth.motion_since_stop = false;
            truth.stop_confirmed_at = None;
            if let Some(action) = truth.action.take() {
                let verb = action.kind.verb();
                self.say(format!("{verb} stopped"), Severity::Info, now);
            }
            return;
        }
        let kind = match command {
            ArmCommand::Jog(_) => None,
            ArmCommand::Home => Some(ActionKind::Home),
            ArmCommand::GoToPosition { name } => Some(ActionKind::GoTo(name.clone())),
            ArmCommand::MoveToPose(_) => Some(ActionKind::GoTo(goto.unwrap_or_default())),
            ArmCommand::Step(_) => Some(ActionKind::Step),
            _ => return,
        };
        truth.unsettled = true;
        truth.motion_since_stop = true;
        truth.stop_confirmed_at = None;
        // A new motion replaces whatever action was running.
        let last = self.telemetry.as_ref();
        truth.action = kind.map(|kind| TrackedAction {
            kind,
            sent: now,
            accepted: None,
            from: last.map(|t| t.joints.map(|j| j.position)),
            warned_before: last.is_some_and(|t| t.warnings.contains(Flag::JointFault)),
            seen_motion: false,
            seen_started: false,
        });
    }

    /// The truth's part of [`App::next_deadline`].
    pub(super) fn truth_deadline(&self) -> Option<Instant> {
        let now = self.now?;
        self.truth
            .next_deadline(now, matches!(self.link, LinkStatus::Up { .. }))
    }
}
