//! The arm driver: one task that carries out the console's [`ArmCommand`]s on a Talos operator,
//! a Modbus arm, or both (jog through Talos, telemetry over Modbus), and reports [`ArmEvent`]s.
//!
//! Order is kept: Talos requests are submitted in command order and their replies awaited
//! apart, so a STOP never waits behind a START's reply; Modbus commands run one after another
//! in a worker that drops jog refreshes a later STOP makes stale. A STOP goes to every link;
//! over Talos it is the one stop set ([`crate::talos::stop_requests`]), on the keys, the panic
//! hook's [`StopHandle`] and the exit alike.
//!
//! The loop awaits nothing a peer controls: Talos submission queues or fails at once (a full
//! queue, or a write stalled 500 ms, ends that link), Modbus commands go to the worker's
//! channel. So an operator that stops reading holds up no STOP for the other link.
//! When a link drops, the driver reports it and reconnects; nothing moves again until the
//! technician presses a key. Connects and handshakes run off the loop (see [`connect`]), so a
//! STOP never waits behind one; a link unreachable at start is retried with back-off.

mod connect;
pub mod hw_telemetry;
mod modbus_worker;
mod speed;
pub use speed::{
    INITIAL_SPEED, JOINT_JOG_SPEED, MAX_ANGULAR_JOG_SPEED, OPERATOR_FULL_SPEED, OperatorScale,
};
pub use talos_side::ORIENTATION_NEEDS_MODBUS;
mod stop_outcome;
mod talos_side;

use std::time::Duration;

use tokio::sync::mpsc;

use super::Dialect;
use super::guard::{self, GuardPolicy, GuardReport, GuardSupervisor};
use super::interface::{ArmCommand, ArmError, ArmEvent, CommandKind, LinkStatus, TelemetrySource};
use super::modbus::{ModbusConfig, ModbusEvent, StopReason};
use super::talos::{TalosConfig, TalosEvent};
use connect::{Attempts, Connected};

/// The latest joint positions (deg) from whichever telemetry the driver has: a joint jog's
/// command carries the joint's last reported position, and none is sent before one is known.
pub(crate) type JointPositions = std::sync::Arc<tokio::sync::watch::Sender<Option<[f32; 7]>>>;

/// What the driver connects to and how it jogs.
#[derive(Debug, Clone)]
pub struct DriverConfig {
    pub talos: Option<TalosConfig>,
    pub modbus: Option<ModbusConfig>,
    /// The tool speed cap at 100 %, m/s (250 mm/s by default): bounds every motion the driver
    /// commands over Modbus and joint jogs over Talos; the speed in force is a percentage of it.
    pub max_jog_speed: f64,
    /// The Talos operator's tool speed at its own 100 %, m/s: Set Speed and Get Speed over
    /// Talos convert through it (see [`OperatorScale`]), so the operator keeps to the cap.
    pub operator_full_speed: f64,
    /// Single-joint jog speed at 100 %, deg/s.
    pub joint_jog_speed: f32,
    /// Hardware-operation telemetry polls per second on a Talos-only link.
    pub hw_telemetry_hz: f64,
    /// Handshake OID.
    pub oid: u16,
    /// The stop guard for a Modbus link that carries motion (none by default; the console
    /// starts one for a real arm).
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

    /// Whether motion can go over Modbus: jogs on a Modbus-only link, go-to of the console's
    /// own positions, and orientation jogs (which Talos cannot carry) whenever there is a Modbus
    /// link.
    pub fn modbus_carries_motion(&self) -> bool {
        self.modbus.is_some()
    }

    /// Whether a stop guard must run before motion goes over Modbus.
    pub fn guard_required(&self) -> bool {
        matches!(self.guard, GuardPolicy::Spawn(_)) && self.modbus_carries_motion()
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

/// The console's handle on the driver task. Dropping every clone stops the arm and ends the
/// task.
#[derive(Debug, Clone)]
pub struct Driver {
    commands: mpsc::UnboundedSender<ArmCommand>,
    task: std::sync::Arc<std::sync::Mutex<Option<tokio::task::JoinHandle<()>>>>,
}

impl Driver {
    /// Starts the driver; it connects in the background and reports through the events.
    pub fn spawn(config: DriverConfig) -> (Driver, mpsc::UnboundedReceiver<ArmEvent>) {
        let (commands, rx) = mpsc::unbounded_channel();
        let (events, events_rx) = mpsc::unbounded_channel();
        let task = tokio::spawn(run(config, rx, events));
        let task = std::sync::Arc::new(std::sync::Mutex::new(Some(task)));
        (Driver { commands, task }, events_rx)
    }

    /// Ends the driver: it stops every motion (the Modbus stop, and the Talos stop set once),
    /// waits (up to 2 s) for the stops to be answered, and closes the links.
    pub async fn shutdown(self) {
        let task = self.task.lock().ok().and_then(|mut t| t.take());
        drop(self);
        if let Some(task) = task {
            let _ = tokio::time::timeout(Duration::from_secs(2), task).await;
        }
    }

    /// A handle that can only stop the arm and does not keep the driver alive: for the panic
    /// hook.
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

/// Link states, combined for the status bar.
#[derive(Default)]
struct Links {
    talos: Option<Result<String, String>>,
    modbus: Option<Result<String, String>>,
}

impl Links {
    fn status(&self, config: &DriverConfig) -> LinkStatus {
        let parts = [
            (config.talos.is_some(), &self.talos),
            (config.modbus.is_some(), &self.modbus),
        ];
        let mut up = Vec::new();
        for (wanted, state) in parts {
            if !wanted {
                continue;
            }
            match state {
                None => return LinkStatus::Connecting,
                Some(Err(reason)) => {
                    return LinkStatus::Down {
                        reason: reason.clone(),
                    };
                }
                Some(Ok(description)) => up.push(description.clone()),
            }
        }
        if up.is_empty() {
            return LinkStatus::Down {
                reason: "no link configured".into(),
            };
        }
        LinkStatus::Up {
            description: up.join(" + "),
        }
    }
}

async fn run(
    config: DriverConfig,
    mut commands: mpsc::UnboundedReceiver<ArmCommand>,
    events: mpsc::UnboundedSender<ArmEvent>,
) {
    let _ = events.send(ArmEvent::TelemetrySource(config.telemetry_source()));
    let _ = events.send(ArmEvent::Status(LinkStatus::Connecting));
    let mut links = Links::default();
    let joints: JointPositions = std::sync::Arc::new(tokio::sync::watch::Sender::new(None));
    // The one speed in force, whichever link sets it and whichever carries the motion.
    let speed = speed::SpeedInForce::default();
    // Each side's events pass through here, so every STOP gets one outcome from all links.
    let mut stops = stop_outcome::StopOutcomes::default();
    let (talos_tx, mut talos_rx) = mpsc::unbounded_channel::<ArmEvent>();
    let (modbus_tx, mut modbus_rx) = mpsc::unbounded_channel::<ArmEvent>();
    let mut talos = talos_side::TalosSide::new(&config, talos_tx, joints.clone(), speed.clone());
    let (modbus_events_tx, mut modbus_events) = mpsc::unbounded_channel::<ModbusEvent>();
    let mut modbus: Option<modbus_worker::ModbusWorker> = None;
    let (guard_reports_tx, mut guard_reports) = mpsc::unbounded_channel::<GuardReport>();
    // Dropped when this task ends: the guard then stops the arm (once more) and exits.
    let guard = start_guard(&config, guard_reports_tx);

    // Connects and handshakes run as tasks that report here: the loop never waits for one.
    let (connected_tx, mut connected) = mpsc::unbounded_channel::<Connected>();
    let mut talos_attempts = match config.talos {
        Some(_) => Attempts::due_now(),
        None => Attempts::never(),
    };
    let mut modbus_attempts = match config.modbus {
        Some(_) => Attempts::due_now(),
        None => Attempts::never(),
    };

    let hz = config.hw_telemetry_hz.clamp(0.5, 50.0);
    let mut hw_poll = tokio::time::interval(Duration::from_secs_f64(1.0 / hz));
    hw_poll.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Skip);
    let hw_telemetry = config.telemetry_source() == TelemetrySource::TalosHardware;

    loop {
        tokio::select! {
            // Commands first: a STOP is never kept waiting by anything else that is ready.
            biased;
            command = commands.recv() => {
                let Some(command) = command else { break };
                if command.is_stop() {
                    // Stops go everywhere, whichever link the motion came through.
                    let (mut sent, mut down) = (Vec::new(), Vec::new());
                    if let Some(m) = &modbus {
                        m.send(command.clone());
                        sent.push(stop_outcome::Side::Modbus);
                    }
                    match (config.talos.is_some(), talos.is_down()) {
                        (true, false) => sent.push(stop_outcome::Side::Talos),
                        (true, true) => down.push(stop_outcome::Side::Talos),
                        (false, _) => {}
                    }
                    if let Some(outcome) = stops.stop(&sent, &down) {
                        let _ = events.send(outcome);
                    }
                    talos.command(command);
                    continue;
                }
                let via_talos = talos.handles(&command, modbus.is_some());
                match (&modbus, via_talos) {
                    (_, true) => {
                        stops.motion(&command, stop_outcome::Side::Talos);
                        talos.command(command)
                    }
                    (Some(m), false) => match guard_refusal(&config, guard.as_ref(), &command) {
                        Some(error) => {
                            let _ = events.send(ArmEvent::Failed { command: command.kind(), error });
                        }
                        None => {
                            stops.motion(&command, stop_outcome::Side::Modbus);
                            m.send(command)
                        }
                    },
                    (None, false) => {
                        // A missing guard is the reason that outlives the connect.
                        let error = match (&config.modbus, guard_refusal(&config, guard.as_ref(), &command)) {
                            (_, Some(error)) => error,
                            (Some(mc), None) => ArmError::ModbusLinkDown { addr: mc.addr.clone() },
                            (None, None) if is_orientation_jog(&command) => {
                                ArmError::Unsupported(ORIENTATION_NEEDS_MODBUS)
                            }
                            (None, None) => ArmError::NoLinkCarriesIt,
                        };
                        let _ = events.send(ArmEvent::Failed { command: command.kind(), error });
                    }
                }
            }
            Some(event) = talos_rx.recv() => {
                forward_side(event, stop_outcome::Side::Talos, &mut stops, &events);
            }
            Some(event) = modbus_rx.recv() => {
                forward_side(event, stop_outcome::Side::Modbus, &mut stops, &events);
            }
            Some(result) = connected.recv() => match result {
                Connected::Talos(Ok(link)) => {
                    talos_attempts.finished(true);
                    links.talos = Some(Ok(talos.attach(link)));
                    // The speed the operator reported comes before the link shows up.
                    while let Ok(event) = talos_rx.try_recv() {
                        forward_side(event, stop_outcome::Side::Talos, &mut stops, &events);
                    }
                    let _ = events.send(ArmEvent::Status(links.status(&config)));
                }
                Connected::Talos(Err(reason)) => {
                    talos_attempts.finished(false);
                    tracing::info!("{reason}; trying again");
                    // A link already down keeps the reason it went down with.
                    if !matches!(links.talos, Some(Err(_))) {
                        links.talos = Some(Err(reason));
                        let _ = events.send(ArmEvent::Status(links.status(&config)));
                    }
                }
                Connected::Modbus(Ok((link, link_events))) => {
                    modbus_attempts.finished(true);
                    forward(link_events, modbus_events_tx.clone());
                    if let Some(mc) = &config.modbus {
                        links.modbus = Some(Ok(format!("modbus {} unit {}", mc.addr, mc.unit)));
                    }
                    modbus = Some(modbus_worker::ModbusWorker::start(
                        link,
                        &config,
                        modbus_tx.clone(),
                        joints.clone(),
                        speed.clone(),
                    ));
                    if config.talos.is_none() {
                        // Without an operator to report one, the speed in force is the driver's.
                        let _ = events.send(ArmEvent::Speed(speed.percent()));
                    }
                    let _ = events.send(ArmEvent::Status(links.status(&config)));
                }
                Connected::Modbus(Err(reason)) => {
                    modbus_attempts.finished(false);
                    tracing::info!("{reason}; trying again");
                    if !matches!(links.modbus, Some(Err(_))) {
                        links.modbus = Some(Err(reason));
                        let _ = events.send(ArmEvent::Status(links.status(&config)));
                    }
                }
            },
            Some(event) = talos.next_event() => {
                if let TalosEvent::Disconnected { reason } = event {
                    links.talos = Some(Err(format!("talos: {reason}")));
                    talos.lost();
                    talos_attempts.lost();
                    let _ = events.send(ArmEvent::Status(links.status(&config)));
                }
            }
            Some(event) = modbus_events.recv() => {
                match event {
                    ModbusEvent::Disconnected { reason } => {
                        links.modbus = Some(Err(format!("modbus: {reason}")));
                        let _ = events.send(ArmEvent::Status(links.status(&config)));
                    }
                    ModbusEvent::Reconnected { .. } => {
                        if let Some(mc) = &config.modbus {
                            links.modbus = Some(Ok(format!("modbus {} unit {}", mc.addr, mc.unit)));
                        }
                        let _ = events.send(ArmEvent::Status(links.status(&config)));
                    }
                    ModbusEvent::StopFailed { error, reason } => {
                        let _ = events.send(ArmEvent::Failed {
                            command: CommandKind::Stop,
                            error: ArmError::StopNotWritten(error.clone()),
                        });
                        // A stop the console asked for gets its outcome from the worker's
                        // answer; one the link made on its own is reported here.
                        if reason != StopReason::Requested {
                            let _ = events.send(ArmEvent::StopUnconfirmed {
                                reason: format!("the Modbus link's own stop ({reason:?}): {error}"),
                            });
                        }
                    }
                    ModbusEvent::SpeedLimitsNotRestored { limits, error } => {
                        let _ = events.send(ArmEvent::Failed {
                            command: CommandKind::RestoreSpeedLimits,
                            error: ArmError::SpeedLimitsNotRestored {
                                linear: limits.linear,
                                angular: limits.angular,
                                error,
                            },
                        });
                    }
                    // Logged once by the link itself.
                    ModbusEvent::PlanFallback { .. } => {}
                    other => tracing::info!("modbus: {other:?}"),
                }
            }
            Some(report) = guard_reports.recv() => {
                if report.stops_motion()
                    && let Some(m) = &modbus
                {
                    m.send(ArmCommand::Stop);
                }
                let _ = events.send(report.into_event());
            }
            _ = connect::sleep_until(talos_attempts.due_at()) => {
                if let Some(attempt) = talos.connect_attempt() {
                    talos_attempts.start(async move { Connected::Talos(attempt.await) }, &connected_tx);
                }
            }
            _ = connect::sleep_until(modbus_attempts.due_at()) => {
                if let Some(mc) = &config.modbus {
                    modbus_attempts.start(connect::modbus(mc.clone()), &connected_tx);
                }
            }
            _ = hw_poll.tick(), if hw_telemetry => talos.poll_telemetry(),
        }
    }
    // The console is gone: stop everything on the way out. A connect still in flight has
    // started nothing and is given up.
    talos_attempts.abort();
    modbus_attempts.abort();
    if let Some(m) = &modbus {
        m.send(ArmCommand::Stop);
    }
    talos.flush().await;
    if let Some(m) = modbus {
        m.close().await;
    }
}

fn is_orientation_jog(command: &ArmCommand) -> bool {
    matches!(
        command,
        ArmCommand::Jog(super::interface::JogMotion::Orientation { .. })
    )
}

/// Starts the stop guard when the configuration needs one.
fn start_guard(
    config: &DriverConfig,
    reports: mpsc::UnboundedSender<GuardReport>,
) -> Option<GuardSupervisor> {
    let (GuardPolicy::Spawn(program), Some(mc)) = (&config.guard, &config.modbus) else {
        return None;
    };
    if !config.guard_required() {
        return None;
    }
    let _ = reports.send(GuardReport::Status(
        crate::link::interface::GuardStatus::Starting,
    ));
    Some(GuardSupervisor::spawn(
        program.clone(),
        mc.addr.clone(),
        mc.unit,
        reports,
    ))
}

/// Why a command bound for the Modbus link is refused for want of a stop guard, if it is.
fn guard_refusal(
    config: &DriverConfig,
    guard: Option<&GuardSupervisor>,
    command: &ArmCommand,
) -> Option<ArmError> {
    if config.guard == GuardPolicy::NotNeeded || !guard::is_motion(command) {
        return None;
    }
    let refusal = match guard {
        Some(g) => g.refusal(),
        None => Some("stop guard not running: none was started for this link".into()),
    };
    refusal.map(ArmError::GuardNotRunning)
}

/// Passes one side's event on, and the STOP outcome it completes after it.
fn forward_side(
    event: ArmEvent,
    side: stop_outcome::Side,
    stops: &mut stop_outcome::StopOutcomes,
    events: &mpsc::UnboundedSender<ArmEvent>,
) {
    let outcome = stop_outcome::stop_answer(&event).and_then(|answer| stops.answer(side, answer));
    let _ = events.send(event);
    if let Some(outcome) = outcome {
        let _ = events.send(outcome);
    }
}

fn forward<T: Send + 'static>(mut from: mpsc::UnboundedReceiver<T>, to: mpsc::UnboundedSender<T>) {
    tokio::spawn(async move {
        while let Some(item) = from.recv().await {
            if to.send(item).is_err() {
                break;
            }
        }
    });
}
