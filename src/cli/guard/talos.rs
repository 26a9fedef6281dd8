//! The guard's stop over Talos: the one stop set ([`stop_requests`]) over a connection of its own,
//! in the console's dialect and checksum, opened only when it must stop the arm. The deployed
//! operator serves one client at a time, so the guard holds none beside the console's (one opened
//! first would hold the console off): when the console dies the kernel closes its connection and
//! the guard's handshake and stop set are read at once.
//!
//! A frozen console still holds its connection. The guard then (or when a signal ends it) sends
//! only a handshake and waits [`SERVED_WITHIN`]: the stop set goes out only on a served connection,
//! so no stop is left queued to land later, at a moment nobody chose. Unanswered, the stop is
//! reported failed: a go-to, home or step runs on to its end; a continuous jog stops at the
//! operator's 500 ms watchdog.

use std::time::Duration;

use tokio::time::Instant;

use crate::link::{Dialect, TalosConfig, TalosError, TalosLink};
use crate::talos::{Checksum, Request, stop_requests};

/// The wait for each answer, and for a handshake while the console may hold its connection.
pub const SERVED_WITHIN: Duration = Duration::from_millis(500);
/// Pause between attempts over a fresh connection.
const RETRY: Duration = Duration::from_millis(50);

/// Whether the console's connection to the operator is known to be closing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Console {
    /// The console's process is gone, and its connection closed.
    Gone,
    /// It may hold its connection: frozen, or the guard was signalled.
    MayBeConnected,
}

/// Where and how the guard stops the arm over Talos.
#[derive(Debug, Clone)]
pub struct TalosStop {
    config: TalosConfig,
    oid: u16,
}

impl TalosStop {
    pub fn new(addr: String, dialect: Dialect, checksum: Checksum, oid: u16) -> TalosStop {
        let mut config = TalosConfig::new(addr);
        config.dialect = dialect;
        config.checksum = checksum;
        config.connect_timeout = Duration::from_secs(1);
        config.request_timeout = SERVED_WITHIN;
        TalosStop { config, oid }
    }

    /// Sends the stop set until every request is answered, over a fresh connection each try, until
    /// `give_up`; one try while the console may still be connected. Returns what was done, or every
    /// distinct error.
    pub async fn stop(&self, console: Console, give_up: Instant) -> Result<String, String> {
        let started = Instant::now();
        let mut errors: Vec<String> = Vec::new();
        loop {
            match self.once(console).await {
                Ok(requests) => {
                    let ms = started.elapsed().as_secs_f64() * 1000.0;
                    return Ok(format!("stop set of {requests} answered in {ms:.1} ms"));
                }
                // Each distinct error once: the tries are 50 ms apart.
                Err(e) if !errors.contains(&e.to_string()) => {
                    tracing::error!("stop guard: talos stop not answered: {e}");
                    errors.push(e.to_string());
                }
                Err(_) => {}
            }
            if console == Console::MayBeConnected || Instant::now() >= give_up {
                return Err(errors.join("; "));
            }
            tokio::time::sleep(RETRY).await;
        }
    }

    /// One connection: handshake, stop set, answers; returns how many stops were answered.
    async fn once(&self, console: Console) -> Result<usize, NotAnswered> {
        let (link, _events) = TalosLink::connect(self.config.clone()).await?;
        let handshake = link.submit(Request::Handshake {
            oid: Some(self.oid),
        })?;
        if console == Console::MayBeConnected {
            match handshake.wait().await {
                // Any answer, a refusal too, says the operator serves this connection.
                Ok(_) | Err(TalosError::ReturnCode { .. }) => {}
                Err(e) => return Err(NotAnswered::NotServed(e)),
            }
        }
        let mut answers = Vec::new();
        for request in stop_requests(self.config.dialect) {
            answers.push(link.submit(request)?.wait());
        }
        let requests = answers.len();
        for answer in futures::future::join_all(answers).await {
            answer?;
        }
        Ok(requests)
    }
}

/// Why one try did not get the stop set answered.
#[derive(Debug, thiserror::Error)]
enum NotAnswered {
    #[error(transparent)]
    Talos(#[from] TalosError),
    #[error(
        "the operator did not answer the guard's connection ({0}): one that \
         serves one client at a time cannot while the console holds its own"
    )]
    NotServed(TalosError),
}
