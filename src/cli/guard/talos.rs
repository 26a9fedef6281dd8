//! The guard's stop over Talos: the one stop set ([`stop_requests`]) over a connection of its
//! own, in the console's dialect and checksum, opened only when the guard must stop the arm.
//!
//! The deployed operator serves one client at a time: a second connection is accepted by the
//! kernel but not answered while the first is open. So the guard holds no connection beside the
//! console's (and must not: one opened before the console's would hold the console off). When
//! the console dies the kernel closes its connection, the operator takes the next one, and the
//! guard's frames, written at once, are read the moment it does: a handshake (as the console
//! sends one) and the stop set behind it.
//!
//! A frozen console still holds its connection: an operator that serves one client at a time
//! does not answer the guard's, and nothing the guard can send reaches it. The guard then (and
//! when a signal ends it, the console perhaps alive) sends only a handshake and waits
//! [`SERVED_WITHIN`] for its answer; the stop set goes out only on a connection the operator
//! serves (one that takes several clients), so no stop is left queued in the operator to land
//! later, at a moment nobody chose. Unanswered, the stop is reported as failed: a go-to, home
//! or step runs on to its end; a continuous jog stops at the operator's 500 ms watchdog, the
//! frozen console refreshing nothing.

use std::time::Duration;

use tokio::time::Instant;

use crate::link::{Dialect, TalosConfig, TalosError, TalosLink};
use crate::talos::{Checksum, Request, stop_requests};

/// How long a request waits for its answer; and how long the operator has to answer a handshake
/// while the console may still hold its connection.
pub const SERVED_WITHIN: Duration = Duration::from_millis(500);
/// Pause between attempts over a fresh connection.
const RETRY: Duration = Duration::from_millis(50);

/// Whether the console's connection to the operator is known to be closing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Console {
    /// Its process is gone (the pipe closed): the kernel has closed its connection, or the
    /// console closed it on its way out.
    Gone,
    /// It may still hold its connection: it stopped beating but lives, or the guard was told
    /// to end by a signal (the console, alive, then stops the arm and starts a new guard).
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
        // Nothing of the console's runs on this thread: no CPU to hand over.
        config.give_way = false;
        TalosStop { config, oid }
    }

    /// Sends the stop set until the operator has answered every request of it, over a fresh
    /// connection each try, until `give_up`; while the console may still be connected, one
    /// try (see the module docs). Returns what was done, or every distinct error.
    pub async fn stop(&self, console: Console, give_up: Instant) -> Result<String, String> {
        let started = Instant::now();
        let mut errors: Vec<String> = Vec::new();
        loop {
            match self.once(console).await {
                Ok(requests) => {
                    return Ok(format!(
                        "stop set of {requests} answered in {:.1} ms",
                        started.elapsed().as_secs_f64() * 1000.0
                    ));
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

    /// One connection: the handshake, the stop set, their answers. Returns how many stop
    /// requests were answered.
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
