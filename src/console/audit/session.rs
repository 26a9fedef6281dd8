//! One console session's audit, at the runtime's edge, stamped with the wall clock.

use std::time::{Duration, SystemTime};

use super::deriver::go_to_name;
use super::{AuditDeriver, AuditEvent, AuditLog, AuditRecord};
use crate::console::app::{App, AppConfig, Input};
use crate::console::positions::PositionBook;
use crate::kortex::ReferenceFrame;
use crate::link::interface::{ArmCommand, ArmEvent};

pub struct AuditSession {
    deriver: AuditDeriver,
    log: AuditLog,
    /// The commands the input being handled has sent so far.
    sent: Vec<ArmCommand>,
    /// The last input and its commands, not yet recorded: recorded at the loop's next turn
    /// ([`AuditSession::record_handled`]) so a key's frames do not wait for them.
    handled: Option<Handled>,
    handled_sent: Vec<ArmCommand>,
}

/// What the app's state after an input says, taken as it is handled, so a panic before the next
/// turn still records it (on drop).
struct Handled {
    at: SystemTime,
    frame: ReferenceFrame,
    /// The book's names for where the commands go (by their index), where one is known.
    go_to_names: Vec<(usize, String)>,
    link_stale: Option<Duration>,
    /// The cap watch's stops, and the reason of the last one when it is new.
    cap_stops: (u64, Option<String>),
}

impl AuditSession {
    /// Starts the writer for `dir` and records the start on `arm` (`profile`: the arm profile),
    /// naming the session's flight `recording`.
    pub fn start(
        config: &AppConfig,
        target: String,
        profile: Option<String>,
        dir: Option<std::path::PathBuf>,
        recording: Option<&std::path::Path>,
    ) -> Self {
        let mut session = AuditSession {
            deriver: AuditDeriver::new(
                config.max_jog_speed,
                config.frames,
                config.positions_on_operator,
            ),
            log: AuditLog::start(dir),
            sent: Vec::new(),
            handled: None,
            handled_sent: Vec::new(),
        };
        let (arm, target) = match profile {
            Some(arm) => (arm, Some(target)),
            None => (target, None),
        };
        let recording = recording.map(|p| p.display().to_string());
        session.write_now(AuditEvent::SessionStart {
            arm,
            target,
            recording,
        });
        session
    }

    fn write(&mut self, records: Vec<AuditRecord>) {
        for record in records {
            self.log.record(record);
        }
    }

    /// A fence taught in the console, about to be written into its profile.
    pub fn fence_changed(&mut self, change: &crate::console::app::FenceChange) {
        self.record_handled();
        self.write_now(AuditEvent::FenceChanged {
            change: change.change.clone(),
            arm: change.arm.clone(),
            file: change.file.display().to_string(),
        });
    }

    fn write_now(&mut self, event: AuditEvent) {
        self.log.record(AuditRecord::new(SystemTime::now(), event));
    }

    /// Before the app sees `input`: the driver's reports and the loaded book.
    pub fn input(&mut self, input: &Input) {
        match input {
            Input::Arm(event) => {
                self.record_handled();
                let records = self.deriver.arm_event(event, SystemTime::now());
                self.write(records);
            }
            Input::PositionsLoaded(Ok(book)) => {
                self.record_handled();
                self.deriver.book_loaded(book);
            }
            _ => {}
        }
    }

    /// A command the app sent to the driver: recorded with the input that sent it.
    pub fn command(&mut self, command: ArmCommand) {
        self.sent.push(command);
    }

    /// The input is handled: recorded at the loop's next turn, after the input before.
    pub fn handled(&mut self, app: &App) {
        self.record_handled();
        std::mem::swap(&mut self.sent, &mut self.handled_sent);
        let (stops, reason) = app.cap_watch().stops();
        let new_stop = stops != self.deriver.cap_stops_recorded();
        let named = self
            .handled_sent
            .iter()
            .enumerate()
            .filter_map(|(i, command)| {
                go_to_name(command, app.positions(), app.selected_name()).map(|name| (i, name))
            });
        self.handled = Some(Handled {
            at: SystemTime::now(),
            frame: app.frame(),
            go_to_names: named.collect(),
            link_stale: app.link_stale(),
            cap_stops: (stops, reason.filter(|_| new_stop).map(str::to_string)),
        });
    }

    /// Records what the last input handled sent and left, if not yet recorded.
    pub fn record_handled(&mut self) {
        let Some(handled) = self.handled.take() else {
            return;
        };
        let mut names = handled.go_to_names.into_iter().peekable();
        // Kept, with its capacity, for the next input's commands.
        let mut sent = std::mem::take(&mut self.handled_sent);
        for (i, command) in sent.iter().enumerate() {
            let name = names.next_if(|(at, _)| *at == i).map(|(_, name)| name);
            let records = self
                .deriver
                .command_named(command, name, handled.frame, handled.at);
            self.write(records);
        }
        sent.clear();
        self.handled_sent = sent;
        let records = self.deriver.link_stale(handled.link_stale, handled.at);
        self.write(records);
        let (stops, reason) = handled.cap_stops;
        let records = self
            .deriver
            .cap_stops((stops, reason.as_deref()), handled.at);
        self.write(records);
    }

    /// A book being saved: what changed from `known` (merged-in positions are not saves).
    pub fn book_saved(&mut self, book: &PositionBook, known: &PositionBook) {
        self.record_handled();
        self.deriver.book_loaded(known);
        let records = self.deriver.book_saved(book, SystemTime::now());
        self.write(records);
    }

    /// The next write failure to show, in words (cancel safe).
    pub async fn next_error(&mut self) -> Option<String> {
        self.log.errors.recv().await
    }

    /// When the records held since the last hand-over are due at the writer.
    pub fn hand_over_at(&self) -> Option<std::time::Instant> {
        self.log.hand_over_at()
    }

    /// Wakes the writer for the records held (see [`AuditLog::hand_over`]).
    pub fn hand_over(&mut self) {
        self.log.hand_over();
    }

    /// Records the session's end and writes everything queued (at most `within`).
    pub async fn finish(mut self, within: Duration) {
        self.record_handled();
        self.write_now(AuditEvent::SessionEnd);
        self.log.finish(within).await;
    }
}

impl Drop for AuditSession {
    /// A panic between an input and the next turn: its records are still made.
    fn drop(&mut self) {
        self.record_handled();
    }
}

/// The write failure as a command log line, so it stays in view after the message goes.
pub fn failure_log_line(reason: String) -> ArmEvent {
    ArmEvent::Log(crate::link::interface::LogEntry {
        name: "audit log".into(),
        outcome: reason,
        ok: false,
        count: 1,
        ..Default::default()
    })
}
