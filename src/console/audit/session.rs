//! The audit log of one console session, at the runtime's edge: inputs, effects and the app's
//! state after each input become records stamped with the wall clock, written off the loop.

use std::time::{Duration, SystemTime};

use super::{AuditDeriver, AuditEvent, AuditLog, AuditRecord};
use crate::console::app::{App, AppConfig, Input};
use crate::console::positions::PositionBook;
use crate::link::interface::{ArmCommand, ArmEvent};

pub struct AuditSession {
    deriver: AuditDeriver,
    log: AuditLog,
    /// The last input's commands, and when it was handled: recorded at the event loop's next
    /// turn ([`AuditSession::record_handled`]), so a key's burst ends with its frames.
    sent: Vec<ArmCommand>,
    handled_at: Option<SystemTime>,
}

impl AuditSession {
    /// Starts the writer for `dir` and records the session's start on `arm`.
    /// `profile`: the name of the arm profile the console was opened with, if any.
    pub fn start(
        config: &AppConfig,
        target: String,
        profile: Option<String>,
        dir: Option<std::path::PathBuf>,
    ) -> Self {
        let mut session = AuditSession {
            deriver: AuditDeriver::new(
                config.max_jog_speed,
                config.frames,
                config.positions_on_operator,
            ),
            log: AuditLog::start(dir),
            sent: Vec::new(),
            handled_at: None,
        };
        session.write(vec![AuditRecord::new(
            SystemTime::now(),
            match profile {
                Some(arm) => AuditEvent::SessionStart {
                    arm,
                    target: Some(target),
                },
                None => AuditEvent::SessionStart {
                    arm: target,
                    target: None,
                },
            },
        )]);
        session
    }

    fn write(&mut self, records: Vec<AuditRecord>) {
        for record in records {
            self.log.record(record);
        }
    }

    /// Before the app sees `input`: what the driver reported, and the book as loaded.
    pub fn input(&mut self, input: &Input) {
        match input {
            Input::Arm(event) => {
                let records = self.deriver.arm_event(event, SystemTime::now());
                self.write(records);
            }
            Input::PositionsLoaded(Ok(book)) => self.deriver.book_loaded(book),
            _ => {}
        }
    }

    /// A command the app sent to the driver: recorded with the input that sent it.
    pub fn command(&mut self, command: ArmCommand) {
        self.sent.push(command);
    }

    /// The input is handled: its commands, and what the app's state after it says (the link
    /// gone stale or fresh, a motion the cap watch stopped), are recorded at the event loop's
    /// next turn, stamped now. Until then the app does not change: no input comes between.
    pub fn handled(&mut self) {
        self.handled_at = Some(SystemTime::now());
    }

    /// Records what the last input sent and left, if not yet recorded.
    pub fn record_handled(&mut self, app: &App) {
        let Some(at) = self.handled_at.take() else {
            return;
        };
        for command in std::mem::take(&mut self.sent) {
            let records = self.deriver.command(
                &command,
                app.positions(),
                app.selected_name(),
                app.frame(),
                at,
            );
            self.write(records);
        }
        let records = self.deriver.link_stale(app.link_stale(), at);
        self.write(records);
        let records = self.deriver.cap_stops(app.cap_watch().stops(), at);
        self.write(records);
    }

    /// A book the app is saving (over Modbus, what the technician saved or deleted).
    pub fn book_saved(&mut self, book: &PositionBook) {
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
        self.write(vec![AuditRecord::new(
            SystemTime::now(),
            AuditEvent::SessionEnd,
        )]);
        self.log.finish(within).await;
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
