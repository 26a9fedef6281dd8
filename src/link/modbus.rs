//! Async client for a Kinova Kortex arm over Modbus TCP (`shared/icd/kinova-modbus-icd.md`). One
//! task owns the connection: it polls telemetry into a `watch` channel and runs commands between
//! polls, one request at a time.
//!
//! Safety: the arm has no twist watchdog, so the link writes the stop sequence when every handle is
//! gone, when a jog is not refreshed within [`ModbusConfig::twist_hold`], when a write or poll
//! fails, and after a reconnect; a refused stop escalates to the abort coil. A capped move (one
//! given a `cap`) is stopped on close and the arm's limits put back (`task/limits.rs`). Await
//! [`ModbusLink::close`] before leaving the runtime: a cancelled task writes nothing.

mod error;
mod task;
mod wire;

pub use error::{ExceptionCode, ModbusError, Operation};

use std::fmt;
use std::time::{Duration, Instant};

use tokio::sync::{mpsc, oneshot, watch};

use crate::kortex::commands::{self, StoredMotion, Write};
use crate::kortex::{
    ControlCoil, PolarPanSettings, PollPlan, Pose, ReferenceFrame, SpeedLimits, Stored, Telemetry,
    Twist,
};
use crate::link::failure::Shared;
use crate::net::ConnectError;

/// Modbus TCP port of the arm.
pub const DEFAULT_PORT: u16 = 502;
/// Unit id used unless told otherwise (the ICD leaves it undocumented).
pub const DEFAULT_UNIT: u8 = 1;
/// armjog's default id of the Home action. Ids are per arm: look yours up in the Kortex Web App.
pub const DEFAULT_HOME_ACTION_ID: u16 = 2;

/// Where and how to reach an arm.
#[derive(Debug, Clone)]
pub struct ModbusConfig {
    /// HOST:PORT.
    pub addr: String,
    pub unit: u8,
    /// Polls per second; `None` polls only when asked (`read_telemetry`): no polar pan then.
    pub poll_rate_hz: Option<f64>,
    pub request_timeout: Duration,
    pub connect_timeout: Duration,
    /// First reconnect delay, doubled after each failed attempt up to `reconnect_max_delay`.
    pub reconnect_delay: Duration,
    pub reconnect_max_delay: Duration,
    /// An unrefreshed twist or pan is stopped after this (the arm has no watchdog); `None`: never.
    pub twist_hold: Option<Duration>,
    pub polar: PolarPanSettings,
    pub plan: PollPlan,
    pub home_action_id: u16,
}

impl ModbusConfig {
    pub fn new(addr: impl Into<String>) -> Self {
        ModbusConfig {
            addr: addr.into(),
            unit: DEFAULT_UNIT,
            poll_rate_hz: Some(30.0),
            request_timeout: Duration::from_millis(500),
            connect_timeout: Duration::from_secs(2),
            reconnect_delay: Duration::from_millis(100),
            reconnect_max_delay: Duration::from_secs(2),
            twist_hold: Some(Duration::from_millis(500)),
            polar: PolarPanSettings::default(),
            plan: PollPlan::Compact,
            home_action_id: DEFAULT_HOME_ACTION_ID,
        }
    }

    /// Home over Modbus: the stored action of the home id.
    pub fn home_action(&self) -> Stored {
        Stored {
            motion: StoredMotion::Action,
            id: self.home_action_id,
        }
    }
}

/// Why the link stopped a motion by itself.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StopReason {
    /// A caller asked for it (`stop`, or a zero twist / zero polar pan).
    Requested,
    /// The jog was not refreshed within `twist_hold`.
    HoldExpired,
    /// A motion write failed.
    WriteFailed,
    /// A poll failed while the arm moved.
    PollFailed,
    /// The connection was lost while a twist could have been running.
    Reconnected,
    /// Every handle of the link was dropped or closed.
    LinkClosed,
    /// A polar pan could not be computed from the live pose.
    PolarPanUndefined,
    /// A cartesian trajectory or action replaces the twist.
    Replaced,
}

/// Things the link did or noticed on its own.
#[derive(Debug, Clone, PartialEq)]
pub enum ModbusEvent {
    /// The connection was lost; the link is reconnecting.
    Disconnected { reason: String },
    /// The connection is back after `attempts` tries.
    Reconnected { attempts: u32 },
    /// A background poll failed.
    PollFailed { error: String },
    /// The arm refused a read spanning unlisted addresses: polls now read the ICD's blocks.
    PlanFallback { plan: PollPlan },
    /// The link stopped a motion.
    Stopped { reason: StopReason },
    /// The arm refused the stop and the abort coil was written instead.
    StopEscalated { reason: StopReason, error: String },
    /// No stop could be written: the arm may still be moving.
    StopFailed { reason: StopReason, error: String },
    /// The speed limits were lowered to `limits` for a capped move; `previous` go back after it.
    SpeedLimitsLowered {
        limits: SpeedLimits,
        previous: SpeedLimits,
    },
    /// The speed limits a capped move lowered are back to `limits`.
    SpeedLimitsRestored { limits: SpeedLimits },
    /// A capped move's lowered limits could not be put back: they stay until set again.
    SpeedLimitsNotRestored {
        limits: SpeedLimits,
        error: Shared<ModbusError>,
    },
}

/// One published poll.
#[derive(Debug, Clone)]
pub struct Snapshot {
    pub telemetry: Telemetry,
    /// Counts polls of this link from 1.
    pub sequence: u64,
    pub completed_at: Instant,
    /// How long the poll's reads took.
    pub poll_time: Duration,
}

/// The writes a command made, in order, and their time; a jog refresh makes none.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct WriteReport {
    pub writes: Vec<Write>,
    pub elapsed: Duration,
}

type Reply<T> = oneshot::Sender<Result<T, ModbusError>>;

/// What a caller asks the task for.
enum Job {
    Read(Reply<Telemetry>),
    Twist {
        frame: ReferenceFrame,
        twist: Twist,
        reply: Reply<WriteReport>,
    },
    PolarPan {
        azimuth: f32,
        altitude: f32,
        settings: PolarPanSettings,
        reply: Reply<WriteReport>,
    },
    Stop(Reply<WriteReport>),
    /// A trajectory or stored motion, any twist stopped first; `cap` lowers the limits for it.
    Move {
        writes: Vec<Write>,
        cap: Option<SpeedLimits>,
        reply: Reply<WriteReport>,
    },
    /// Writes that leave motion alone (limits, fault reset), or end it (`halts`).
    Plain {
        writes: Vec<Write>,
        halts: bool,
        reply: Reply<WriteReport>,
    },
    Close(Reply<()>),
}

/// A connected arm. Cheap to clone; the task ends, stopping any twist, when every clone is gone.
#[derive(Clone)]
pub struct ModbusLink {
    jobs: mpsc::Sender<Job>,
    snapshots: watch::Receiver<Option<Snapshot>>,
    config: ModbusConfig,
}

impl fmt::Debug for ModbusLink {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("ModbusLink")
            .field("addr", &self.config.addr)
            .field("unit", &self.config.unit)
            .finish()
    }
}

impl ModbusLink {
    /// Connects within the connect timeout and starts the task, which reconnects on its own.
    pub async fn connect(
        config: ModbusConfig,
    ) -> Result<(ModbusLink, mpsc::UnboundedReceiver<ModbusEvent>), ModbusError> {
        let connector = wire::tcp_connector(&config);
        Self::start(config, connector).await
    }

    /// As [`connect`](Self::connect), each connection from `open` (in-memory in tests).
    pub async fn connect_via<F, Fut, T>(
        config: ModbusConfig,
        open: F,
    ) -> Result<(ModbusLink, mpsc::UnboundedReceiver<ModbusEvent>), ModbusError>
    where
        F: Fn() -> Fut + Send + Sync + 'static,
        Fut: std::future::Future<Output = std::io::Result<T>> + Send + 'static,
        T: tokio::io::AsyncRead + tokio::io::AsyncWrite + Send + Unpin + fmt::Debug + 'static,
    {
        let open = std::sync::Arc::new(open);
        let for_connector = config.clone();
        let connector: wire::Connector = std::sync::Arc::new(move || {
            let (open, config) = (open.clone(), for_connector.clone());
            Box::pin(async move {
                match open().await {
                    Ok(transport) => Ok(wire::attach(transport, &config)),
                    Err(source) => Err(ModbusError::Connect(ConnectError::Refused {
                        addr: config.addr.clone(),
                        source,
                    })),
                }
            })
        });
        Self::start(config, connector).await
    }

    async fn start(
        config: ModbusConfig,
        connector: wire::Connector,
    ) -> Result<(ModbusLink, mpsc::UnboundedReceiver<ModbusEvent>), ModbusError> {
        if let Some(hz) = config.poll_rate_hz
            && !(hz.is_finite() && hz > 0.0 && hz <= 1000.0)
        {
            return Err(ModbusError::BadConfig {
                reason: format!("poll rate {hz} Hz is outside (0, 1000]"),
            });
        }
        let context = connector().await?;
        let (jobs_tx, jobs_rx) = mpsc::channel(64);
        let (events_tx, events_rx) = mpsc::unbounded_channel();
        let (snapshots_tx, snapshots_rx) = watch::channel(None);
        let task = task::LinkTask::new(config.clone(), connector, jobs_rx, snapshots_tx, events_tx);
        tokio::spawn(task.run(context));
        let link = ModbusLink {
            jobs: jobs_tx,
            snapshots: snapshots_rx,
            config,
        };
        Ok((link, events_rx))
    }

    pub fn config(&self) -> &ModbusConfig {
        &self.config
    }

    /// The latest published snapshot, updated after every background poll.
    pub fn subscribe(&self) -> watch::Receiver<Option<Snapshot>> {
        self.snapshots.clone()
    }

    /// Polls the complete telemetry now (also published to subscribers).
    pub async fn read_telemetry(&self) -> Result<Telemetry, ModbusError> {
        self.ask(Job::Read).await
    }

    /// Starts or updates a twist (m/s, deg/s); the same only refreshes, zero stops.
    pub async fn jog_twist(
        &self,
        frame: ReferenceFrame,
        twist: Twist,
    ) -> Result<WriteReport, ModbusError> {
        commands::check_twist(twist)?;
        self.ask(|reply| Job::Twist {
            frame,
            twist,
            reply,
        })
        .await
    }

    /// Starts or updates a polar pan at `settings` (the console's speed), directions in -1..1
    /// ([`crate::kortex::polar`]); the twist is recomputed from every poll's pose. The same
    /// directions and settings only refresh the hold; other settings restart it; zero stops.
    pub async fn polar_pan_with(
        &self,
        azimuth: f32,
        altitude: f32,
        settings: PolarPanSettings,
    ) -> Result<WriteReport, ModbusError> {
        crate::kortex::check_directions(azimuth, altitude, settings)?;
        if self.config.poll_rate_hz.is_none() {
            return Err(ModbusError::NoPolling);
        }
        self.ask(|reply| Job::PolarPan {
            azimuth,
            altitude,
            settings,
            reply,
        })
        .await
    }

    /// Stops any motion (holding register 200 <- 2), the abort coil if the arm refuses.
    pub async fn stop(&self) -> Result<WriteReport, ModbusError> {
        self.ask(Job::Stop).await
    }

    /// Moves the tool to `pose` (m, deg) in `frame` as a cartesian trajectory, with the arm's
    /// limits lowered to `cap` (m/s, deg/s) for the move if one is given.
    pub async fn go_to_pose(
        &self,
        frame: ReferenceFrame,
        pose: Pose,
        cap: Option<SpeedLimits>,
    ) -> Result<WriteReport, ModbusError> {
        self.run_move(commands::go_to_pose(frame, pose)?, cap).await
    }

    /// A stored action or sequence (home among them: [`ModbusConfig::home_action`]), under `cap`
    /// if one is given (whether it honours the limits is the arm's).
    pub async fn start_stored(
        &self,
        stored: Stored,
        cap: Option<SpeedLimits>,
    ) -> Result<WriteReport, ModbusError> {
        self.run_move(commands::start_stored(stored.id, stored.motion)?, cap)
            .await
    }

    /// Sets the desired cartesian speed limits: linear m/s, angular deg/s.
    pub async fn set_speed_limits(
        &self,
        linear: f32,
        angular: f32,
    ) -> Result<WriteReport, ModbusError> {
        let writes = commands::speed_limits(linear, angular)?;
        self.plain(writes, false).await
    }

    /// Pulses a control coil: quick stop (0), abort / manual stop (1), both ending any motion, or
    /// fault reset (2; after a quick stop the arm may need more than one).
    pub async fn pulse(&self, coil: ControlCoil) -> Result<WriteReport, ModbusError> {
        let halts = coil != ControlCoil::FaultReset;
        self.plain(commands::pulse(coil), halts).await
    }

    /// Stops any twist and ends the task; unlike a drop, says if the stop failed.
    pub async fn close(self) -> Result<(), ModbusError> {
        self.ask(Job::Close).await
    }

    /// A move's writes, with the arm's speed limits lowered to `cap` (checked first) while it
    /// runs.
    async fn run_move(
        &self,
        writes: Vec<Write>,
        cap: Option<SpeedLimits>,
    ) -> Result<WriteReport, ModbusError> {
        if let Some(cap) = cap {
            commands::speed_limits(cap.linear, cap.angular)?;
        }
        self.ask(|reply| Job::Move { writes, cap, reply }).await
    }

    async fn plain(&self, writes: Vec<Write>, halts: bool) -> Result<WriteReport, ModbusError> {
        self.ask(|reply| Job::Plain {
            writes,
            halts,
            reply,
        })
        .await
    }

    async fn ask<T>(&self, job: impl FnOnce(Reply<T>) -> Job) -> Result<T, ModbusError> {
        let gone = || ModbusError::Disconnected {
            reason: "the link task has ended".into(),
        };
        let (reply, answer) = oneshot::channel();
        self.jobs.send(job(reply)).await.map_err(|_| gone())?;
        answer.await.map_err(|_| gone())?
    }
}
