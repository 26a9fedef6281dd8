//! The motion truth in the state machine: notes what the console sends after every input, takes the
//! driver's evidence (status, telemetry, answers, STOP outcomes, action ends), and says what the
//! status bar shows and when it next changes on its own.

use std::time::{Duration, Instant};

use super::actions::{End, heuristic_end, run_end};
use super::{
    ActionKind, GoToTarget, INTERVALS_KEPT, MotionShown, MotionStatusView, STOP_GRACE,
    StoredAction, TrackedAction,
};
use crate::console::app::age::age_text;
use crate::console::app::message::Until;
use crate::console::app::{App, Effect, Severity};
use crate::kortex::arm_state::at_rest;
use crate::kortex::{Flag, MoveType, OurMove, StoredRun, Telemetry};
use crate::link::interface::{ArmCommand, ArmEvent, LinkStatus};

impl App {
    /// Evidence from the driver, before the event is otherwise handled.
    pub(in crate::console::app) fn motion_truth_on_arm(&mut self, event: &ArmEvent, now: Instant) {
        let motion_truth = &mut self.motion_truth;
        match event {
            ArmEvent::Status(status) => {
                if matches!(status, LinkStatus::Up { .. }) && !self.arm.link_up() {
                    motion_truth.link_up_at = Some(now);
                    motion_truth.waiting_since = None;
                    // Back after a loss with motion unaccounted for: a STOP is always safe.
                    motion_truth.stop_needed |=
                        motion_truth.unsettled || motion_truth.action.is_some();
                }
            }
            ArmEvent::TelemetrySource(source) => motion_truth.expect = Some(*source),
            ArmEvent::Telemetry(t) => {
                if let Some(last) = motion_truth.telemetry_at {
                    let interval = now.saturating_duration_since(last);
                    if motion_truth.intervals.len() >= INTERVALS_KEPT {
                        motion_truth.intervals.pop_front();
                    }
                    motion_truth.intervals.push_back(interval);
                }
                motion_truth.telemetry_at = Some(now);
                motion_truth.telemetry_moving = !at_rest(t);
                if !motion_truth.telemetry_moving
                    && motion_truth
                        .stop_confirmed_at
                        .is_some_and(|confirmed| now >= confirmed)
                {
                    motion_truth.unsettled = false;
                    motion_truth.stop_confirmed_at = None;
                }
            }
            // No answer to a command: a latency comes for polls as well as replies, the guard is
            // the console's own process, a notice the driver's own words (its answer comes apart).
            ArmEvent::Latency(_) | ArmEvent::Guard(_) | ArmEvent::Notice(_) => {}
            ArmEvent::Log(entry) if entry.poll => {}
            ArmEvent::Log(_)
            | ArmEvent::Speed(_)
            | ArmEvent::Done { .. }
            | ArmEvent::Failed { .. }
            | ArmEvent::Position { .. }
            | ArmEvent::UnknownPosition { .. } => motion_truth.waiting_since = None,
            ArmEvent::StopConfirmed => {
                motion_truth.waiting_since = None;
                motion_truth.stop_sent = None;
                if !motion_truth.motion_since_stop {
                    motion_truth.stop_failure = None;
                    if motion_truth.expects_telemetry() {
                        motion_truth.stop_confirmed_at = Some(now);
                    } else {
                        motion_truth.unsettled = false;
                    }
                }
            }
            ArmEvent::StopUnconfirmed { reason } => {
                motion_truth.waiting_since = None;
                motion_truth.stop_sent = None;
                motion_truth.stop_failure = Some(reason.clone());
                motion_truth.stop_confirmed_at = None;
            }
        }
        match event {
            ArmEvent::Telemetry(t) => self.watch_action(t, now),
            ArmEvent::Done { command } => {
                if let Some(action) = self.motion_truth.action.as_mut()
                    && action.kind.answers(command)
                {
                    action.accepted.get_or_insert(now);
                }
            }
            ArmEvent::Failed { command, .. }
                if self
                    .motion_truth
                    .action
                    .as_ref()
                    .is_some_and(|a| a.kind.failed_by(*command)) =>
            {
                // The failure itself is said by the caller; a STOP settles the doubt.
                self.motion_truth.action = None;
                self.motion_truth.stop_needed = true;
            }
            ArmEvent::StopUnconfirmed { reason } => {
                let text = format!(
                    "STOP NOT CONFIRMED: {reason}. The arm may still be moving: use its e-stop"
                );
                self.say_until(text, Severity::Error, Until::StopConfirmed, now);
            }
            _ => {}
        }
    }

    /// The truth's part of the view: the motion shown and the ages that make things stale.
    pub(in crate::console::app) fn motion_status_view(&self) -> MotionStatusView {
        MotionStatusView {
            motion: self.motion_shown(),
            link_stale: self.link_stale(),
            telemetry_source: self.telemetry_source(),
            telemetry_stale: self.telemetry_stale(),
            cap_watched: self.cap_watched(),
        }
    }

    /// The status bar's motion, by precedence: jog, action, STOP confirming, doubt, idle.
    pub fn motion_shown(&self) -> MotionShown {
        if let Some(motion) = self.keys.jog().active() {
            return MotionShown::Jog(motion);
        }
        let motion_truth = &self.motion_truth;
        if let Some(action) = &motion_truth.action {
            return MotionShown::Action {
                label: action.kind.label(),
                confirmed: motion_truth.expects_telemetry(),
            };
        }
        let Some(now) = self.now else {
            return MotionShown::Idle;
        };
        if let Some(reason) = &motion_truth.stop_failure {
            return MotionShown::MayBeMoving(format!("stop not confirmed: {reason}"));
        }
        if motion_truth.unsettled {
            if !self.arm.link_up() {
                return MotionShown::MayBeMoving("link lost after motion".into());
            }
            if let Some(age) = self.link_stale() {
                return MotionShown::MayBeMoving(format!(
                    "no word from the arm for {}",
                    age_text(age)
                ));
            }
        }
        let within = |at: Option<Instant>| at.is_some_and(|at| now < at + STOP_GRACE);
        if within(motion_truth.stop_sent)
            || (motion_truth.unsettled && within(motion_truth.stop_confirmed_at))
        {
            return MotionShown::Stopping;
        }
        let telemetry_fresh =
            self.telemetry_stale().is_none() && motion_truth.telemetry_at.is_some();
        if telemetry_fresh && self.moved_by_another_client() {
            return MotionShown::MovedByAnotherClient;
        }
        if telemetry_fresh && motion_truth.telemetry_moving {
            return MotionShown::MayBeMoving("telemetry shows motion".into());
        }
        if motion_truth.stop_sent.is_some() {
            return MotionShown::MayBeMoving("stop not acknowledged".into());
        }
        if motion_truth.unsettled {
            let why = if motion_truth.stop_confirmed_at.is_some() {
                "no telemetry at rest since the stop"
            } else {
                "motion not shown to have ended: press stop"
            };
            return MotionShown::MayBeMoving(why.into());
        }
        MotionShown::Idle
    }

    /// How long the link has been silent, when that makes it stale (only while it is up).
    pub fn link_stale(&self) -> Option<Duration> {
        let now = self.now.filter(|_| self.arm.link_up())?;
        self.motion_truth.stale_for(now)
    }

    /// The age of the telemetry shown, when it is old enough to be drawn as stale.
    pub fn telemetry_stale(&self) -> Option<Duration> {
        let (now, at) = (self.now?, self.motion_truth.telemetry_at?);
        let age = now.saturating_duration_since(at);
        (age >= self.motion_truth.stale_after()).then_some(age)
    }

    /// The truth's part of [`App::next_deadline`].
    pub(in crate::console::app) fn motion_truth_deadline(&self) -> Option<Instant> {
        let now = self.now?;
        self.motion_truth.next_deadline(now, self.arm.link_up())
    }

    /// After every input: a stale link starts no motion (a frozen network could deliver it any
    /// time) and stops the jog; tracked actions time out; emitted commands are noted.
    pub(in crate::console::app) fn motion_truth_after(
        &mut self,
        goto: Option<String>,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) {
        // Whatever emitted it, no motion starts while the gate refuses (a stale link above all).
        self.gate_effects(now, effects);
        // After the gate: the fence shapes or stops what the gate let through.
        self.fence_effects(now, effects);
        if let Some(age) = self.link_stale() {
            // An action the console can no longer watch is stopped: never moving unseen.
            self.motion_truth.stop_needed |= self.motion_truth.action.is_some();
            if self.keys.jog().is_jogging() {
                self.stop_jog(now, effects);
                let age = age_text(age);
                let text = format!("link stale: no word from the arm for {age}: jog stopped");
                self.say_until(text, Severity::Error, Until::LinkFresh, now);
            }
        }
        self.time_out_action(now);
        if std::mem::take(&mut self.motion_truth.stop_needed)
            && !effects.iter().any(Effect::is_stop)
        {
            effects.push(Effect::Arm(ArmCommand::Stop));
        }
        for effect in effects.iter() {
            if let Effect::Arm(command) = effect {
                self.note_sent(command, goto.clone(), now);
                self.other_client_note_sent(command, now);
            }
        }
    }

    fn note_sent(&mut self, command: &ArmCommand, goto: Option<String>, now: Instant) {
        // Where a go-to must end, and the move the arm's status shows for it (see `target`).
        let (target, move_type) = match command {
            ArmCommand::MoveToPose(pose) => (
                Some(GoToTarget::pose(*pose)),
                Some(OurMove {
                    move_type: MoveType::CartesianTrajectory,
                    id: None,
                }),
            ),
            ArmCommand::GoToPosition { name } => (
                self.book.positions().get(name).and_then(GoToTarget::book),
                None,
            ),
            _ => (None, None),
        };
        let motion_truth = &mut self.motion_truth;
        motion_truth.waiting_since.get_or_insert(now);
        if command.is_stop() {
            motion_truth.stop_sent = Some(now);
            motion_truth.motion_since_stop = false;
            motion_truth.stop_confirmed_at = None;
            if let Some(action) = motion_truth.action.take() {
                let verb = action.kind.verb();
                self.info(format!("{verb} stopped"), now);
            }
            return;
        }
        let kind = match command {
            ArmCommand::Jog(_) => None,
            ArmCommand::Home => Some(ActionKind::HOME),
            ArmCommand::StartStored(stored) => {
                Some(ActionKind::Stored(StoredAction::ById(*stored)))
            }
            ArmCommand::GoToPosition { name } => Some(ActionKind::GoTo(name.clone())),
            ArmCommand::MoveToPose(_) => Some(ActionKind::GoTo(goto.unwrap_or_default())),
            ArmCommand::Step(_) => Some(ActionKind::Step),
            _ => return,
        };
        motion_truth.unsettled = true;
        motion_truth.motion_since_stop = true;
        motion_truth.stop_confirmed_at = None;
        // A new motion replaces whatever action was running.
        let last = self.arm.telemetry();
        motion_truth.action = kind.map(|kind| TrackedAction {
            run: match kind {
                ActionKind::Stored(StoredAction::ById(stored)) => Some(StoredRun::new(stored)),
                ActionKind::Stored(StoredAction::Home) => {
                    self.config.home_action.map(StoredRun::new)
                }
                _ => None,
            },
            kind,
            sent: now,
            accepted: None,
            target,
            move_type,
            seen_ours: false,
            status_before: last.map(|t| t.action),
            from: last.map(|t| t.joints.map(|j| j.position)),
            warned_before: last.is_some_and(|t| t.warnings.contains(Flag::JointFault)),
            seen_motion: false,
            seen_started: false,
        });
    }

    /// Watches a tracked action's end ([`crate::kortex::StoredRun::observe`], [`heuristic_end`]).
    pub(super) fn watch_action(&mut self, t: &Telemetry, now: Instant) {
        let Some(action) = self.motion_truth.action.as_mut() else {
            return;
        };
        let Some(accepted) = action.accepted else {
            return;
        };
        let end = match action.run.as_mut() {
            Some(run) => run_end(run.observe(t, now.saturating_duration_since(accepted))),
            None => heuristic_end(action, accepted, t, now),
        };
        let verb = action.kind.verb();
        match end {
            Some(End::Failed { reason, fault }) => {
                self.motion_truth.action = None;
                self.motion_truth.stop_needed = true;
                // A fault's message stays until the fault is gone; an abort's is a notice.
                let until = match fault {
                    true => Until::fault(None, true),
                    false => Until::TimeOut { done: None },
                };
                let text = format!("{verb} failed: {reason}");
                self.say_until(text, Severity::Error, until, now);
            }
            Some(End::MovedByAnotherClient(evidence)) => {
                // Not ours: stopped like a failure, and never said done.
                self.motion_truth.action = None;
                self.motion_truth.stop_needed = true;
                let text =
                    format!("{verb} not done: MOVED BY ANOTHER CLIENT: {evidence}; STOP sent");
                self.error(text, now);
            }
            Some(End::Done) => {
                // The arm reported the end and telemetry shows it at rest: settled.
                self.motion_truth.action = None;
                self.motion_truth.unsettled = false;
                self.info(format!("{verb} done"), now);
            }
            None => {}
        }
    }

    pub(super) fn time_out_action(&mut self, now: Instant) {
        let Some(action) = &self.motion_truth.action else {
            return;
        };
        let with_telemetry = self.motion_truth.expects_telemetry();
        let limit = self.motion_truth.action_time_limit();
        if now < action.sent + limit {
            return;
        }
        let (verb, secs) = (action.kind.verb(), limit.as_secs());
        self.motion_truth.action = None;
        if with_telemetry {
            self.warn(format!("{verb}: no end seen within {secs} s"), now);
        } else {
            // Without telemetry an action ends once its longest expected time has passed.
            self.motion_truth.unsettled = false;
            let text = format!("{verb}: no telemetry; taken as ended after {secs} s");
            self.info(text, now);
        }
    }
}
