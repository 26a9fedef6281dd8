//! `armjog guard` (hidden): the stop guard the console starts for a real arm; why, and its
//! stdin/stdout protocol: [`crate::link::guard`]. Over Modbus it holds its own connection and
//! writes nothing while the console lives; over Talos it connects only to stop the arm
//! (`guard/talos.rs`). On stdin closing, or the heartbeat stopping (then it keeps watching), it
//! stops the arm on every link (Modbus: holding register 200 <- 2, else the abort coil; Talos: the
//! one stop set). SIGTERM, SIGINT and SIGHUP stop the arm too before it exits.

mod talos;

use std::future::Future;
use std::time::Duration;

use clap::Args;
use futures::future::OptionFuture;
use tokio::io::{AsyncRead, AsyncReadExt, AsyncWrite, AsyncWriteExt};
use tokio::sync::mpsc;
use tokio::time::Instant;

use crate::kortex::ControlCoil;
use crate::link::guard::{ALIVE_PERIOD, HEARTBEAT_TIMEOUT};
use crate::link::modbus::{DEFAULT_PORT, DEFAULT_UNIT, ModbusConfig, ModbusEvent, ModbusLink};
use crate::link::{Dialect, talos::DEFAULT_PORT as TALOS_PORT};
use crate::talos::Checksum;
pub use talos::{Console, SERVED_WITHIN, TalosStop};

/// How long the guard keeps trying to write a stop (reconnecting meanwhile) before it gives up.
const STOP_PERSISTENCE: Duration = Duration::from_secs(3);
/// Pause between connection attempts while the arm cannot be reached.
const CONNECT_RETRY: Duration = Duration::from_secs(1);

#[derive(Debug, Args)]
#[command(group = links_group())]
pub struct GuardArgs {
    /// The arm over Modbus, HOST:PORT (port 502 if omitted).
    #[arg(long, value_name = "HOST:PORT")]
    pub modbus: Option<String>,
    /// Modbus unit id.
    #[arg(long, default_value_t = DEFAULT_UNIT, value_name = "N")]
    pub unit: u8,
    /// The Talos operator, HOST:PORT (port 61616 if omitted): connected to only to stop it.
    #[arg(long, value_name = "HOST:PORT")]
    pub talos: Option<String>,
    /// The console's Talos dialect.
    #[arg(long, default_value = "icd", value_parser = super::values::dialect_parser())]
    pub dialect: Dialect,
    /// The console's Talos checksum.
    #[arg(long, default_value = "crc16", value_parser = super::values::checksum_parser())]
    pub checksum: Checksum,
    /// The handshake's OID, as the console sends it.
    #[arg(long, default_value_t = 0, value_name = "N")]
    pub oid: u16,
    /// Stop the arm when no heartbeat byte came for this long, milliseconds.
    #[arg(long, default_value_t = HEARTBEAT_TIMEOUT.as_millis() as u64, value_name = "MS")]
    pub heartbeat_timeout: u64,
}

impl GuardArgs {
    /// What the guard stops: the links it was given.
    pub fn targets(&self) -> Targets {
        Targets {
            // Writes only when told, a slow poll, short timeouts for retries.
            modbus: self.modbus.as_ref().map(|addr| {
                let mut config = ModbusConfig::new(super::with_default_port(addr, DEFAULT_PORT));
                config.unit = self.unit;
                config.poll_rate_hz = Some(1.0);
                config.twist_hold = None;
                config.request_timeout = Duration::from_millis(300);
                config.connect_timeout = Duration::from_secs(1);
                config
            }),
            talos: self.talos.as_ref().map(|addr| {
                TalosStop::new(
                    super::with_default_port(addr, TALOS_PORT),
                    self.dialect,
                    self.checksum,
                    self.oid,
                )
            }),
        }
    }
}

/// At least one link, either or both.
fn links_group() -> clap::ArgGroup {
    clap::ArgGroup::new("links")
        .args(["modbus", "talos"])
        .multiple(true)
        .required(true)
}

/// The links the guard stops the arm over.
#[derive(Debug, Clone)]
pub struct Targets {
    pub modbus: Option<ModbusConfig>,
    pub talos: Option<TalosStop>,
}

/// Runs the guard on stdin and stdout: exit 0 (stopped, or nothing connected) or 1 (stop failed).
pub async fn run(args: &GuardArgs) -> i32 {
    let timeout = Duration::from_millis(args.heartbeat_timeout.max(100));
    let signal = match signals() {
        Ok(signal) => signal,
        Err(e) => {
            tracing::error!("stop guard: cannot watch signals: {e}");
            return 1;
        }
    };
    watch(
        args.targets(),
        timeout,
        tokio::io::stdin(),
        tokio::io::stdout(),
        signal,
    )
    .await
}

fn signals() -> std::io::Result<impl Future<Output = &'static str>> {
    use tokio::signal::unix::{SignalKind, signal};
    let mut interrupt = signal(SignalKind::interrupt())?;
    let mut terminate = signal(SignalKind::terminate())?;
    let mut hangup = signal(SignalKind::hangup())?;
    Ok(async move {
        tokio::select! {
            _ = interrupt.recv() => "SIGINT",
            _ = terminate.recv() => "SIGTERM",
            _ = hangup.recv() => "SIGHUP",
        }
    })
}

/// The console's next byte (a heartbeat), or why it is gone. Cancel safe: nothing read is lost.
async fn from_console<R: AsyncRead + Unpin>(pipe: &mut R) -> Result<(), String> {
    let mut buf = [0u8; 64];
    match pipe.read(&mut buf).await {
        Ok(0) => Err("its pipe closed".into()),
        Ok(_) => Ok(()),
        Err(e) => Err(format!("reading its pipe failed: {e}")),
    }
}

/// Waits until the console is gone, ignoring heartbeats.
async fn console_gone<R: AsyncRead + Unpin>(pipe: &mut R) -> String {
    loop {
        if let Err(reason) = from_console(pipe).await {
            return reason;
        }
    }
}

/// The guard on any pipe and output; ready once Modbus is up, or at once with Talos alone.
pub async fn watch<R, W>(
    targets: Targets,
    heartbeat_timeout: Duration,
    mut pipe: R,
    mut out: W,
    signal: impl Future<Output = &'static str>,
) -> i32
where
    R: AsyncRead + Unpin,
    W: AsyncWrite + Unpin,
{
    tokio::pin!(signal);
    let (modbus, mut link_events) = match targets.modbus {
        None => (None, None),
        Some(config) => {
            let connect = connect(config, &mut out);
            tokio::pin!(connect);
            tokio::select! {
                biased;
                reason = console_gone(&mut pipe) => {
                    // Not ready yet, so the console was refused every motion: nothing to stop.
                    tracing::info!("stop guard: the console is gone ({reason}) before the arm was reached");
                    return 0;
                }
                name = &mut signal => {
                    tracing::info!("stop guard: {name} before the arm was reached");
                    return 0;
                }
                (link, events) = &mut connect => (Some(link), Some(events)),
            }
        }
    };
    let stopper = Stopper {
        modbus,
        talos: targets.talos,
    };
    say(&mut out, "ready").await;
    let mut deadline = Instant::now() + heartbeat_timeout;
    let mut starved = false;
    let mut alive = tokio::time::interval(ALIVE_PERIOD);
    alive.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    loop {
        tokio::select! {
            biased;
            message = from_console(&mut pipe) => match message {
                Ok(()) => {
                    deadline = Instant::now() + heartbeat_timeout;
                    if starved {
                        tracing::info!("stop guard: the console's heartbeat is back");
                        starved = false;
                    }
                }
                Err(reason) => {
                    let why = format!("the console is gone ({reason})");
                    return stopper.finish(&why, Console::Gone, &mut out).await;
                }
            },
            name = &mut signal => {
                // The console may live on: it then stops the arm and starts a new guard.
                return stopper.finish(name, Console::MayBeConnected, &mut out).await;
            }
            _ = tokio::time::sleep_until(deadline), if !starved => {
                starved = true;
                let why = format!("no heartbeat from the console for {} ms", heartbeat_timeout.as_millis());
                match stopper.stop(&why, Console::MayBeConnected).await {
                    Ok(done) => say(&mut out, &format!("stopped {why}: {done}")).await,
                    Err(e) => say(&mut out, &format!("stop-failed {why}: {e}")).await,
                }
            }
            _ = alive.tick() => say(&mut out, "alive").await,
            event = next_event(&mut link_events) => match event {
                Some(ModbusEvent::Disconnected { reason }) => say(&mut out, &format!("down {reason}")).await,
                Some(ModbusEvent::Reconnected { .. }) => say(&mut out, "ready").await,
                Some(_) => {}
                None => {
                    say(&mut out, "down the link to the arm has ended").await;
                    return 1;
                }
            },
        }
    }
}

/// The Modbus link's next event; never, without a Modbus link.
async fn next_event(
    events: &mut Option<mpsc::UnboundedReceiver<ModbusEvent>>,
) -> Option<ModbusEvent> {
    match events {
        Some(events) => events.recv().await,
        None => std::future::pending().await,
    }
}

/// Connects, retrying until it works; says `down` while the arm cannot be reached.
async fn connect<W: AsyncWrite + Unpin>(
    config: ModbusConfig,
    out: &mut W,
) -> (ModbusLink, mpsc::UnboundedReceiver<ModbusEvent>) {
    let mut last = String::new();
    loop {
        match ModbusLink::connect(config.clone()).await {
            Ok(connected) => return connected,
            Err(e) => {
                let reason = e.to_string();
                if reason != last {
                    tracing::warn!("stop guard: cannot reach the arm: {reason}");
                    say(out, &format!("down {reason}")).await;
                    last = reason;
                }
                tokio::time::sleep(CONNECT_RETRY).await;
            }
        }
    }
}

/// What the guard stops: the Modbus link it holds, the Talos operator it connects to.
struct Stopper {
    modbus: Option<ModbusLink>,
    talos: Option<TalosStop>,
}

impl Stopper {
    /// Stops the arm on the guard's way out, and returns the exit status.
    async fn finish<W: AsyncWrite + Unpin>(&self, why: &str, console: Console, out: &mut W) -> i32 {
        let code = match self.stop(why, console).await {
            Ok(done) => {
                tracing::info!("stop guard: {why}: arm stopped ({done})");
                say(out, &format!("stopped {why}: {done}")).await;
                0
            }
            Err(e) => {
                tracing::error!("stop guard: {why}: THE STOP FAILED: {e}. Use the arm's e-stop");
                say(out, &format!("stop-failed {why}: {e}")).await;
                1
            }
        };
        if let Some(link) = &self.modbus {
            let _ = tokio::time::timeout(Duration::from_secs(1), link.clone().close()).await;
        }
        code
    }

    /// Every link at once, each until it is written or [`STOP_PERSISTENCE`] has passed; what
    /// was done on each, or (any failed) what failed and what was done.
    async fn stop(&self, why: &str, console: Console) -> Result<String, String> {
        let give_up = Instant::now() + STOP_PERSISTENCE;
        let modbus = self
            .modbus
            .as_ref()
            .map(|link| stop_modbus(link, why, give_up));
        let talos = self
            .talos
            .as_ref()
            .map(|talos| talos.stop(console, give_up));
        let (modbus, talos) = (OptionFuture::from(modbus), OptionFuture::from(talos));
        let (modbus, talos) = tokio::join!(modbus, talos);
        let outcomes: Vec<(&str, Result<String, String>)> = [("modbus", modbus), ("talos", talos)]
            .into_iter()
            .filter_map(|(link, outcome)| Some((link, outcome?)))
            .collect();
        let said = outcomes
            .iter()
            .map(|(link, outcome)| match outcome {
                Ok(done) => format!("{link}: {done}"),
                Err(e) => format!("{link}: FAILED: {e}"),
            })
            .collect::<Vec<_>>()
            .join("; ");
        match outcomes.iter().all(|(_, outcome)| outcome.is_ok()) {
            true => Ok(said),
            false => Err(said),
        }
    }
}

/// Holding register 200 <- 2 (the link pulses the abort coil if the arm refuses it), else the abort
/// coil; both again over a fresh connection until one is written or `give_up`.
async fn stop_modbus(link: &ModbusLink, why: &str, give_up: Instant) -> Result<String, String> {
    let started = Instant::now();
    let mut errors = Vec::new();
    loop {
        match link.stop().await {
            Ok(report) => return Ok(done(started, report.writes.len())),
            Err(e) => {
                tracing::error!("stop guard ({why}): stop not written: {e}");
                errors.push(e.to_string());
            }
        }
        match link.pulse(ControlCoil::Abort).await {
            Ok(report) => return Ok(done(started, report.writes.len())),
            Err(e) => {
                tracing::error!("stop guard ({why}): abort coil not written: {e}");
                errors.push(e.to_string());
            }
        }
        if Instant::now() >= give_up {
            errors.dedup();
            return Err(errors.join("; "));
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
}

fn done(started: Instant, writes: usize) -> String {
    let ms = started.elapsed().as_secs_f64() * 1000.0;
    format!("{writes} writes in {ms:.1} ms")
}

/// One status line to the console; a console that is gone cannot read it, which is fine.
async fn say<W: AsyncWrite + Unpin>(out: &mut W, line: &str) {
    let _ = out.write_all(format!("{line}\n").as_bytes()).await;
    let _ = out.flush().await;
}
