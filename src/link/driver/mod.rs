//! The arm driver: one task that carries the console's [`ArmCommand`]s to a Talos operator, a
//! Modbus arm or both, and reports [`ArmEvent`]s.
//!
//! Order is kept, and a STOP never waits: Talos replies are awaited apart from submission, Modbus
//! commands run in a worker that drops refreshes a later STOP makes stale, and the loop awaits
//! nothing a peer controls (a full queue or a write stalled 500 ms ends that link). A STOP goes to
//! every link; over Talos it is the one stop set ([`crate::talos::stop_requests`]). After a link
//! drops nothing moves until the technician presses a key.

mod connect;
mod event_loop;
pub mod hw_telemetry;
mod links;
mod modbus_worker;
mod speed;
// The cap's facts the driver's callers set or check it by (`link::speed` is their home).
pub use super::speed::{INITIAL_SPEED, JOINT_JOG_SPEED, tool_speed_at};
pub use talos_side::{ORIENTATION_NEEDS_MODBUS, STORED_NEEDS_MODBUS};
mod stop_outcome;
mod talos_side;

use std::time::Duration;

use tokio::sync::mpsc;

use super::Dialect;
use super::guard::GuardPolicy;
use super::interface::{ArmCommand, ArmEvent, TelemetrySource};
use super::modbus::ModbusConfig;
use super::speed::{OPERATOR_FULL_SPEED, OperatorScale, SpeedCap, SpeedCapError};
use super::talos::TalosConfig;
use crate::kortex::Stored;

/// The latest joint positions (deg): a joint jog carries its joint's, so none goes before one.
pub(crate) type JointPositions = std::sync::Arc<tokio::sync::watch::Sender<Option<[f32; 7]>>>;

/// What the driver connects to and how it jogs.
#[derive(Debug, Clone)]
pub struct DriverConfig {
    pub talos: Option<TalosConfig>,
    pub modbus: Option<ModbusConfig>,
    /// The tool speed cap at 100 %, m/s (default 0.25); the speed in force is a percentage of it.
    pub max_jog_speed: f64,
    /// The operator's speed at its 100 %, m/s ([`OperatorScale`]).
    pub operator_full_speed: f64,
    /// Single-joint jog speed at 100 %, deg/s.
    pub joint_jog_speed: f32,
    /// Hardware-operation telemetry polls per second on a Talos-only link.
    pub hw_telemetry_hz: f64,
    /// Handshake OID.
    pub oid: u16,
    /// The stop guard for the links (none by default; the console starts one for a real arm).
    pub guard: GuardPolicy,
}

impl DriverConfig {
    pub fn new(talos: Option<TalosConfig>, modbus: Option<ModbusConfig>) -> DriverConfig {
        DriverConfig {
            talos,
            modbus,
            max_jog_speed: 0.25,
            operator_full_speed: OPERATOR_FULL_SPEED,
            joint_jog_speed: JOINT_JOG_SPEED,
            hw_telemetry_hz: 10.0,
            oid: 0,
            guard: GuardPolicy::NotNeeded,
        }
    }

    /// The cap on the operator ([`SpeedCap::with_operator`]) both sides keep to.
    pub fn speed_cap(&self) -> Result<OperatorScale, SpeedCapError> {
        SpeedCap::new(self.max_jog_speed)?.with_operator(self.operator_full_speed)
    }

    /// Home's stored action when Modbus runs it; `None` when the operator does.
    pub fn modbus_home(&self) -> Option<Stored> {
        match (&self.talos, &self.modbus) {
            (None, Some(modbus)) => Some(modbus.home_action()),
            _ => None,
        }
    }

    /// A guard must run on every real link: a killed console leaves a twist or go-to running.
    pub fn guard_required(&self) -> bool {
        matches!(self.guard, GuardPolicy::Spawn(_))
            && (self.talos.is_some() || self.modbus.is_some())
    }

    /// Where the telemetry panels get their data.
    pub fn telemetry_source(&self) -> TelemetrySource {
        match (&self.modbus, &self.talos) {
            (Some(_), _) => TelemetrySource::Modbus,
            (None, Some(t)) if t.dialect == Dialect::Icd => TelemetrySource::TalosHardware,
            _ => TelemetrySource::None,
        }
    }

    /// Named positions live on the operator when there is a Talos link in the ICD dialect.
    pub fn positions_on_operator(&self) -> bool {
        self.talos
            .as_ref()
            .is_some_and(|t| t.dialect == Dialect::Icd)
    }

    /// A short name of the target, for the positions file.
    pub fn target(&self) -> String {
        match (&self.talos, &self.modbus) {
            (Some(t), _) => format!("talos-{}", t.addr),
            (None, Some(m)) => format!("modbus-{}-{}", m.addr, m.unit),
            (None, None) => "none".into(),
        }
    }
}

/// The console's handle on the driver; dropping every clone stops the arm and ends the task.
#[derive(Debug, Clone)]
pub struct Driver {
    commands: mpsc::UnboundedSender<ArmCommand>,
    task: std::sync::Arc<std::sync::Mutex<Option<tokio::task::JoinHandle<()>>>>,
}

impl Driver {
    /// Starts the driver; it connects in the background.
    ///
    /// # Panics
    /// On a speed cap [`DriverConfig::speed_cap`] refuses (the front ends refuse it first).
    ///
    /// Not inlined: its set-up stays out of its caller's stack frame.
    #[inline(never)]
    pub fn spawn(config: DriverConfig) -> (Driver, mpsc::UnboundedReceiver<ArmEvent>) {
        let (commands, rx) = mpsc::unbounded_channel();
        let (events, events_rx) = mpsc::unbounded_channel();
        let started = event_loop::start(config, rx, events);
        // Boxed: tokio keeps a future under 16 KB inline, and its poll then holds room for it.
        let task = tokio::spawn(Box::pin(event_loop::run(started)));
        let task = std::sync::Arc::new(std::sync::Mutex::new(Some(task)));
        (Driver { commands, task }, events_rx)
    }

    /// Stops every motion, waits up to 2 s for the answers, and closes the links.
    pub async fn shutdown(self) {
        let task = self.task.lock().ok().and_then(|mut t| t.take());
        drop(self);
        if let Some(task) = task {
            let _ = tokio::time::timeout(Duration::from_secs(2), task).await;
        }
    }

    /// A handle that can only stop the arm and keeps the driver alive no longer: the panic hook's.
    pub fn stop_handle(&self) -> StopHandle {
        StopHandle(self.commands.downgrade())
    }

    /// Queues a command; never blocks. Returns false if the driver has ended.
    pub fn send(&self, command: ArmCommand) -> bool {
        self.commands.send(command).is_ok()
    }
}

/// See [`Driver::stop_handle`].
#[derive(Debug, Clone)]
pub struct StopHandle(mpsc::WeakUnboundedSender<ArmCommand>);

impl StopHandle {
    /// Asks the driver to stop every motion, if it still runs.
    pub fn stop(&self) {
        if let Some(commands) = self.0.upgrade() {
            let _ = commands.send(ArmCommand::Stop);
        }
    }
}
