//! The flight recorder: every console session written as an MCAP file (zstd chunks, JSON messages
//! with JSON Schemas; `topics.rs`) beside the audit files. The event loop never waits for it: what
//! it hands over goes through a bounded queue to the recorder's thread, which makes the JSON and
//! writes it; a full queue drops the message and counts it, and the count is recorded. Chunks are
//! closed at least once a second, so a console killed outright leaves a file readable up to its
//! last second; a clean end writes the summary and the index.

mod messages;
pub mod topics;

use std::collections::BTreeMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError, SyncSender, TrySendError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant, SystemTime};

pub use messages::{FOCUS_LOST, Recorded};

use crate::console::app::{AppConfig, Input, Severity};
use crate::console::jog::ReleaseMode;
use crate::link::interface::{ArmCommand, ArmEvent};

/// The queue between the event loop and the recorder's thread: some seconds of telemetry.
pub const QUEUE: usize = 1024;
/// The recorder's thread sleeps this long after each batch: the queue holds what comes meanwhile
/// (some 10 messages at 30 Hz telemetry, far under [`QUEUE`]).
const NAP: Duration = Duration::from_millis(100);
/// Chunks are closed at least this often: what a killed console's file is readable up to.
pub const FLUSH_EVERY: Duration = Duration::from_secs(1);
/// A held channel's message that says what its last one said is left out, up to this long: a
/// reader holds the last value, and playback takes the last one with each `/joint_states`.
pub const SAME_HELD_NS: u64 = 1_000_000_000;
/// Telemetry polls are folded into one command-log message for at most this long (ns).
const POLLS_FOLDED_NS: u64 = 1_000_000_000;
/// The link's round trip is recorded at most this often (ns): the status bar's figure.
const LATENCY_EVERY_NS: u64 = 250_000_000;
/// Recordings older than this many days are removed when a console starts.
pub const KEPT_DAYS: i64 = 14;

/// The event loop's end of the recorder. Dropping it ends the recording (the summary written).
pub struct Recorder {
    queue: Option<SyncSender<(u64, Recorded)>>,
    dropped: Arc<AtomicU64>,
    thread: Option<JoinHandle<()>>,
    path: PathBuf,
    said: Option<String>,
    fence: Option<String>,
    /// What this input brought, each with when it was seen, handed over after its frames.
    pending: Vec<(u64, Recorded)>,
    /// The time of what is handed next, when a test sets it; else the wall clock.
    clock: Option<u64>,
    /// The session's cap (mm/s), which `/speed` messages carry, once [`Recorder::session`] said it.
    cap_mm_s: Option<f64>,
    /// Telemetry polls not yet written: the first's time, the last entry, how many.
    polls: Option<(u64, crate::link::interface::LogEntry, u32)>,
    latency_at: Option<u64>,
}

/// Nanoseconds since the Unix epoch, as MCAP readers expect a log time.
fn now_ns() -> u64 {
    SystemTime::now()
        .duration_since(SystemTime::UNIX_EPOCH)
        .map_or(0, |d| u64::try_from(d.as_nanos()).unwrap_or(u64::MAX))
}

impl Recorder {
    /// Starts recording into `path` (its folder made), with a queue of `queue` messages.
    pub fn start(path: PathBuf, queue: usize) -> std::io::Result<Recorder> {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir)?;
        }
        let file = File::create(&path)?;
        let writer = mcap::WriteOptions::new()
            .compression(Some(mcap::Compression::Zstd))
            .create(BufWriter::new(file))
            .map_err(std::io::Error::other)?;
        let (queue, received) = mpsc::sync_channel(queue);
        let dropped = Arc::new(AtomicU64::new(0));
        let counted = dropped.clone();
        let thread = std::thread::Builder::new()
            .name("armjog-recorder".into())
            .spawn(move || record(writer, &received, &counted))?;
        Ok(Recorder {
            queue: Some(queue),
            dropped,
            thread: Some(thread),
            path,
            said: None,
            fence: None,
            pending: Vec::new(),
            clock: None,
            cap_mm_s: None,
            polls: None,
            latency_at: None,
        })
    }

    /// The file being written.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Messages dropped so far (the queue was full).
    pub fn dropped(&self) -> u64 {
        self.dropped.load(Ordering::Relaxed)
    }

    /// What is handed from now on was seen at `ns` (ns since the Unix epoch), not at the wall
    /// clock's time: for tests on a fake clock.
    pub fn set_clock(&mut self, ns: u64) {
        self.clock = Some(ns);
    }

    fn now(&self) -> u64 {
        self.clock.unwrap_or_else(now_ns)
    }

    /// Kept, with when it was seen, until [`Recorder::hand_over`].
    fn hand(&mut self, recorded: Recorded) {
        let now = self.now();
        self.pending.push((now, recorded));
    }

    /// The session's facts, first in the file: what `armjog replay` starts the panels with.
    pub fn session(&mut self, config: &AppConfig, link: &str) {
        let cap_mm_s = config.max_jog_speed * 1000.0;
        self.cap_mm_s = Some(cap_mm_s);
        let arm = match (&config.arm_name, config.simulated) {
            (Some(name), _) => name.clone(),
            (None, true) => "sim".to_string(),
            (None, false) => String::new(),
        };
        let release_mode = match config.release_mode {
            ReleaseMode::Reported => "reported",
            ReleaseMode::AutoRepeat => "auto-repeat",
        };
        let facts = serde_json::json!({
            "armjog": env!("CARGO_PKG_VERSION"),
            "arm": arm,
            "link": link,
            "simulated": config.simulated,
            "release_mode": release_mode,
            "refresh_ms": u64::try_from(config.refresh.as_millis()).unwrap_or(u64::MAX).max(1),
            "cap_mm_s": cap_mm_s,
            "joint_jog_deg_s": config.joint_jog_speed,
            "frames": config.frames,
            "positions_on_operator": config.positions_on_operator,
            "fence": config.fence.is_some(),
        });
        self.hand(Recorded::Session(facts));
    }

    /// Hands what was kept to the recorder's thread: after the input's frames are out, so that
    /// the queue (a lock, maybe a wake-up) never comes before a frame. A full queue drops.
    pub fn hand_over(&mut self) {
        let Some(queue) = &self.queue else { return };
        for message in self.pending.drain(..) {
            match queue.try_send(message) {
                Ok(()) | Err(TrySendError::Disconnected(_)) => {}
                Err(TrySendError::Full(_)) => {
                    self.dropped.fetch_add(1, Ordering::Relaxed);
                }
            }
        }
    }

    /// An input the app is about to handle: telemetry, keys, the link's reports.
    pub fn input(&mut self, input: &Input) {
        let now = self.now();
        // Polls folded for a second are written, whatever comes.
        if self
            .polls
            .as_ref()
            .is_some_and(|(at, ..)| now >= at.saturating_add(POLLS_FOLDED_NS))
        {
            self.write_polls();
        }
        match input {
            Input::Arm(ArmEvent::Latency(latency))
                if self
                    .latency_at
                    .is_none_or(|at| now >= at.saturating_add(LATENCY_EVERY_NS)) =>
            {
                self.latency_at = Some(now);
                self.hand(Recorded::Latency(*latency));
            }
            Input::Arm(ArmEvent::Latency(_)) => {}
            Input::Arm(ArmEvent::Speed(percent)) => {
                let cap_mm_s = self.cap_mm_s;
                self.hand(Recorded::Speed {
                    percent: *percent,
                    cap_mm_s,
                });
            }
            Input::Arm(ArmEvent::Log(entry)) if entry.poll => self.poll(entry),
            Input::Arm(_) | Input::Key(_) | Input::FocusLost | Input::Signal(_) => {
                // A line after folded polls comes after them, as in the panel.
                if matches!(input, Input::Arm(ArmEvent::Log(_))) {
                    self.write_polls();
                }
                self.hand(Recorded::Input(input.clone()));
            }
            _ => {}
        }
    }

    /// A telemetry poll's line: folded into the polls not yet written when it says the same.
    fn poll(&mut self, entry: &crate::link::interface::LogEntry) {
        let count = entry.count.max(1);
        if let Some((_, last, folded)) = self.polls.as_mut()
            && last.name == entry.name
            && last.outcome == entry.outcome
        {
            *folded = folded.saturating_add(count);
            last.clone_from(entry);
            return;
        }
        self.write_polls();
        self.polls = Some((self.now(), entry.clone(), count));
    }

    fn write_polls(&mut self) {
        if let Some((_, entry, count)) = self.polls.take() {
            self.hand(Recorded::Polls(entry, count));
        }
    }

    /// What the fence says of the tool after an input: recorded when it changed.
    pub fn fence(&mut self, verdict: Option<String>) {
        if verdict != self.fence {
            self.fence.clone_from(&verdict);
            self.hand(Recorded::Fence(verdict));
        }
    }

    /// A command going to the arm.
    pub fn command(&mut self, command: &ArmCommand) {
        self.hand(Recorded::Command(command.clone()));
    }

    /// The console's message line after an input: recorded when it changed.
    pub fn said(&mut self, message: Option<(&str, Severity)>) {
        let Some((text, severity)) = message else {
            if self.said.take().is_some() {
                self.hand(Recorded::Said(None));
            }
            return;
        };
        if self.said.as_deref() != Some(text) {
            self.said = Some(text.to_string());
            self.hand(Recorded::Said(Some((text.to_string(), severity))));
        }
    }
}

impl Drop for Recorder {
    fn drop(&mut self) {
        // The queue closed: the thread writes what is left, the count, the summary, and ends.
        self.write_polls();
        self.hand_over();
        self.queue.take();
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// The recorder's thread: writes what comes, closes a chunk each [`FLUSH_EVERY`].
fn record(
    mut writer: mcap::Writer<BufWriter<File>>,
    received: &Receiver<(u64, Recorded)>,
    dropped: &AtomicU64,
) {
    let Ok(channels) = add_channels(&mut writer) else {
        tracing::error!("recorder: the channels could not be written");
        return;
    };
    let mut sequence = 0u32;
    let mut links_at = 0u64;
    // The latest log time written: the dropped count is stamped with it, so that the file's
    // times never go backwards (what came during a nap carries earlier times than the clock's).
    let written_ns = std::cell::Cell::new(0u64);
    // Per held topic: what it last said (without its time) and when.
    let mut held: BTreeMap<&'static str, (String, u64)> = BTreeMap::new();
    let mut write = |writer: &mut mcap::Writer<BufWriter<File>>, ns: u64, recorded: &Recorded| {
        let with_links = ns >= links_at.saturating_add(messages::TRANSFORMS_EVERY_NS);
        let recorded_messages = messages::messages(recorded, ns, with_links);
        if recorded_messages
            .iter()
            .any(|(t, _)| t.topic == topics::TRANSFORMS.topic)
        {
            links_at = ns;
        }
        for (topic, message) in recorded_messages {
            let Some(&(_, id)) = channels.iter().find(|(t, _)| t == &topic.topic) else {
                continue;
            };
            let data = message.to_string();
            if topic.held {
                // A message with a time says the same when all but its time is the same.
                let timed =
                    message.get("timestamp").is_some() || message.get("transforms").is_some();
                let content = match timed {
                    true => std::borrow::Cow::Owned(messages::content(&message)),
                    false => std::borrow::Cow::Borrowed(data.as_str()),
                };
                match held.get(topic.topic) {
                    Some((same, at))
                        if same == content.as_ref() && ns < at.saturating_add(SAME_HELD_NS) =>
                    {
                        continue;
                    }
                    _ => {
                        held.insert(topic.topic, (content.into_owned(), ns));
                    }
                }
            }
            written_ns.set(written_ns.get().max(ns));
            sequence = sequence.wrapping_add(1);
            let header = mcap::records::MessageHeader {
                channel_id: id,
                sequence,
                log_time: ns,
                publish_time: ns,
            };
            if let Err(e) = writer.write_to_known_channel(&header, data.as_bytes()) {
                tracing::warn!("recorder: a message not written: {e}");
            }
        }
    };
    let mut flushed_at = Instant::now();
    let mut dropped_written = 0;
    loop {
        let wait = FLUSH_EVERY.saturating_sub(flushed_at.elapsed());
        match received.recv_timeout(wait) {
            Ok((ns, recorded)) => {
                write(&mut writer, ns, &recorded);
                // What came meanwhile, then a nap: a few wake-ups a second, not one a sample.
                for (ns, recorded) in received.try_iter() {
                    write(&mut writer, ns, &recorded);
                }
                std::thread::sleep(NAP);
            }
            Err(RecvTimeoutError::Timeout) => {}
            Err(RecvTimeoutError::Disconnected) => break,
        }
        let count = dropped.load(Ordering::Relaxed);
        if count != dropped_written {
            dropped_written = count;
            write(&mut writer, written_ns.get(), &Recorded::Dropped(count));
        }
        if flushed_at.elapsed() >= FLUSH_EVERY {
            flushed_at = Instant::now();
            if let Err(e) = writer.flush() {
                tracing::warn!("recorder: a chunk not flushed: {e}");
            }
        }
    }
    let end = now_ns().max(written_ns.get());
    write(
        &mut writer,
        end,
        &Recorded::Dropped(dropped.load(Ordering::Relaxed)),
    );
    if let Err(e) = writer.finish() {
        tracing::warn!("recorder: the summary not written: {e}");
    }
}

/// Each channel with its schema; their topics and ids.
fn add_channels(
    writer: &mut mcap::Writer<BufWriter<File>>,
) -> mcap::McapResult<Vec<(&'static str, u16)>> {
    let mut ids = Vec::new();
    for topic in topics::ALL {
        let schema = writer.add_schema(topic.schema, "jsonschema", topic.json_schema.as_bytes())?;
        let id = writer.add_channel(schema, topic.topic, "json", &BTreeMap::new())?;
        ids.push((topic.topic, id));
    }
    Ok(ids)
}

/// The file a session starting at `at` on `arm` records into, in `dir`:
/// `armjog-2026-12-06T18-03-05Z-cell3.mcap` (`sim` for the built-in simulator, `arm` unnamed).
pub fn file_for(dir: &Path, at: SystemTime, arm: &str) -> PathBuf {
    let at = time::OffsetDateTime::from(at);
    let name = format!(
        "armjog-{:04}-{:02}-{:02}T{:02}-{:02}-{:02}Z-{arm}.mcap",
        at.year(),
        u8::from(at.month()),
        at.day(),
        at.hour(),
        at.minute(),
        at.second()
    );
    dir.join(name)
}

/// Removes the recordings in `dir` dated more than [`KEPT_DAYS`] before `today` (by the date in
/// their names; other files are left alone).
pub fn prune(dir: &Path, today: time::Date) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(date) = name.to_str().and_then(recording_date) else {
            continue;
        };
        if (today - date).whole_days() > KEPT_DAYS {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

/// The date in a recording's name (`armjog-YYYY-MM-DDT...mcap`).
fn recording_date(name: &str) -> Option<time::Date> {
    let rest = name.strip_prefix("armjog-")?;
    if !name.ends_with(".mcap") {
        return None;
    }
    let date = rest.get(..10)?;
    let format = time::macros::format_description!("[year]-[month]-[day]");
    time::Date::parse(date, &format).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_carry_the_start_time_and_the_arm_and_old_ones_are_pruned() {
        let at = SystemTime::UNIX_EPOCH + Duration::from_secs(1_796_580_185);
        let path = file_for(Path::new("/x"), at, "cell3");
        assert_eq!(path, Path::new("/x/armjog-2026-12-06T18-03-05Z-cell3.mcap"));
        let date = |s| recording_date(s);
        assert_eq!(
            date("armjog-2026-11-21T00-00-00Z-sim.mcap"),
            time::Date::from_calendar_date(2026, time::Month::November, 21).ok()
        );
        assert_eq!(date("audit-2026-11-21.jsonl"), None);
        assert_eq!(date("armjog-2026-11-21.log"), None);
        let dir = tempfile::tempdir().expect("dir");
        for name in [
            "armjog-2026-11-21T00-00-00Z-sim.mcap",
            "armjog-2026-11-22T00-00-00Z-sim.mcap",
            "audit-2026-11-01.jsonl",
        ] {
            std::fs::write(dir.path().join(name), b"").expect("file");
        }
        let today = time::Date::from_calendar_date(2026, time::Month::December, 6).expect("date");
        prune(dir.path(), today);
        let mut left: Vec<String> = std::fs::read_dir(dir.path())
            .expect("dir")
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect();
        left.sort();
        // 15 days old goes; 14 stays; not a recording stays.
        assert_eq!(
            left,
            [
                "armjog-2026-11-22T00-00-00Z-sim.mcap",
                "audit-2026-11-01.jsonl"
            ]
        );
    }
}
