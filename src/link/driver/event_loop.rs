//! The driver's loop: the `select!` waits and dispatches, one handler per event. Commands come
//! first (`biased`) so a STOP never waits, and no handler awaits anything a peer controls.

use std::time::Duration;

use tokio::sync::mpsc;

use super::connect::{self, Attempts, Connected};
use super::links::{LinkState, Links, LostReason, modbus_description};
use super::stop_outcome::{self, Side, StopOutcomes};
use super::talos_side::{ORIENTATION_NEEDS_MODBUS, STORED_NEEDS_MODBUS, TalosSide};
use super::{DriverConfig, JointPositions, modbus_worker::ModbusWorker, speed::SpeedInForce};
use crate::link::guard::{self, GuardNotRunning, GuardPolicy, GuardReport, GuardSupervisor};
use crate::link::interface::{
    ArmCommand, ArmError, ArmEvent, CommandKind, GuardStatus, JogMotion, LinkStatus,
    TelemetrySource,
};
use crate::link::modbus::{ModbusEvent, StopReason};
use crate::link::talos::TalosEvent;
use crate::net::Deadline;

/// Everything the loop waits on that is not part of the driver's state.
struct Inbox {
    commands: mpsc::UnboundedReceiver<ArmCommand>,
    talos_side: mpsc::UnboundedReceiver<ArmEvent>,
    modbus_side: mpsc::UnboundedReceiver<ArmEvent>,
    connected: mpsc::UnboundedReceiver<Connected>,
    modbus_link: mpsc::UnboundedReceiver<ModbusEvent>,
    guard_reports: mpsc::UnboundedReceiver<GuardReport>,
    hw_poll: tokio::time::Interval,
}

/// The driver's state: the links, their workers, and what the console is told.
struct DriverState {
    config: DriverConfig,
    events: mpsc::UnboundedSender<ArmEvent>,
    links: Links,
    joints: JointPositions,
    // The one speed in force, whichever link sets it and whichever carries the motion.
    speed: SpeedInForce,
    // Each side's events pass through here, so every STOP gets one outcome from all links.
    stops: StopOutcomes,
    talos: TalosSide,
    modbus: Option<ModbusWorker>,
    modbus_side_tx: mpsc::UnboundedSender<ArmEvent>,
    modbus_link_tx: mpsc::UnboundedSender<ModbusEvent>,
    // Dropped when the driver ends: the guard then stops the arm (once more) and exits.
    guard: Option<GuardSupervisor>,
    // Connects and handshakes run as tasks that report here: the loop never waits for one.
    connected_tx: mpsc::UnboundedSender<Connected>,
    talos_attempts: Attempts,
    modbus_attempts: Attempts,
    hw_telemetry: bool,
}

/// The loop's state, made before its task starts, so the task's future holds no set-up.
pub(super) struct Started {
    driver: Box<DriverState>,
    inbox: Inbox,
}

pub(super) fn start(
    config: DriverConfig,
    commands: mpsc::UnboundedReceiver<ArmCommand>,
    events: mpsc::UnboundedSender<ArmEvent>,
) -> Started {
    let _ = events.send(ArmEvent::TelemetrySource(config.telemetry_source()));
    let _ = events.send(ArmEvent::Status(LinkStatus::Connecting));
    let joints: JointPositions = std::sync::Arc::new(tokio::sync::watch::Sender::new(None));
    // A cap made in code that skipped the front ends' check stops here, before anything connects.
    let cap = config.speed_cap().unwrap_or_else(|e| {
        let (cap, operator) = (config.max_jog_speed, config.operator_full_speed);
        panic!("speed cap {cap} m/s on an operator of {operator} m/s: {e}")
    });
    let speed = SpeedInForce::default();
    let (talos_side_tx, talos_side) = mpsc::unbounded_channel();
    let (modbus_side_tx, modbus_side) = mpsc::unbounded_channel();
    let (modbus_link_tx, modbus_link) = mpsc::unbounded_channel();
    let (guard_reports_tx, guard_reports) = mpsc::unbounded_channel();
    let (connected_tx, connected) = mpsc::unbounded_channel();
    let talos = TalosSide::new(&config, cap, talos_side_tx, joints.clone(), speed.clone());
    let guard = start_guard(&config, guard_reports_tx);
    let hz = config.hw_telemetry_hz.clamp(0.5, 50.0);
    let mut hw_poll = tokio::time::interval(Duration::from_secs_f64(1.0 / hz));
    hw_poll.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Skip);
    let inbox = Inbox {
        commands,
        talos_side,
        modbus_side,
        connected,
        modbus_link,
        guard_reports,
        hw_poll,
    };
    let driver = Box::new(DriverState {
        talos_attempts: Attempts::new(config.talos.is_some()),
        modbus_attempts: Attempts::new(config.modbus.is_some()),
        hw_telemetry: config.telemetry_source() == TelemetrySource::TalosHardware,
        config,
        events,
        links: Links::default(),
        joints,
        speed,
        stops: StopOutcomes::default(),
        talos,
        modbus: None,
        modbus_side_tx,
        modbus_link_tx,
        guard,
        connected_tx,
    });
    Started { driver, inbox }
}

/// On the key path: set-up, exit and connects live out of line so the poll's stack frame stays
/// small (each page of it is touched on every poll).
pub(super) async fn run(started: Started) {
    let Started {
        mut driver,
        mut inbox,
    } = started;
    let (mut talos_due, mut modbus_due) = (Deadline::new(), Deadline::new());
    loop {
        talos_due.set(driver.talos_attempts.due_at());
        modbus_due.set(driver.modbus_attempts.due_at());
        tokio::select! {
            // Commands first: a STOP is never kept waiting by anything else that is ready.
            biased;
            command = inbox.commands.recv() => match command {
                Some(command) => {
                    driver.on_command(command);
                    let last = inbox.commands.is_empty();
                    driver.talos.spawn_answers(last).await;
                }
                None => break,
            },
            Some(event) = inbox.talos_side.recv() => driver.on_side_event(Side::Talos, event),
            Some(event) = inbox.modbus_side.recv() => driver.on_side_event(Side::Modbus, event),
            Some(result) = inbox.connected.recv() => driver.on_connected(result, &mut inbox),
            Some(event) = driver.talos.next_event() => driver.on_talos_link(event),
            Some(event) = inbox.modbus_link.recv() => driver.on_modbus_link(event),
            Some(report) = inbox.guard_reports.recv() => driver.on_guard_report(report),
            _ = talos_due.fired(), if talos_due.armed() => driver.on_talos_due(),
            _ = modbus_due.fired(), if modbus_due.armed() => driver.on_modbus_due(),
            _ = inbox.hw_poll.tick(), if driver.hw_telemetry => driver.talos.poll_telemetry(),
        }
    }
    // Behind a box and a vtable, so it is not inlined into the loop's poll (see above).
    let finish: std::pin::Pin<Box<dyn Future<Output = ()> + Send>> = Box::pin(driver.finish());
    finish.await;
}

impl DriverState {
    fn emit(&self, event: ArmEvent) {
        let _ = self.events.send(event);
    }

    fn emit_status(&self) {
        self.emit(ArmEvent::Status(self.links.status(&self.config)));
    }

    fn on_command(&mut self, command: ArmCommand) {
        if command.is_stop() {
            return self.on_stop(command);
        }
        if let Some(error) = guard_refusal(&self.config, self.guard.as_ref(), &command) {
            return self.emit(ArmEvent::failed(&command, error));
        }
        if let ArmCommand::FenceSpeed(permille) = command {
            // In force for both sides at once; the operator, with one speed, is told too.
            self.speed.set_fence(permille);
            if !self.talos.handles(&command, self.modbus.is_some()) || self.talos.is_down() {
                return self.emit(ArmEvent::Done { command });
            }
        }
        if self.talos.handles(&command, self.modbus.is_some()) {
            self.stops.motion(&command, Side::Talos);
            return self.talos.command(command);
        }
        match &self.modbus {
            Some(modbus) => {
                self.stops.motion(&command, Side::Modbus);
                modbus.send(command);
            }
            None => {
                let error = match &self.config.modbus {
                    Some(mc) => ArmError::ModbusLinkDown {
                        addr: mc.addr.clone(),
                    },
                    None if matches!(command, ArmCommand::Jog(JogMotion::Orientation { .. })) => {
                        ArmError::Unsupported(ORIENTATION_NEEDS_MODBUS)
                    }
                    None if matches!(command, ArmCommand::StartStored(_)) => {
                        ArmError::Unsupported(STORED_NEEDS_MODBUS)
                    }
                    None => ArmError::NoLinkCarriesIt,
                };
                self.emit(ArmEvent::failed(&command, error));
            }
        }
    }

    /// Stops go everywhere, whichever link the motion came through.
    fn on_stop(&mut self, command: ArmCommand) {
        let (mut sent, mut down) = (Vec::new(), Vec::new());
        if let Some(modbus) = &self.modbus {
            modbus.send(command.clone());
            sent.push(Side::Modbus);
        }
        match (self.config.talos.is_some(), self.talos.is_down()) {
            (true, false) => sent.push(Side::Talos),
            (true, true) => down.push(Side::Talos),
            (false, _) => {}
        }
        if let Some(outcome) = self.stops.stop(&sent, &down) {
            self.emit(outcome);
        }
        self.talos.command(command);
    }

    /// Passes one side's event on, and the STOP outcome it completes after it.
    fn on_side_event(&mut self, side: Side, event: ArmEvent) {
        let outcome =
            stop_outcome::stop_answer(&event).and_then(|answer| self.stops.answer(side, answer));
        self.emit(event);
        if let Some(outcome) = outcome {
            self.emit(outcome);
        }
    }

    #[inline(never)]
    fn on_connected(&mut self, result: Connected, inbox: &mut Inbox) {
        match result {
            Connected::Talos(Ok(link)) => {
                self.talos_attempts.finished(true);
                self.links.talos = LinkState::Up {
                    description: self.talos.attach(link),
                };
                // The speed the operator reported comes before the link shows up.
                while let Ok(event) = inbox.talos_side.try_recv() {
                    self.on_side_event(Side::Talos, event);
                }
                self.emit_status();
            }
            Connected::Talos(Err(reason)) => {
                self.talos_attempts.finished(false);
                tracing::info!("{reason}; trying again");
                if Links::connect_failed(&mut self.links.talos, reason) {
                    self.emit_status();
                }
            }
            Connected::Modbus(Ok((link, link_events))) => {
                self.modbus_attempts.finished(true);
                forward(link_events, self.modbus_link_tx.clone());
                self.modbus_up();
                self.modbus = Some(ModbusWorker::start(
                    link,
                    self.talos.cap(),
                    self.modbus_side_tx.clone(),
                    self.joints.clone(),
                    self.speed.clone(),
                ));
                if self.config.talos.is_none() {
                    // Without an operator to report one, the speed in force is the driver's.
                    self.emit(ArmEvent::Speed(self.speed.percent()));
                }
                self.emit_status();
            }
            Connected::Modbus(Err(reason)) => {
                self.modbus_attempts.finished(false);
                tracing::info!("{reason}; trying again");
                if Links::connect_failed(&mut self.links.modbus, reason) {
                    self.emit_status();
                }
            }
        }
    }

    fn modbus_up(&mut self) {
        if let Some(mc) = &self.config.modbus {
            self.links.modbus = LinkState::Up {
                description: modbus_description(mc),
            };
        }
    }

    fn on_talos_link(&mut self, event: TalosEvent) {
        if let TalosEvent::Disconnected { reason } = event {
            self.links.talos = LinkState::Lost(LostReason::TalosDisconnected(reason));
            self.talos.lost();
            self.talos_attempts.lost();
            self.emit_status();
        }
    }

    fn on_modbus_link(&mut self, event: ModbusEvent) {
        match event {
            ModbusEvent::Disconnected { reason } => {
                self.links.modbus = LinkState::Lost(LostReason::ModbusDisconnected(reason));
                self.emit_status();
            }
            ModbusEvent::Reconnected { .. } => {
                self.modbus_up();
                self.emit_status();
            }
            ModbusEvent::StopFailed { error, reason } => {
                self.emit(ArmEvent::Failed {
                    command: CommandKind::Stop,
                    error: ArmError::StopNotWritten(error.clone()),
                });
                // A requested stop's outcome comes from the worker.
                if reason != StopReason::Requested {
                    self.emit(ArmEvent::StopUnconfirmed {
                        reason: format!("the Modbus link's own stop ({reason:?}): {error}"),
                    });
                }
            }
            ModbusEvent::SpeedLimitsNotRestored { limits, error } => {
                self.emit(ArmEvent::Failed {
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

    fn on_guard_report(&mut self, report: GuardReport) {
        if report.stops_motion() {
            // Outside the STOP outcomes: the console stops on the event and asks for its own STOP.
            if let Some(modbus) = &self.modbus {
                modbus.send(ArmCommand::Stop);
            }
            // Without a link the Talos side drops a stop silently.
            self.talos.command(ArmCommand::Stop);
        }
        self.emit(report.into_event());
    }

    #[inline(never)]
    fn on_talos_due(&mut self) {
        if let Some(attempt) = self.talos.connect_attempt() {
            self.talos_attempts.start(
                async move { Connected::Talos(attempt.await) },
                &self.connected_tx,
            );
        }
    }

    #[inline(never)]
    fn on_modbus_due(&mut self) {
        if let Some(mc) = &self.config.modbus {
            self.modbus_attempts
                .start(connect::modbus(mc.clone()), &self.connected_tx);
        }
    }

    /// The exit's stop set over both links: Modbus queued, Talos answered (or 500 ms).
    async fn stop_everywhere(&self) {
        if let Some(modbus) = &self.modbus {
            modbus.send(ArmCommand::Stop);
        }
        self.talos.stop_and_wait().await;
    }

    /// The console is gone: stop everything; a connect in flight started nothing and is dropped.
    async fn finish(mut self: Box<Self>) {
        self.talos_attempts.abort();
        self.modbus_attempts.abort();
        self.stop_everywhere().await;
        // Again: another console's refresh that crossed the first stop set restarted the arm.
        tokio::time::sleep(EXIT_STOP_AGAIN).await;
        self.stop_everywhere().await;
        self.talos.close();
        if let Some(modbus) = self.modbus.take() {
            modbus.close().await;
        }
    }
}

/// Past a crossing refresh's trip, and about when the other console's next refresh falls due (100
/// ms apart; it needs two samples to see this stop, `console/app/other_client.rs`).
const EXIT_STOP_AGAIN: Duration = Duration::from_millis(100);

/// Starts the stop guard when the configuration needs one.
fn start_guard(
    config: &DriverConfig,
    reports: mpsc::UnboundedSender<GuardReport>,
) -> Option<GuardSupervisor> {
    let GuardPolicy::Spawn(program) = &config.guard else {
        return None;
    };
    if !config.guard_required() {
        return None;
    }
    let _ = reports.send(GuardReport::Status(GuardStatus::Starting));
    let args = guard::guard_args(config.talos.as_ref(), config.modbus.as_ref(), config.oid);
    Some(GuardSupervisor::spawn(program.clone(), args, reports))
}

/// Why a motion is refused for want of a stop guard on the link that would carry it.
fn guard_refusal(
    config: &DriverConfig,
    guard: Option<&GuardSupervisor>,
    command: &ArmCommand,
) -> Option<ArmError> {
    if !config.guard_required() || !command.starts_motion() {
        return None;
    }
    let refusal = match guard {
        Some(g) => g.refusal(),
        None => Some(GuardNotRunning::NoneStarted),
    };
    refusal.map(ArmError::GuardNotRunning)
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
