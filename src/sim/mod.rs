//! The simulated Gen3 and its Talos (:61616) and Modbus (:5020) servers, one arm task.

pub mod arm_model;
pub mod kinematics;
pub mod modbus_frames;
pub mod modbus_registers;
pub mod modbus_server;
pub mod operator;
pub mod reject_log;
pub mod stored;
pub mod talos_server;
pub mod telemetry;
pub mod world;

use std::net::SocketAddr;

use tokio::net::TcpListener;
use tokio::sync::watch;
use tokio::task::JoinHandle;

use arm_model::Arm;
use operator::Operator;
use talos_server::{NetworkFaults, TalosServerConfig};
use world::SimArm;

pub const DEFAULT_TALOS_LISTEN: &str = "127.0.0.1:61616";
pub const DEFAULT_MODBUS_LISTEN: &str = "127.0.0.1:5020";

/// Where and how the simulator serves.
#[derive(Debug, Clone)]
pub struct SimConfig {
    pub talos_listen: String,
    /// `None` runs no Modbus server.
    pub modbus_listen: Option<String>,
    pub talos: TalosServerConfig,
    pub faults: NetworkFaults,
    /// The arm's starting state (home pose at rest by default).
    pub arm: Arm,
    /// The operator's tool speed cap at 100 %, m/s, for every motion it commands.
    pub max_jog_speed: f64,
    /// Named positions the operator starts with (remembered from earlier runs).
    pub positions: Vec<operator::RememberedPosition>,
    /// What a Modbus read over addresses the ICD does not list gets.
    pub unlisted_reads: UnlistedReads,
}

/// How the Modbus server answers a read that spans addresses the ICD does not list. A real
/// arm's behaviour is not documented; the console reads either kind (see `PollPlan`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum UnlistedReads {
    /// "Illegal data address", as a strict arm does: the console then reads the ICD's blocks
    /// one by one (9 requests a snapshot).
    #[default]
    Refuse,
    /// Zeros for the unlisted addresses inside the register image, as many Modbus servers do:
    /// the console's compact plan reads a snapshot in 4 requests.
    Zero,
}

impl Default for SimConfig {
    fn default() -> Self {
        SimConfig {
            talos_listen: DEFAULT_TALOS_LISTEN.into(),
            modbus_listen: Some(DEFAULT_MODBUS_LISTEN.into()),
            talos: TalosServerConfig::default(),
            faults: NetworkFaults::default(),
            arm: Arm::default(),
            max_jog_speed: operator::MAX_JOG_LINEAR,
            positions: Vec::new(),
            unlisted_reads: UnlistedReads::default(),
        }
    }
}

impl SimConfig {
    /// Both servers on ephemeral loopback ports: for tests and the console's built-in arm.
    pub fn ephemeral() -> Self {
        SimConfig {
            talos_listen: "127.0.0.1:0".into(),
            modbus_listen: Some("127.0.0.1:0".into()),
            ..SimConfig::default()
        }
    }
}

/// Why the simulator could not start.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    #[error("cannot listen for {what} on {addr}: {}{hint}", crate::net::io_error_words(.source), hint = port_hint(.source))]
    Bind {
        what: &'static str,
        addr: String,
        source: std::io::Error,
    },
}

fn port_hint(e: &std::io::Error) -> &'static str {
    match e.kind() {
        std::io::ErrorKind::AddrInUse => {
            " (another program, perhaps another armjog sim, uses that port: choose another with --talos-listen or --modbus-listen)"
        }
        std::io::ErrorKind::PermissionDenied => " (ports below 1024 need privileges)",
        _ => "",
    }
}

/// A running simulator. Dropping it stops the servers.
pub struct Simulator {
    pub arm: SimArm,
    pub talos_addr: SocketAddr,
    /// Where the Kinova Modbus server listens, when it runs.
    pub modbus_addr: Option<SocketAddr>,
    faults: watch::Sender<NetworkFaults>,
    tasks: Vec<JoinHandle<()>>,
}

impl Simulator {
    pub async fn start(config: SimConfig) -> Result<Simulator, SimError> {
        let (talos_listener, talos_addr) = bind("the Talos operator", &config.talos_listen).await?;
        let modbus_listener = match &config.modbus_listen {
            Some(addr) => Some(bind("the Modbus server", addr).await?),
            None => None,
        };
        let mut operator = Operator::with_max_jog_linear(config.max_jog_speed);
        if !config.positions.is_empty() {
            let offered = config.positions.len();
            let restored = operator.restore(&config.arm, config.positions);
            tracing::info!(
                "the simulated operator starts with {restored} of {offered} remembered positions"
            );
        }
        let arm = SimArm::spawn(config.arm, operator);
        let (faults, faults_rx) = watch::channel(config.faults);
        let mut tasks = vec![tokio::spawn(talos_server::serve(
            talos_listener,
            arm.clone(),
            config.talos,
            faults_rx.clone(),
        ))];
        let modbus_addr = modbus_listener.map(|(listener, local)| {
            tasks.push(tokio::spawn(modbus_server::serve_on(
                listener,
                arm.clone(),
                faults_rx,
                config.unlisted_reads,
            )));
            local
        });
        Ok(Simulator {
            arm,
            talos_addr,
            modbus_addr,
            faults,
            tasks,
        })
    }

    /// Changes the injected network faults; they apply to the next frame.
    pub fn set_faults(&self, faults: NetworkFaults) {
        self.faults.send_replace(faults);
    }
}

impl Drop for Simulator {
    fn drop(&mut self) {
        for task in &self.tasks {
            task.abort();
        }
    }
}

/// A listener on `addr` and the address it got (the port chosen for `:0`).
async fn bind(what: &'static str, addr: &str) -> Result<(TcpListener, SocketAddr), SimError> {
    let bound = async {
        let listener = TcpListener::bind(addr).await?;
        let local = listener.local_addr()?;
        Ok((listener, local))
    };
    bound.await.map_err(|source| SimError::Bind {
        what,
        addr: addr.to_string(),
        source,
    })
}
