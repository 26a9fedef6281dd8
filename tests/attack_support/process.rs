//! `armjog sim` in its own process, for what only a process shows: its memory, its descriptors,
//! its limits.

use std::io::{BufRead, BufReader};
use std::net::SocketAddr;
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::mpsc;
use std::time::Duration;

/// `armjog sim` on ephemeral ports, killed on drop.
pub struct SimProcess {
    child: Child,
    /// Where the sim writes `armjog-sim.DATE.log`.
    pub log_dir: PathBuf,
    pub talos: SocketAddr,
    pub modbus: SocketAddr,
}

impl SimProcess {
    /// Starts `armjog sim`, with its open-file limit lowered to `fd_limit` if given (through
    /// the shell's `ulimit`, which then execs the binary: the child is the sim itself).
    pub fn spawn(fd_limit: Option<u32>) -> SimProcess {
        Self::spawn_with(fd_limit, &[])
    }

    /// [`SimProcess::spawn`] with more of `armjog sim`'s options (`--one-client`, ...).
    pub fn spawn_with(fd_limit: Option<u32>, options: &[&str]) -> SimProcess {
        static SPAWNED: AtomicU32 = AtomicU32::new(0);
        let log_dir = std::env::temp_dir().join(format!(
            "armjog-attack-{}-{}",
            std::process::id(),
            SPAWNED.fetch_add(1, Ordering::Relaxed)
        ));
        let _ = std::fs::remove_dir_all(&log_dir);
        let mut args = vec![
            "sim",
            "--talos-listen",
            "127.0.0.1:0",
            "--modbus-listen",
            "127.0.0.1:0",
        ];
        args.extend_from_slice(options);
        let mut command = match fd_limit {
            Some(limit) => {
                let mut c = Command::new("sh");
                c.arg("-c")
                    .arg(format!("ulimit -n {limit} && exec \"$0\" \"$@\""))
                    .arg(env!("CARGO_BIN_EXE_armjog"))
                    .args(&args);
                c
            }
            None => {
                let mut c = Command::new(env!("CARGO_BIN_EXE_armjog"));
                c.args(&args);
                c
            }
        };
        let mut child = command
            .env("ARMJOG_LOG_DIR", &log_dir)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("spawn armjog sim");
        let stdout = child.stdout.take().expect("piped stdout");
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines().map_while(Result::ok) {
                if tx.send(line).is_err() {
                    break;
                }
            }
        });
        let mut talos = None;
        let mut modbus = None;
        while talos.is_none() || modbus.is_none() {
            let line = rx
                .recv_timeout(Duration::from_secs(20))
                .expect("armjog sim prints its addresses");
            let address = || {
                line.split_whitespace()
                    .nth(2)
                    .and_then(|a| a.parse::<SocketAddr>().ok())
            };
            if line.contains("talos operator") {
                talos = address();
            } else if line.contains("kinova modbus") {
                modbus = address();
            }
        }
        SimProcess {
            child,
            log_dir,
            talos: talos.expect("talos address"),
            modbus: modbus.expect("modbus address"),
        }
    }

    /// Waits (up to 10 s: the log is written in the background) for a log line containing
    /// `needle`.
    pub async fn logged(&self, needle: &str) -> bool {
        for _ in 0..100 {
            let log = crate::log_files::read_logs(&self.log_dir, "armjog-sim");
            if log.contains(needle) {
                return true;
            }
            tokio::time::sleep(Duration::from_millis(100)).await;
        }
        false
    }

    pub fn pid(&self) -> u32 {
        self.child.id()
    }

    pub fn rss_kb(&self) -> u64 {
        let status = std::fs::read_to_string(format!("/proc/{}/status", self.pid()))
            .expect("the sim process lives");
        status
            .lines()
            .find_map(|l| l.strip_prefix("VmRSS:"))
            .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
            .expect("VmRSS in /proc/PID/status")
    }

    pub fn open_fds(&self) -> usize {
        std::fs::read_dir(format!("/proc/{}/fd", self.pid()))
            .expect("the sim process lives")
            .count()
    }

    /// Waits (up to 10 s) for the server to finish closing connections: the descriptor count
    /// falls back to `baseline`. Returns the last count seen.
    pub async fn settle_fds(&self, baseline: usize) -> usize {
        let mut fds = self.open_fds();
        for _ in 0..100 {
            if fds <= baseline {
                break;
            }
            tokio::time::sleep(Duration::from_millis(100)).await;
            fds = self.open_fds();
        }
        fds
    }

    pub fn alive(&mut self) -> bool {
        matches!(self.child.try_wait(), Ok(None))
    }
}

impl Drop for SimProcess {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
