//! Another client on the same arm: its STOP is a STOP, and its motion is shown as its own.
//!
//! After [`OTHER_CLIENT_GRACE`] from a jog's START, the console stops and latches its keys when the
//! telemetry says someone else stopped or replaced the jog: over Modbus the action status (aborted,
//! completed) or move type leaving twist, one sample; otherwise [`OTHER_CLIENT_SAMPLES`]
//! contradicting samples in a row (`jog_evidence`), or one standing for [`CONTRADICTED_FOR`]. A
//! joint-fault warning at such a stop is the arm stopping itself at a limit, and is said so.
//!
//! A refreshed START is a new START to the operator, so a due refresh is held
//! ([`App::hold_refresh`]) until the [`REFRESH_SAMPLES`]th sample that does not contradict the jog,
//! or [`REFRESH_WAIT`]. A STOP landing between that read and the refresh leaves no trace: its
//! sender holds it (`stop_hold`). Idle, motion over [`OTHER_MOTION_M_S`] (or
//! [`OTHER_MOTION_JOINT_DEG_S`]) with nothing of ours unsettled is `MOVED BY ANOTHER CLIENT`. The
//! rules in full: `docs/safety.md`, "Another client's STOP".

use std::time::{Duration, Instant};

use super::jog_evidence::{
    Contradiction, OTHER_MOTION_JOINT_DEG_S, OTHER_MOTION_M_S, contradiction, progress,
};
use super::{App, Effect};
use crate::console::coords::describe_motion;
use crate::console::jog::{JogEffect, JogMotion};
use crate::kortex::arm_state::{
    REST_ANGULAR_DEG_S, REST_JOINT_DEG_S, REST_LINEAR_M_S, abort_reason,
};
use crate::kortex::{ActionStatus, Coded, Flag, MoveType, ReferenceFrame, Telemetry};
use crate::link::interface::{ArmCommand, TelemetrySource};
use crate::link::speed::{INITIAL_SPEED, fraction};

/// How long after a jog's START telemetry may still show the arm as before: the START's trip, the
/// arm's ramp-up and a poll or two, with a margin over twice that; the grace an action's first
/// status gets too.
pub const OTHER_CLIENT_GRACE: Duration = Duration::from_millis(500);
/// Samples in a row before it counts: three at 30 Hz are 100 ms of agreement.
pub const OTHER_CLIENT_SAMPLES: u32 = 3;
/// A jog is told from rest only at this many times the at-rest threshold (1 % creeps at it).
const REST_MARGIN: f64 = 3.0;
/// A shorter contradicting run lasting this long is a stop too (inside the 500 ms watchdog).
pub const CONTRADICTED_FOR: Duration = Duration::from_millis(250);
/// The first sample after a due refresh may predate it; the second was read a poll later.
pub const REFRESH_SAMPLES: u32 = 2;
/// A refresh waits at most this long for its samples (under 300 ms between refreshes).
pub const REFRESH_WAIT: Duration = Duration::from_millis(200);

/// What the console watches for other clients.
#[derive(Debug, Clone, Default)]
pub struct OtherClients {
    /// The jog motion last sent and when it was first sent (refreshes keep the time).
    jog_since: Option<(JogMotion, Instant)>,
    /// The move type has read twist since the jog started: only then is another type a change.
    seen_twist: bool,
    /// Since when the jog's speed is compared with its steady speed, and that speed (mm/s, deg/s).
    baseline_since: Option<Instant>,
    steady: Option<f64>,
    /// The run of samples that contradict the jog: how many, since when, and the last.
    contradicting_in_a_row: u32,
    contradicting_since: Option<Instant>,
    last_contradiction: Option<Contradiction>,
    /// When a refresh fell due, and how many non-contradicting samples came since.
    refresh_waiting: Option<(Instant, u32)>,
    /// Refreshes held back at least once by a contradicting sample.
    withheld: u64,
    moving_in_a_row: u32,
    /// How many of our jogs another client stopped.
    stops: u64,
    /// The technician's STOP, held against a restart from elsewhere.
    pub(super) hold: super::stop_hold::StopHold,
}

impl OtherClients {
    pub fn stops(&self) -> u64 {
        self.stops
    }

    pub fn withheld(&self) -> u64 {
        self.withheld
    }

    pub fn stop_hold(&self) -> &super::stop_hold::StopHold {
        &self.hold
    }

    /// A due refresh of `motion`, held out of `jog` for samples ([`App::hold_refresh`]).
    pub(super) fn hold_refresh(
        &mut self,
        motion: JogMotion,
        watched: bool,
        jog: &mut Vec<JogEffect>,
        now: Instant,
    ) {
        let past_grace = self
            .jog_since
            .is_some_and(|(m, since)| m == motion && now >= since + OTHER_CLIENT_GRACE);
        if !(watched && past_grace) {
            return;
        }
        let asked = jog.len();
        jog.retain(|e| *e != JogEffect::Start(motion));
        if jog.len() != asked && self.refresh_waiting.is_none() {
            if self.contradicting_in_a_row > 0 {
                self.withheld += 1;
            }
            self.refresh_waiting = Some((now, 0));
        }
    }

    fn forget_jog(&mut self) {
        self.jog_since = None;
        self.refresh_waiting = None;
        self.end_contradiction();
    }

    fn end_contradiction(&mut self) {
        self.contradicting_in_a_row = 0;
        self.contradicting_since = None;
        self.last_contradiction = None;
    }
}

impl App {
    /// A command going out: a START starts the grace, a stop ends the watch, a speed resets it.
    pub(super) fn other_client_note_sent(&mut self, command: &ArmCommand, now: Instant) {
        let others = &mut self.arm.others_mut();
        match command {
            // A refresh of the same motion keeps its start.
            ArmCommand::Jog(motion) if others.jog_since.is_none_or(|(m, _)| m != *motion) => {
                others.forget_jog();
                others.jog_since = Some((*motion, now));
                others.seen_twist = false;
                others.baseline_since = Some(now);
                others.steady = None;
            }
            ArmCommand::Jog(_) => others.refresh_waiting = None,
            ArmCommand::SetSpeed(_) | ArmCommand::FenceSpeed(_) => {
                self.other_client_note_speed(now)
            }
            c if c.is_stop() || c.starts_motion() => others.forget_jog(),
            _ => {}
        }
        if command.starts_motion() {
            self.arm.others_mut().hold.release();
        }
    }

    /// The speed in force changed: the steady speed is learnt anew after a grace.
    pub(super) fn other_client_note_speed(&mut self, now: Instant) {
        let others = self.arm.others_mut();
        (others.baseline_since, others.steady) = (Some(now), None);
    }

    /// Fresh telemetry: is our jog still the arm's motion, and is someone else moving it?
    pub(super) fn watch_other_clients(
        &mut self,
        t: &Telemetry,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) {
        let moving = fast_motion(t);
        self.keep_stop(moving, now, effects);
        let others = self.arm.others_mut();
        others.moving_in_a_row = if moving {
            others.moving_in_a_row.saturating_add(1)
        } else {
            0
        };
        let Some(motion) = self.keys.jog().active() else {
            others.end_contradiction();
            return;
        };
        let Some((_, since)) = others.jog_since.filter(|(m, _)| *m == motion) else {
            return;
        };
        let was_twist = others.seen_twist;
        others.seen_twist |= t.action.move_type == Coded::Known(MoveType::Twist);
        if now < since + OTHER_CLIENT_GRACE {
            others.end_contradiction();
            return;
        }
        let modbus = self.motion_truth.expected_telemetry() == Some(TelemetrySource::Modbus);
        if modbus && ended_under_jog(t, motion, was_twist) {
            let evidence = format!(
                "the arm's action is {} ({}) under our {} jog",
                t.action.status.key(),
                t.action.move_type.key(),
                describe_motion(motion)
            );
            self.stop_for_other_client(t, evidence, now, effects);
            return;
        }
        let base = !self.config.frames || self.arm.frame() == ReferenceFrame::Base;
        let rest_telling = self.jog_unmistakable_from_rest(motion);
        let others = self.arm.others_mut();
        let slow_ready = others
            .baseline_since
            .is_some_and(|at| now >= at + OTHER_CLIENT_GRACE);
        let steady = others.steady.filter(|_| slow_ready);
        let Some(found) = contradiction(t, motion, base, steady, rest_telling) else {
            others.end_contradiction();
            if slow_ready && let Some((seen, _)) = progress(t, motion, base) {
                others.steady = Some(others.steady.map_or(seen, |s| s.max(seen)));
            }
            if let Some((_, fine)) = others.refresh_waiting.as_mut() {
                *fine += 1;
                if *fine >= REFRESH_SAMPLES {
                    others.refresh_waiting = None;
                    effects.push(Effect::Arm(ArmCommand::Jog(motion)));
                }
            }
            return;
        };
        others.contradicting_in_a_row += 1;
        let first = *others.contradicting_since.get_or_insert(now);
        others.last_contradiction = Some(found.clone());
        if others.contradicting_in_a_row >= OTHER_CLIENT_SAMPLES || now >= first + CONTRADICTED_FOR
        {
            self.stop_for_other_client(t, found.words(motion), now, effects);
        }
    }

    /// Time under a held jog: a long contradiction stops it; a long-waiting refresh goes out.
    pub(super) fn other_clients_on_tick(&mut self, now: Instant, effects: &mut Vec<Effect>) {
        let Some(motion) = self.keys.jog().active() else {
            return;
        };
        let others = self.arm.others_mut();
        if let (Some(first), Some(found)) = (
            others.contradicting_since,
            others.last_contradiction.clone(),
        ) && now >= first + CONTRADICTED_FOR
        {
            let text = found.words(motion);
            if let Some(t) = self.arm.telemetry().cloned() {
                self.stop_for_other_client(&t, text, now, effects);
            }
            return;
        }
        if others.contradicting_in_a_row == 0
            && others
                .refresh_waiting
                .is_some_and(|(at, _)| now >= at + REFRESH_WAIT)
        {
            others.refresh_waiting = None;
            effects.push(Effect::Arm(ArmCommand::Jog(motion)));
        }
    }

    /// When [`App::other_clients_on_tick`] has something to do.
    pub(super) fn other_clients_deadline(&self) -> Option<Instant> {
        self.keys.jog().active()?;
        let others = self.arm.others();
        let contradicted = others.contradicting_since.map(|at| at + CONTRADICTED_FOR);
        let waiting = others.refresh_waiting.map(|(at, _)| at + REFRESH_WAIT);
        contradicted.into_iter().chain(waiting).min()
    }

    /// Stops and latches a jog another client (or a joint limit) stopped, saying which and why.
    fn stop_for_other_client(
        &mut self,
        t: &Telemetry,
        evidence: String,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) {
        self.arm.others_mut().forget_jog();
        let text = if t.warnings.contains(Flag::JointFault) {
            format!("jog stopped by the arm: {}", abort_reason(t))
        } else {
            self.arm.others_mut().stops += 1;
            format!("stopped by another client: {evidence}")
        };
        self.stop_from_telemetry(text, now, effects);
    }

    /// Whether `motion` runs at least [`REST_MARGIN`] times the at-rest threshold of what it moves.
    fn jog_unmistakable_from_rest(&self, motion: JogMotion) -> bool {
        let percent = self.arm.speed().unwrap_or(INITIAL_SPEED);
        let (expected, rest) = match motion {
            JogMotion::Cartesian { .. } | JogMotion::Polar { .. } => {
                (self.cap.tool_speed(percent), f64::from(REST_LINEAR_M_S))
            }
            JogMotion::Orientation { .. } => (
                f64::from(self.cap.turn_rate(percent)),
                f64::from(REST_ANGULAR_DEG_S),
            ),
            JogMotion::Joint { .. } => (
                f64::from(self.config.joint_jog_speed) * fraction(percent),
                f64::from(REST_JOINT_DEG_S),
            ),
        };
        expected >= REST_MARGIN * rest
    }

    /// Idle, nothing unsettled, and the arm moving for [`OTHER_CLIENT_SAMPLES`] samples.
    pub(super) fn moved_by_another_client(&self) -> bool {
        self.keys.jog().active().is_none()
            && self.motion_truth.action().is_none()
            && !self.motion_truth.is_unsettled()
            && self.arm.others().moving_in_a_row >= OTHER_CLIENT_SAMPLES
    }

    pub fn other_clients(&self) -> &OtherClients {
        self.arm.others()
    }

    /// The technician's STOP went out: hold it (see `stop_hold`).
    pub(super) fn hold_stop(&mut self, now: Instant) {
        self.arm.others_mut().hold.arm(now);
    }

    /// A telemetry sample while the STOP holds: moving, it is stopped again.
    pub(super) fn keep_stop(&mut self, moving: bool, now: Instant, effects: &mut Vec<Effect>) {
        if !self.arm.others_mut().hold.resend(moving, now) {
            return;
        }
        tracing::warn!("the arm moves after our STOP: sending STOP again");
        effects.push(Effect::Arm(ArmCommand::Stop));
        if self.arm.others().hold.past_slowing_down(now) {
            let text = "the arm moved after our STOP (another client?): stopped again";
            self.warn(text, now);
        }
    }
}

/// Over Modbus: the action ended under our jog, or the move type left twist (not a joint jog).
fn ended_under_jog(t: &Telemetry, motion: JogMotion, was_twist: bool) -> bool {
    let ended = matches!(
        t.action.status,
        Coded::Known(ActionStatus::Aborted | ActionStatus::Completed)
    );
    let twist_expected = was_twist && !matches!(motion, JogMotion::Joint { .. });
    let not_twist = matches!(t.action.move_type, Coded::Known(m) if m != MoveType::Twist);
    ended || (twist_expected && not_twist)
}

/// The tool point or a joint faster than the idle thresholds (NaN is not fast: it says nothing).
fn fast_motion(t: &Telemetry) -> bool {
    t.tcp.twist.linear_speed() > OTHER_MOTION_M_S
        || t.joints
            .iter()
            .any(|j| j.velocity.abs() > OTHER_MOTION_JOINT_DEG_S)
}

#[cfg(test)]
mod tests {
    use super::*;

    const PLUS_X: JogMotion = JogMotion::Cartesian { x: 1, y: 0, z: 0 };

    fn jogging_since(t0: Instant) -> OtherClients {
        OtherClients {
            jog_since: Some((PLUS_X, t0)),
            ..OtherClients::default()
        }
    }

    #[test]
    fn a_refresh_is_held_only_past_the_grace_with_telemetry_to_go_by() {
        let t0 = Instant::now();
        let past = t0 + OTHER_CLIENT_GRACE;
        let early = past - Duration::from_millis(1);
        for (watched, now, held) in [
            (true, past, true),
            (false, past, false),
            (true, early, false),
        ] {
            let mut others = jogging_since(t0);
            let mut jog = vec![JogEffect::Start(PLUS_X)];
            others.hold_refresh(PLUS_X, watched, &mut jog, now);
            assert_eq!(jog.is_empty(), held, "watched {watched}, at {now:?}");
            assert_eq!(others.refresh_waiting.is_some(), held);
        }
    }

    #[test]
    fn a_refresh_held_after_a_contradicting_sample_is_counted_withheld_once() {
        let t0 = Instant::now();
        let now = t0 + OTHER_CLIENT_GRACE;
        let mut others = jogging_since(t0);
        others.contradicting_in_a_row = 1;
        let mut jog = vec![JogEffect::Start(PLUS_X), JogEffect::Stop];
        others.hold_refresh(PLUS_X, true, &mut jog, now);
        assert_eq!(jog, vec![JogEffect::Stop], "only the refresh is held");
        assert_eq!(others.withheld(), 1);
        let mut again = vec![JogEffect::Start(PLUS_X)];
        others.hold_refresh(PLUS_X, true, &mut again, now + Duration::from_millis(100));
        assert!(again.is_empty());
        assert_eq!(others.withheld(), 1, "one refresh waiting is one withheld");
    }
}
