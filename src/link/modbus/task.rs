//! The task that owns the connection (rules: parent module).

mod jog;
mod limits;
mod other_client;
mod reconnect;

use std::time::Duration;

use tokio::sync::{mpsc, watch};
use tokio::time::{Instant, MissedTickBehavior};
use tokio_modbus::client::{Client, Context};

use super::{
    ExceptionCode, Job, ModbusConfig, ModbusError, ModbusEvent, Reply, Snapshot, StopReason,
    WriteReport, wire,
};
use crate::kortex::commands::{self, Write};
use crate::kortex::{
    ControlCoil, PolarPanSettings, PollPlan, ReferenceFrame, RegisterImage, SLOW_REFRESH,
    Telemetry, Twist,
};

/// Reconnects tried, once the link is closing, to write a stop that is still owed.
const CLOSING_ATTEMPTS: u32 = 5;

/// The motion this link keeps running on the arm.
#[derive(Debug, Clone, Copy, PartialEq)]
enum MotionInForce {
    Idle,
    Twist {
        frame: ReferenceFrame,
        twist: Twist,
    },
    /// A polar pan at `settings`, with the base-frame twist last written for it.
    Polar {
        azimuth: f32,
        altitude: f32,
        settings: PolarPanSettings,
        twist: Twist,
    },
}

impl MotionInForce {
    /// The same motion asked for: a polar pan by its directions and settings, not its last twist.
    fn same_ask(&self, other: &MotionInForce) -> bool {
        use MotionInForce::Polar;
        match (self, other) {
            (
                Polar {
                    azimuth,
                    altitude,
                    settings,
                    ..
                },
                Polar {
                    azimuth: a,
                    altitude: e,
                    settings: s,
                    ..
                },
            ) => (azimuth, altitude, settings) == (a, e, s),
            _ => self == other,
        }
    }
}

/// What woke the task.
enum Wake {
    Job(Option<Job>),
    HoldExpired,
    Tick,
}

pub(super) struct LinkTask {
    config: ModbusConfig,
    /// Opens each new connection after a loss.
    connector: wire::Connector,
    jobs: mpsc::Receiver<Job>,
    jobs_closed: bool,
    snapshots: watch::Sender<Option<Snapshot>>,
    events: mpsc::UnboundedSender<ModbusEvent>,
    /// `None` while disconnected, or once a request broke the connection.
    ctx: Option<Context>,
    lost_reason: String,
    plan: PollPlan,
    /// When the plan's slow blocks were last read on this connection.
    slow_read_at: Option<Instant>,
    image: RegisterImage,
    sequence: u64,
    motion: MotionInForce,
    hold_until: Option<Instant>,
    /// A twist may be running on the arm: set before any twist write, cleared by a stop.
    stop_owed: bool,
    closing: bool,
    /// The arm's speed limits as they were before a capped move lowered them: owed back.
    limit_hold: Option<limits::LimitHold>,
    /// Reconnects tried since closing began, to deliver an owed stop.
    closing_attempts: u32,
    close_replies: Vec<Reply<()>>,
    /// Our twist's write, until the arm is seen to run it (see `elsewhere`).
    twist_start: Option<other_client::TwistStart>,
    /// The motion another client stopped or replaced: asked again, it is not restarted.
    ended_by_other_client: Option<MotionInForce>,
}

/// Which of a strict arm's blocks a snapshot reads (see [`PollPlan::is_slow`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum PollScope {
    /// The slow blocks only once [`SLOW_REFRESH`] has passed since they were last read.
    Due,
    /// Every block: for a decision that rests on a slow one (the arm's speed limits).
    Everything,
}

impl LinkTask {
    pub(super) fn new(
        config: ModbusConfig,
        connector: wire::Connector,
        jobs: mpsc::Receiver<Job>,
        snapshots: watch::Sender<Option<Snapshot>>,
        events: mpsc::UnboundedSender<ModbusEvent>,
    ) -> LinkTask {
        LinkTask {
            plan: config.plan,
            slow_read_at: None,
            config,
            connector,
            jobs,
            jobs_closed: false,
            snapshots,
            events,
            ctx: None,
            lost_reason: String::new(),
            image: RegisterImage::default(),
            sequence: 0,
            motion: MotionInForce::Idle,
            hold_until: None,
            stop_owed: false,
            closing: false,
            limit_hold: None,
            closing_attempts: 0,
            close_replies: Vec::new(),
            twist_start: None,
            ended_by_other_client: None,
        }
    }

    pub(super) async fn run(mut self, context: Context) {
        self.ctx = Some(context);
        self.slow_read_at = None;
        loop {
            if self.ctx.is_none() && !self.reconnect().await {
                return;
            }
            if self.serve().await {
                return;
            }
            let reason = std::mem::take(&mut self.lost_reason);
            tracing::warn!("modbus link to {} lost: {reason}", self.config.addr);
            self.motion = MotionInForce::Idle;
            self.hold_until = None;
            self.event(ModbusEvent::Disconnected { reason });
        }
    }

    /// Serves one connection: true when the task is done, false when the connection was lost.
    async fn serve(&mut self) -> bool {
        if self.stop_owed {
            // After a reconnect: whatever was running before the loss must not go on.
            let _ = self.stop(StopReason::Reconnected).await;
        }
        let period = self
            .config
            .poll_rate_hz
            .and_then(|hz| Duration::try_from_secs_f64(1.0 / hz).ok());
        let mut ticker = tokio::time::interval(period.unwrap_or(Duration::from_secs(3600)));
        ticker.set_missed_tick_behavior(MissedTickBehavior::Delay);
        loop {
            if self.ctx.is_none() {
                return false;
            }
            if self.closing {
                return self.shut_down().await;
            }
            let hold = self.hold_until;
            let wake = tokio::select! {
                biased;
                job = self.jobs.recv(), if !self.jobs_closed => Wake::Job(job),
                _ = tokio::time::sleep_until(hold.unwrap_or_else(Instant::now)), if hold.is_some() => {
                    Wake::HoldExpired
                }
                _ = ticker.tick(), if period.is_some() => Wake::Tick,
            };
            match wake {
                Wake::Job(Some(job)) => self.handle(job).await,
                Wake::Job(None) => {
                    self.jobs_closed = true;
                    self.closing = true;
                }
                Wake::HoldExpired => {
                    let _ = self.stop(StopReason::HoldExpired).await;
                }
                Wake::Tick => self.tick().await,
            }
        }
    }

    /// Writes the owed stop, answers `close`, disconnects; false if the stop broke the connection.
    async fn shut_down(&mut self) -> bool {
        // A capped move must not run on at the limits put back: it is stopped first.
        let result = if self.stop_owed || self.limit_hold.is_some() {
            self.stop(StopReason::LinkClosed).await.map(|_| ())
        } else {
            Ok(())
        };
        if self.ctx.is_none() && self.stop_owed {
            return false;
        }
        self.answer_close(result);
        if let Some(mut ctx) = self.ctx.take() {
            let _ = ctx.disconnect().await;
        }
        true
    }

    fn answer_close(&mut self, result: Result<(), ModbusError>) {
        let mut result = Some(result);
        for reply in self.close_replies.drain(..) {
            let outcome = result.take().unwrap_or_else(|| {
                Err(ModbusError::Disconnected {
                    reason: "closed by another caller".into(),
                })
            });
            let _ = reply.send(outcome);
        }
    }

    async fn handle(&mut self, job: Job) {
        match job {
            Job::Read(reply) => _ = reply.send(self.poll_or_stop().await),
            Job::Twist {
                frame,
                twist,
                reply,
            } => _ = reply.send(self.jog_twist(frame, twist).await),
            Job::PolarPan {
                azimuth,
                altitude,
                settings,
                reply,
            } => _ = reply.send(self.polar_pan(azimuth, altitude, settings).await),
            Job::Stop(reply) => _ = reply.send(self.stop(StopReason::Requested).await),
            Job::Move { writes, cap, reply } => {
                let mut result = Ok(WriteReport::default());
                if self.stop_owed {
                    result = self.stop(StopReason::Replaced).await;
                }
                if result.is_ok() {
                    result = match cap {
                        Some(cap) => self.capped_move(&writes, cap).await,
                        None => self.execute(&writes).await,
                    };
                }
                let _ = reply.send(result);
            }
            Job::Plain {
                writes,
                halts,
                reply,
            } => {
                let result = self.execute_read_back(&writes).await;
                if halts && result.is_ok() {
                    self.motion = MotionInForce::Idle;
                    self.hold_until = None;
                    self.stop_owed = false;
                    self.restore_limits().await;
                }
                let _ = reply.send(result);
            }
            Job::Close(reply) => {
                self.close_replies.push(reply);
                self.closing = true;
            }
        }
    }

    /// Writes a twist; if that fails the twist is stopped (now, or after the reconnect).
    async fn write_motion(&mut self, writes: &[Write]) -> Result<WriteReport, ModbusError> {
        self.stop_owed = true;
        let result = self.execute(writes).await;
        if result.is_ok() {
            // A rewrite of the running twist (a new direction, a pan's new pose) keeps its start.
            self.twist_start
                .get_or_insert_with(other_client::TwistStart::now);
            self.ended_by_other_client = None;
        } else if self.ctx.is_some() {
            let _ = self.stop(StopReason::WriteFailed).await;
        } else {
            self.motion = MotionInForce::Idle;
            self.hold_until = None;
        }
        result
    }

    /// The stop sequence (200 <- 2), else the abort coil; failures logged and sent as events.
    async fn stop(&mut self, reason: StopReason) -> Result<WriteReport, ModbusError> {
        self.motion = MotionInForce::Idle;
        self.hold_until = None;
        self.twist_start = None;
        self.ended_by_other_client = None;
        let stop_error = match self.execute(&commands::stop()).await {
            Ok(report) => {
                self.stop_owed = false;
                tracing::info!("twist stopped ({reason:?})");
                self.event(ModbusEvent::Stopped { reason });
                self.restore_after_stop(reason).await;
                return Ok(report);
            }
            Err(e) if self.ctx.is_none() => {
                self.stop_failed(reason, &e);
                return Err(e);
            }
            Err(e) => e,
        };
        tracing::error!("the arm refused the stop ({stop_error}); pulsing the abort coil");
        match self.execute(&commands::pulse(ControlCoil::Abort)).await {
            Ok(mut report) => {
                self.stop_owed = false;
                report.writes.splice(0..0, commands::stop());
                self.event(ModbusEvent::StopEscalated {
                    reason,
                    error: stop_error.to_string(),
                });
                self.restore_after_stop(reason).await;
                Ok(report)
            }
            Err(abort) => {
                let e = ModbusError::StopFailed {
                    stop: Box::new(stop_error),
                    abort: Box::new(abort),
                };
                self.stop_failed(reason, &e);
                Err(e)
            }
        }
    }

    fn stop_failed(&mut self, reason: StopReason, error: &ModbusError) {
        let retry = match self.ctx {
            None => "; retrying after the reconnect",
            Some(_) => "",
        };
        tracing::error!(
            "STOP NOT WRITTEN ({reason:?}): {error}{retry}. The arm may still be moving: use its e-stop"
        );
        self.event(ModbusEvent::StopFailed {
            reason,
            error: error.to_string(),
        });
    }

    /// A poll failed: a moving arm we cannot see is stopped.
    async fn stop_after_failed_poll(&mut self) {
        if self.motion != MotionInForce::Idle && self.ctx.is_some() {
            let _ = self.stop(StopReason::PollFailed).await;
        }
    }

    /// A poll asked for: if it fails, a moving arm we cannot see is stopped.
    pub(super) async fn poll_or_stop(&mut self) -> Result<Telemetry, ModbusError> {
        let result = self.poll().await;
        if result.is_err() {
            self.stop_after_failed_poll().await;
        }
        result
    }

    async fn tick(&mut self) {
        match self.poll().await {
            Ok(telemetry) => {
                self.note_motion_ended_by_other_client(&telemetry);
                self.refresh_polar(telemetry.tcp.pose).await;
                self.note_action(&telemetry).await;
            }
            Err(e) => {
                tracing::debug!("poll failed: {e}");
                self.event(ModbusEvent::PollFailed {
                    error: e.to_string(),
                });
                self.stop_after_failed_poll().await;
            }
        }
    }

    /// Reads one complete snapshot (the slow blocks when due) and publishes it.
    async fn poll(&mut self) -> Result<Telemetry, ModbusError> {
        self.poll_scoped(PollScope::Due).await
    }

    /// Reads and publishes one snapshot (the ICD's blocks if compact reads are refused).
    async fn poll_scoped(&mut self, scope: PollScope) -> Result<Telemetry, ModbusError> {
        let started = Instant::now();
        let mut with_slow = scope == PollScope::Everything
            || self
                .slow_read_at
                .is_none_or(|at| started.saturating_duration_since(at) >= SLOW_REFRESH);
        let mut index = 0;
        while let Some(block) = self.plan.blocks().get(index).copied() {
            if !with_slow && self.plan.is_slow(block) {
                index += 1;
                continue;
            }
            let Some(ctx) = self.ctx.as_mut() else {
                return Err(self.not_connected());
            };
            match wire::read(ctx, block, &mut self.image, self.config.request_timeout).await {
                Ok(()) => index += 1,
                Err(e)
                    if self.plan == PollPlan::Compact
                        && e.exception() == Some(ExceptionCode::IllegalDataAddress) =>
                {
                    // Expected of a strict arm, not a fault: said once, at info.
                    tracing::info!(
                        "{e}; this arm refuses reads over unlisted addresses: reading the ICD's \
                         blocks one by one from now on"
                    );
                    self.plan = PollPlan::IcdBlocks;
                    self.event(ModbusEvent::PlanFallback { plan: self.plan });
                    index = 0;
                    with_slow = true;
                }
                Err(e) => {
                    self.note_broken(&e);
                    return Err(e);
                }
            }
        }
        if with_slow {
            self.slow_read_at = Some(started);
        }
        let telemetry = Telemetry::decode(&self.image);
        self.sequence += 1;
        self.snapshots.send_replace(Some(Snapshot {
            telemetry: telemetry.clone(),
            sequence: self.sequence,
            completed_at: std::time::Instant::now(),
            poll_time: started.elapsed(),
        }));
        Ok(telemetry)
    }

    /// Writes what a slow block may show (speed limits above all); the next snapshot reads it back.
    /// Jog and move writes use [`LinkTask::execute`].
    async fn execute_read_back(&mut self, writes: &[Write]) -> Result<WriteReport, ModbusError> {
        let written = self.execute(writes).await;
        self.slow_read_at = None;
        written
    }

    /// Sends writes in order, stopping at the first failure.
    async fn execute(&mut self, writes: &[Write]) -> Result<WriteReport, ModbusError> {
        let started = Instant::now();
        for write in writes {
            let Some(ctx) = self.ctx.as_mut() else {
                return Err(self.not_connected());
            };
            if let Err(e) = wire::write(ctx, write, self.config.request_timeout).await {
                self.note_broken(&e);
                return Err(e);
            }
        }
        Ok(WriteReport {
            writes: writes.to_vec(),
            elapsed: started.elapsed(),
        })
    }

    /// Drops a connection that can no longer be trusted.
    fn note_broken(&mut self, error: &ModbusError) {
        if error.breaks_connection() {
            self.ctx = None;
            self.lost_reason = error.to_string();
        }
    }

    fn not_connected(&self) -> ModbusError {
        let reason = match self.lost_reason.as_str() {
            "" => "reconnecting".into(),
            lost => format!("reconnecting after: {lost}"),
        };
        ModbusError::Disconnected { reason }
    }

    fn event(&self, event: ModbusEvent) {
        tracing::debug!("modbus event: {event:?}");
        let _ = self.events.send(event);
    }
}
