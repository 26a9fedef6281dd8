//! The driver's Talos half: frames, replies, hardware ICD telemetry, reconnection.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use tokio::sync::mpsc;

use super::connect::ConnectError;
use super::hw_telemetry;
use super::speed::SpeedInForce;
use super::{DriverConfig, JointPositions};
use crate::link::interface::{ArmCommand, ArmError, ArmEvent, JogMotion, LogEntry, StepMove};
use crate::link::speed::{OperatorScale, SpeedCap};
use crate::link::talos::{TalosConfig, TalosEvent};
use crate::link::{Dialect, TalosLink};
use crate::talos::hardware::{ActuatorCommand, HwReply, HwRequest};
use crate::talos::{CommandValue, Request, stop_requests};

/// How long a joint jog command may run unrenewed: the operator's watchdog, s.
const JOINT_JOG_HORIZON: f64 = 0.5;

/// Why an orientation jog is refused without a Modbus link: nothing goes over Talos for it.
pub const ORIENTATION_NEEDS_MODBUS: &str =
    "orientation jog needs the Modbus link: Talos has no orientation jog";

/// Talos starts only its Home, by no id.
pub const STORED_NEEDS_MODBUS: &str = "stored actions and sequences by id need the Modbus link: \
     Talos runs only home (add --modbus)";

mod answers;
mod connect;

use answers::{answers, failure_reason, hw_reply, log_entry, log_error, report_error};
pub use connect::TalosConnected;

pub struct TalosSide {
    config: Option<TalosConfig>,
    oid: u16,
    joint_jog_speed: f32,
    /// The cap (bounding joint rates by lever arm) and its conversion to the operator's percentage.
    scale: OperatorScale,
    link: Option<TalosLink>,
    link_events: Option<mpsc::UnboundedReceiver<TalosEvent>>,
    events: mpsc::UnboundedSender<ArmEvent>,
    /// The speed in force: changed here only on the operator's answers, never on a request alone.
    speed: SpeedInForce,
    polling: Arc<AtomicBool>,
    /// Joint positions from the latest telemetry, for joint jog commands.
    joints: JointPositions,
    /// The last command's answers, spawned once its frames are written ([`Self::spawn_answers`]).
    answers: Option<Submitted>,
}

/// A command whose requests were submitted: what [`answers`] waits for and reports.
struct Submitted {
    command: ArmCommand,
    pending: Vec<crate::link::talos::PendingReply>,
    stop_failure: Option<ArmError>,
}

impl TalosSide {
    pub fn new(
        config: &DriverConfig,
        scale: OperatorScale,
        events: mpsc::UnboundedSender<ArmEvent>,
        joints: JointPositions,
        speed: SpeedInForce,
    ) -> TalosSide {
        TalosSide {
            config: config.talos.clone(),
            oid: config.oid,
            joint_jog_speed: config.joint_jog_speed,
            scale,
            link: None,
            link_events: None,
            events,
            speed,
            polling: Arc::new(AtomicBool::new(false)),
            joints,
            answers: None,
        }
    }

    /// The driver's one speed cap.
    pub fn cap(&self) -> SpeedCap {
        self.scale.cap()
    }

    fn dialect(&self) -> Dialect {
        self.config.as_ref().map_or(Dialect::Icd, |c| c.dialect)
    }

    /// Whether an operator is configured but not connected.
    pub fn is_down(&self) -> bool {
        self.config.is_some() && self.link.is_none()
    }

    pub fn lost(&mut self) {
        self.link = None;
        self.link_events = None;
    }

    /// Connect, handshake and speed read, run off the loop; `None` with no operator configured.
    pub fn connect_attempt(
        &self,
    ) -> Option<impl Future<Output = Result<TalosConnected, ConnectError>> + Send + 'static> {
        let config = self.config.clone()?;
        Some(connect::connect(config, self.oid, self.scale))
    }

    /// Takes a link that connected; returns its description for the status bar.
    pub fn attach(&mut self, connected: TalosConnected) -> String {
        if let Some(speed) = connected.speed {
            self.speed.set(speed);
            let _ = self.events.send(ArmEvent::Speed(speed));
        }
        if let Some(text) = connected.speed_lowered {
            let _ = self.events.send(ArmEvent::Notice(text));
        }
        self.link = Some(connected.link);
        self.link_events = Some(connected.link_events);
        connected.description
    }

    /// The next unsolicited link event; pends forever without a link.
    pub async fn next_event(&mut self) -> Option<TalosEvent> {
        if let Some(rx) = &mut self.link_events
            && let Some(event) = rx.recv().await
        {
            return Some(event);
        }
        self.link_events = None;
        std::future::pending().await
    }

    /// Whether the Talos link carries `command` (rather than the Modbus link).
    pub fn handles(&self, command: &ArmCommand, has_modbus: bool) -> bool {
        self.config.is_some()
            && match command {
                // The Talos ICD has no orientation jog, stored run by id, pose move or frame.
                ArmCommand::Jog(JogMotion::Orientation { .. })
                | ArmCommand::MoveToPose(_)
                | ArmCommand::SetFrame(_)
                | ArmCommand::StartStored(_) => false,
                // Over Modbus the coils do it properly; over Talos only the nearest equivalent.
                ArmCommand::FaultReset => !has_modbus,
                _ => true,
            }
    }

    /// The requests that carry out `command`, in order.
    fn requests(&self, command: &ArmCommand) -> Result<Vec<Request>, ArmError> {
        let icd = self.dialect() == Dialect::Icd;
        Ok(match command {
            ArmCommand::Jog(JogMotion::Cartesian { x, y, z }) => {
                vec![Request::CartesianMoveStart {
                    moving_x: *x,
                    moving_y: *y,
                    moving_z: *z,
                }]
            }
            ArmCommand::Jog(JogMotion::Polar { azimuth, altitude }) => {
                vec![Request::PolarPanStart {
                    moving_azimuth: *azimuth,
                    moving_altitude: *altitude,
                }]
            }
            ArmCommand::Jog(JogMotion::Joint { joint, direction }) => {
                if !icd {
                    return Err(ArmError::Unsupported("joint jog needs the icd dialect"));
                }
                // The command carries the joint's last reported position: none is invented.
                let Some(positions) = *self.joints.borrow() else {
                    return Err(ArmError::NoJointPosition);
                };
                let index = usize::from(joint.saturating_sub(1)).min(6);
                // The rate keeps the tool point under the cap until the 500 ms watchdog, deg/s.
                let (speed, percent) = (self.joint_jog_speed, self.speed.percent());
                let rate =
                    self.cap()
                        .joint_rate(speed, &positions, *joint, percent, JOINT_JOG_HORIZON);
                let velocity = f32::from(*direction) * rate * self.speed.fence_share();
                let position = positions[index];
                vec![hw_request(&HwRequest::SendActuatorCommand {
                    joint: *joint,
                    command: ActuatorCommand::jog(position, velocity),
                })?]
            }
            ArmCommand::Jog(JogMotion::Orientation { .. }) => {
                return Err(ArmError::Unsupported(ORIENTATION_NEEDS_MODBUS));
            }
            ArmCommand::Stop | ArmCommand::QuickStop => stop_requests(self.dialect()),
            ArmCommand::Step(StepMove::Cartesian { dx, dy, dz }) => vec![Request::CartesianMove {
                delta_x: *dx,
                delta_y: *dy,
                delta_z: *dz,
                delay_ms: 0,
                time_ms: 0,
            }],
            ArmCommand::Step(StepMove::Polar { azimuth, altitude }) => vec![Request::PolarPan {
                delta_azimuth: *azimuth,
                delta_altitude: *altitude,
                delay_ms: 0,
                time_ms: 0,
            }],
            ArmCommand::Home => vec![Request::Home { delay_ms: 0 }],
            // The operator has one speed: the fence's share is taken from it while it holds.
            ArmCommand::SetSpeed(speed) => vec![Request::SetSpeed {
                speed: self.scale.to_operator(self.speed.fenced(*speed)),
            }],
            ArmCommand::FenceSpeed(_) => vec![Request::SetSpeed {
                speed: self
                    .scale
                    .to_operator(self.speed.fenced(self.speed.percent())),
            }],
            ArmCommand::FaultReset => vec![hw_request(&HwRequest::ClearAllFaults)?],
            ArmCommand::SavePosition {
                name,
                anchor,
                parent,
            } => vec![Request::SavePosition {
                name: name.clone(),
                anchor: *anchor,
                parent: parent.clone().unwrap_or_default(),
            }],
            ArmCommand::DeletePosition { name } => {
                vec![Request::DeletePosition { name: name.clone() }]
            }
            ArmCommand::GoToPosition { name } => vec![Request::GoToPosition { name: name.clone() }],
            ArmCommand::SetPolarPosition {
                name,
                delta,
                azimuth,
                radius,
            } => vec![Request::SetPolarPosition {
                name: name.clone(),
                delta: *delta,
                azimuth: *azimuth,
                radius: *radius,
            }],
            ArmCommand::SetCartesianPosition { name, x, y, z } => {
                vec![Request::SetCartesianPosition {
                    name: name.clone(),
                    x: *x,
                    y: *y,
                    z: *z,
                }]
            }
            ArmCommand::GetPosition { name } => vec![
                Request::GetCartesianPosition { name: name.clone() },
                Request::GetPolarPosition { name: name.clone() },
            ],
            ArmCommand::MoveToPose(_) | ArmCommand::SetFrame(_) => {
                return Err(ArmError::Unsupported("not available over Talos"));
            }
            ArmCommand::StartStored(_) => return Err(ArmError::Unsupported(STORED_NEEDS_MODBUS)),
        })
    }

    /// Submits the command's requests in order; never waits (a full queue ends the link).
    pub fn command(&mut self, command: ArmCommand) {
        // Borrowed, not cloned: a clone of the link copies its address, on every key's path.
        let Some(link) = &self.link else {
            if !command.is_stop() {
                let _ = self
                    .events
                    .send(ArmEvent::failed(&command, ArmError::NoTalosLink));
            }
            return;
        };
        let requests = match self.requests(&command) {
            Ok(requests) => requests,
            Err(error) => {
                let _ = self.events.send(ArmEvent::failed(&command, error));
                return;
            }
        };
        let mut pending = Vec::new();
        // A stop reports one outcome, whichever of its requests failed (see `answers`).
        let mut stop_failure = None;
        for request in requests {
            let name = request.command();
            match link.submit(request) {
                Ok(p) => pending.push(p),
                Err(e) if command.is_stop() => {
                    log_error(&self.events, &command, name, None, &e);
                    stop_failure.get_or_insert_with(|| failure_reason(e));
                }
                Err(e) => report_error(&self.events, &command, name, None, e),
            }
        }
        // A command that came in the same turn as the last one spawns that one's answers now.
        self.spawn_answers_now();
        self.answers = Some(Submitted {
            command,
            pending,
            stop_failure,
        });
    }

    fn spawn_answers_now(&mut self) {
        if let Some(s) = self.answers.take() {
            let (events, speed) = (self.events.clone(), self.speed.clone());
            tokio::spawn(answers(s.command, s.pending, s.stop_failure, events, speed));
        }
    }

    /// Spawns the last command's answers after the link task wrote its frames if `after_the_write`,
    /// so the spawn's allocation does not delay the frame. In a flood they are spawned at once, so
    /// the link's events still get in.
    pub async fn spawn_answers(&mut self, after_the_write: bool) {
        if self.answers.is_some() {
            if after_the_write {
                after_tasks_woken().await;
            }
            self.spawn_answers_now();
        }
    }

    /// Asks for arm state and actuator feedback unless the last poll is outstanding; never waits.
    pub fn poll_telemetry(&mut self) {
        let Some(link) = self.link.clone() else {
            return;
        };
        let polls = [
            HwRequest::GetArmState,
            HwRequest::GetActuatorFeedback { selector: 0 },
        ]
        .map(|r| hw_request(&r));
        let [state, feedback] = match polls {
            [Ok(state), Ok(feedback)] => [state, feedback],
            [Err(e), _] | [_, Err(e)] => {
                tracing::error!("talos telemetry poll not sent: {e}");
                let name = CommandValue::ExecuteHardwareOperation.name();
                let entry = LogEntry::new(name, e.to_string());
                let _ = self.events.send(ArmEvent::Log(LogEntry {
                    poll: true,
                    ..entry
                }));
                return;
            }
        };
        if self.polling.swap(true, Ordering::AcqRel) {
            return;
        }
        let state = link.submit(state);
        let feedback = link.submit(feedback);
        let events = self.events.clone();
        let polling = self.polling.clone();
        let joints = self.joints.clone();
        tokio::spawn(async move {
            if let (Ok(state), Ok(feedback)) = (state, feedback)
                && let (Ok(state), Ok(feedback)) = (state.wait().await, feedback.wait().await)
            {
                for exchange in [&state, &feedback] {
                    let entry = LogEntry {
                        poll: true,
                        ..log_entry(exchange)
                    };
                    let _ = events.send(ArmEvent::Log(entry));
                }
                if let (
                    Some(HwReply::GetArmState { state: arm }),
                    Some(HwReply::GetActuatorFeedback { actuators }),
                ) = (hw_reply(&state), hw_reply(&feedback))
                {
                    let telemetry = hw_telemetry::telemetry(&arm, &actuators);
                    // Only a full set: a joint jog never carries a position not reported.
                    if actuators.len() == 7 {
                        joints.send_replace(Some(telemetry.joints.map(|j| j.position)));
                    }
                    let _ = events.send(ArmEvent::Telemetry(Box::new(telemetry)));
                    let _ = events.send(ArmEvent::Latency(state.latency));
                }
            }
            polling.store(false, Ordering::Release);
        });
    }

    /// On the way out: sends the stop set and waits (up to 500 ms) for its answers. The link stays
    /// up (the exit sends it twice); [`TalosSide::close`] drops it.
    pub async fn stop_and_wait(&self) {
        let Some(link) = &self.link else {
            return;
        };
        let mut answers = Vec::new();
        for stop in stop_requests(self.dialect()) {
            let name = stop.command();
            match link.submit(stop) {
                Ok(pending) => answers.push(pending.wait()),
                Err(e) => tracing::warn!("talos: {name} on the way out: {e}"),
            }
        }
        let answered = futures::future::join_all(answers);
        if let Ok(results) = tokio::time::timeout(FLUSH_WAIT, answered).await {
            for error in results.into_iter().filter_map(Result::err) {
                tracing::warn!("talos: a stop on the way out: {error}");
            }
        } else {
            tracing::warn!("talos: the stops on the way out not answered within {FLUSH_WAIT:?}");
        }
    }

    /// Drops the link: its task ends once it has written what it was given.
    pub fn close(&mut self) {
        self.link = None;
    }
}

/// How long the driver's exit waits for the operator to answer its stops.
const FLUSH_WAIT: Duration = Duration::from_millis(500);

/// A hardware operation as its request; a refused field is an error, never an empty payload.
fn hw_request(request: &HwRequest) -> Result<Request, ArmError> {
    request.to_request().map_err(ArmError::Encode)
}

/// Comes back after the tasks already woken on this thread (the link task) have run. Unlike tokio's
/// `yield_now` it does not poll the reactor, a syscall per key.
async fn after_tasks_woken() {
    let mut woken = false;
    std::future::poll_fn(|cx| {
        if woken {
            return std::task::Poll::Ready(());
        }
        woken = true;
        cx.waker().wake_by_ref();
        std::task::Poll::Pending
    })
    .await
}
