//! The built-in simulated arm on its own thread and runtime, off the console's key path.

use std::net::SocketAddr;

use tokio::sync::oneshot;

use crate::sim::{SimConfig, SimError, Simulator};

/// The running simulator's addresses; dropping it ends the simulator.
pub struct SimThread {
    pub talos_addr: SocketAddr,
    pub modbus_addr: Option<SocketAddr>,
    /// Dropped with this: the thread's runtime then ends, and the simulator with it.
    _stop: oneshot::Sender<()>,
}

type Started = Result<(SocketAddr, Option<SocketAddr>), NotStarted>;

/// Why the simulator did not start.
#[derive(Debug, thiserror::Error)]
pub enum NotStarted {
    /// Its runtime or its thread.
    #[error("its {0}: {1}")]
    Io(&'static str, std::io::Error),
    #[error("its thread ended before it listened")]
    ThreadEnded,
    #[error(transparent)]
    Listen(#[from] SimError),
}

/// Starts the simulator on its own thread; returns once it listens (or why it cannot).
pub async fn start(config: SimConfig) -> Result<SimThread, NotStarted> {
    let (ready_tx, ready) = oneshot::channel::<Started>();
    let (stop, stopped) = oneshot::channel::<()>();
    std::thread::Builder::new()
        .name("armjog-sim".into())
        .spawn(move || {
            let runtime = match tokio::runtime::Builder::new_current_thread()
                .enable_all()
                .build()
            {
                Ok(runtime) => runtime,
                Err(e) => {
                    let _ = ready_tx.send(Err(NotStarted::Io("runtime", e)));
                    return;
                }
            };
            runtime.block_on(async move {
                match Simulator::start(config).await {
                    Ok(sim) => {
                        let _ = ready_tx.send(Ok((sim.talos_addr, sim.modbus_addr)));
                        // Until the console drops its handle (or ends).
                        let _ = stopped.await;
                        drop(sim);
                    }
                    Err(e) => {
                        let _ = ready_tx.send(Err(e.into()));
                    }
                }
            });
        })
        .map_err(|e| NotStarted::Io("thread", e))?;
    let (talos_addr, modbus_addr) = ready.await.map_err(|_| NotStarted::ThreadEnded)??;
    Ok(SimThread {
        talos_addr,
        modbus_addr,
        _stop: stop,
    })
}
