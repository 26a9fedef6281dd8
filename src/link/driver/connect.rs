//! Connects run as tasks of their own, so a STOP never waits behind one.

use std::time::Duration;

use tokio::sync::mpsc;
use tokio::task::AbortHandle;
use tokio::time::Instant;

use super::talos_side::TalosConnected;
use crate::link::TalosError;
use crate::link::failure::Shared;
use crate::link::modbus::{ModbusConfig, ModbusError, ModbusEvent, ModbusLink};
use crate::talos::ReturnCode;

/// First retry delay after a failed connect or a lost link.
pub const RETRY_FIRST: Duration = Duration::from_secs(1);
/// Retry delays double up to this.
pub const RETRY_MAX: Duration = Duration::from_secs(5);

/// What a connect task reports.
pub enum Connected {
    Talos(Result<TalosConnected, ConnectError>),
    Modbus(Result<(ModbusLink, mpsc::UnboundedReceiver<ModbusEvent>), ConnectError>),
}

/// Why a link could not be opened, named by its link.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ConnectError {
    #[error("talos: {0}")]
    Talos(Shared<TalosError>),
    /// The handshake's failure in words, with its hint (`talos::first_exchange_error`).
    #[error("talos handshake: {0}")]
    Handshake(String),
    #[error(
        "talos: the operator's speed {speed}% is over the cap and it refused Set Speed ({code})"
    )]
    SpeedRefused { speed: u8, code: ReturnCode },
    #[error("talos: the operator's speed {speed}% is over the cap and Set Speed failed: {error}")]
    SpeedNotSet {
        speed: u8,
        error: Shared<TalosError>,
    },
    #[error("modbus {addr}: {error}")]
    Modbus {
        addr: String,
        error: Shared<ModbusError>,
    },
}

/// One link's connect attempts: at most one in flight, the next one due after a back-off.
pub struct Attempts {
    in_flight: Option<AbortHandle>,
    next_at: Option<Instant>,
    delay: Duration,
}

impl Attempts {
    /// A configured link's first attempt is due at once; an unconfigured one's never.
    pub fn new(configured: bool) -> Attempts {
        Attempts {
            in_flight: None,
            next_at: configured.then(Instant::now),
            delay: RETRY_FIRST,
        }
    }

    /// When the next attempt is due, if one is.
    pub fn due_at(&self) -> Option<Instant> {
        self.next_at.filter(|_| self.in_flight.is_none())
    }

    /// Runs `attempt` as a task that reports on `to`.
    pub fn start(
        &mut self,
        attempt: impl Future<Output = Connected> + Send + 'static,
        to: &mpsc::UnboundedSender<Connected>,
    ) {
        let to = to.clone();
        let task = tokio::spawn(async move {
            let _ = to.send(attempt.await);
        });
        self.in_flight = Some(task.abort_handle());
        self.next_at = None;
    }

    /// The attempt in flight ended: on failure the next one is due after the back-off.
    pub fn finished(&mut self, succeeded: bool) {
        self.in_flight = None;
        if succeeded {
            self.delay = RETRY_FIRST;
            self.next_at = None;
        } else {
            self.next_at = Some(Instant::now() + self.delay);
            self.delay = (self.delay * 2).min(RETRY_MAX);
        }
    }

    /// The link was lost: try again after the first delay.
    pub fn lost(&mut self) {
        self.delay = RETRY_FIRST;
        self.finished(false);
    }

    /// Gives up the attempt in flight (the driver is ending).
    pub fn abort(&mut self) {
        if let Some(task) = self.in_flight.take() {
            task.abort();
        }
        self.next_at = None;
    }
}

/// The Modbus connect, reporting as [`Connected::Modbus`].
pub async fn modbus(config: ModbusConfig) -> Connected {
    let addr = config.addr.clone();
    let failed = |e: ModbusError| ConnectError::Modbus {
        addr,
        error: e.into(),
    };
    Connected::Modbus(ModbusLink::connect(config).await.map_err(failed))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The delay until the next attempt, in whole seconds (the clock runs on meanwhile).
    fn due_in_secs(attempts: &Attempts, before: Instant) -> Option<u64> {
        attempts.due_at().map(|at| (at - before).as_secs())
    }

    #[tokio::test]
    async fn failed_attempts_back_off_from_one_second_to_five_and_reset_on_success() {
        let mut attempts = Attempts::new(true);
        let mut delays = Vec::new();
        for _ in 0..5 {
            let before = Instant::now();
            attempts.finished(false);
            delays.push(due_in_secs(&attempts, before));
        }
        assert_eq!(
            delays,
            [1, 2, 4, 5, 5].map(Some),
            "1 s doubling, capped at 5 s"
        );
        attempts.finished(true);
        assert_eq!(attempts.due_at(), None, "nothing is due while connected");
        let before = Instant::now();
        attempts.lost();
        assert_eq!(due_in_secs(&attempts, before), Some(1));
        assert_eq!(Attempts::new(false).due_at(), None);
    }

    #[tokio::test]
    async fn no_attempt_is_due_while_one_is_in_flight() {
        let (tx, mut rx) = mpsc::unbounded_channel();
        let mut attempts = Attempts::new(true);
        assert!(attempts.due_at().is_some());
        attempts.start(
            async {
                tokio::time::sleep(Duration::from_millis(20)).await;
                Connected::Talos(Err(ConnectError::Handshake("late".into())))
            },
            &tx,
        );
        assert_eq!(attempts.due_at(), None);
        let Some(Connected::Talos(Err(reason))) = rx.recv().await else {
            panic!("the attempt reports on the channel");
        };
        assert_eq!(reason, ConnectError::Handshake("late".into()));
        attempts.finished(false);
        assert!(attempts.due_at().is_some());
    }
}
