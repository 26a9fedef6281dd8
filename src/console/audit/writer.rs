//! Appends audit records to the file of each record's UTC date on a thread of its own. A failed
//! write is reported once and never stops the console; the next record tries again. Records are
//! held for [`HAND_OVER_AFTER`] before the writer is woken, so it does not run before a STOP's
//! receiver on a busy core; they are handed over on drop too, so a panic keeps them.

use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use tokio::sync::mpsc::{UnboundedReceiver, UnboundedSender, unbounded_channel};

use super::AuditRecord;

/// How long records wait on the loop's thread before the writer is woken for them.
pub const HAND_OVER_AFTER: Duration = Duration::from_millis(20);

/// The console's handle on the writer thread.
pub struct AuditLog {
    records: Option<mpsc::Sender<AuditRecord>>,
    /// Recorded and not yet handed to the writer.
    held: Vec<AuditRecord>,
    /// When `held` is due at the writer.
    hand_over_at: Option<Instant>,
    thread: Option<std::thread::JoinHandle<()>>,
    /// The first write failure (and the first after each recovery), in words.
    pub errors: UnboundedReceiver<String>,
}

impl AuditLog {
    /// Starts the writer for `dir` (`None`: no directory could be named; reported at once).
    pub fn start(dir: Option<PathBuf>) -> AuditLog {
        let (records, incoming) = mpsc::channel::<AuditRecord>();
        let (error_tx, errors) = unbounded_channel();
        let thread = std::thread::Builder::new()
            .name("audit-writer".into())
            .spawn(move || write_all(dir, incoming, error_tx))
            .inspect_err(|e| tracing::warn!("audit log off: cannot start its writer thread: {e}"))
            .ok();
        AuditLog {
            records: thread.as_ref().map(|_| records),
            held: Vec::new(),
            hand_over_at: None,
            thread,
            errors,
        }
    }

    /// Queues a record for the writer within [`HAND_OVER_AFTER`]; never waits for the disk.
    pub fn record(&mut self, record: AuditRecord) {
        if self.records.is_none() {
            return;
        }
        self.held.push(record);
        if self.hand_over_at.is_none() {
            self.hand_over_at = Some(Instant::now() + HAND_OVER_AFTER);
        }
    }

    /// When the held records are due at the writer ([`Self::hand_over`]), if any are held.
    pub fn hand_over_at(&self) -> Option<Instant> {
        self.hand_over_at
    }

    /// Gives the held records to the writer (this wakes its thread).
    pub fn hand_over(&mut self) {
        self.hand_over_at = None;
        let held = std::mem::take(&mut self.held);
        if let Some(records) = &self.records {
            for record in held {
                // A writer that ended has already said why.
                let _ = records.send(record);
            }
        }
    }

    /// Writes what is queued and ends the writer, waiting at most `within`.
    pub async fn finish(&mut self, within: Duration) {
        self.hand_over();
        self.records = None;
        let Some(thread) = self.thread.take() else {
            return;
        };
        let until = tokio::time::Instant::now() + within;
        while !thread.is_finished() {
            if tokio::time::Instant::now() >= until {
                tracing::warn!("audit log: the last records were not written within {within:?}");
                return;
            }
            tokio::time::sleep(Duration::from_millis(10)).await;
        }
        let _ = thread.join();
    }
}

impl Drop for AuditLog {
    fn drop(&mut self) {
        self.hand_over();
    }
}

/// The open file and the date it is for.
struct DayFile {
    name: String,
    file: File,
}

fn write_all(
    dir: Option<PathBuf>,
    incoming: mpsc::Receiver<AuditRecord>,
    errors: UnboundedSender<String>,
) {
    let Some(dir) = dir else {
        let reason = "audit log off: no directory for it (set ARMJOG_STATE_DIR)".to_string();
        tracing::warn!("{reason}");
        let _ = errors.send(reason);
        return;
    };
    let mut current: Option<DayFile> = None;
    let mut failing = false;
    for record in incoming {
        match append(&dir, &mut current, &record) {
            Ok(()) => failing = false,
            Err(e) => {
                // Opened again for the next record: a disk that was full may have room.
                current = None;
                if !failing {
                    let reason = format!(
                        "audit log not written to {}: {e}",
                        dir.join(record.file_name()).display()
                    );
                    tracing::warn!("{reason}");
                    let _ = errors.send(reason);
                    failing = true;
                }
            }
        }
    }
}

fn append(dir: &Path, current: &mut Option<DayFile>, record: &AuditRecord) -> std::io::Result<()> {
    let name = record.file_name();
    let file = match current {
        Some(day) if day.name == name => &mut day.file,
        _ => {
            std::fs::create_dir_all(dir)?;
            let file = OpenOptions::new()
                .create(true)
                .append(true)
                .open(dir.join(&name))?;
            &mut current.insert(DayFile { name, file }).file
        }
    };
    let mut line = record.json_line();
    line.push('\n');
    // One write per line: each line is whole on disk even if the process dies after it.
    file.write_all(line.as_bytes())
}
