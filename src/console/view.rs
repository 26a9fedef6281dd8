//! What one frame shows, built once per frame from the app (oxker's `FrameData`): the panels
//! draw from it alone, and the drawing thread gets it instead of a copy of the whole app.
//!
//! It holds plain values, worked out once (ages, the motion shown) and cut to what a screen can
//! show (the part of the book around the selection, the newest log lines): building it costs
//! the same whatever the book's or the log's size.

use std::collections::VecDeque;
use std::sync::Arc;
use std::time::Duration;

use super::app::{
    App, BookState, HistorySeries, MotionShown, NearLimit, Overlay, Severity, Step, TrailShade,
    near_limits, near_singularity,
};
use super::jog::{ReleaseMode, RepeatTiming};
use super::keymap::Keymap;
use super::positions::PositionBook;
use crate::kortex::{ReferenceFrame, Telemetry};
use crate::link::interface::{GuardStatus, LinkStatus, LogEntry, TelemetrySource};

/// Everything the panels draw. Compared with the last one drawn to skip a frame that would
/// show the same (see [`super::pacing`]): every field must take part in `PartialEq`.
#[derive(Debug, Clone, PartialEq)]
pub struct View {
    /// The terminal's size as the app last heard it.
    pub size: (u16, u16),
    /// Shared with the app: the keymap never changes during a session.
    pub keymap: Arc<Keymap>,
    pub release_mode: ReleaseMode,
    /// The measured auto-repeat timing (auto-repeat fallback).
    pub repeat_timing: RepeatTiming,
    /// The joint a single-joint jog moves (1 to 7).
    pub joint: u8,
    pub motion: MotionShown,
    pub link: LinkStatus,
    /// How long the link has been silent, when that makes it stale.
    pub link_stale: Option<Duration>,
    pub latency: Option<Duration>,
    pub guard: Option<GuardStatus>,
    pub speed: Option<u8>,
    /// Cartesian jog speed cap, m/s.
    pub max_jog_speed: f64,
    /// Whether the telemetry lets the console watch the cap (`None` until the driver says).
    pub cap_watched: Option<bool>,
    /// Orientation jog rate at 100 %, deg/s.
    pub max_angular_jog_speed: f64,
    /// Reference frames apply (Modbus jogging).
    pub frames: bool,
    /// The arm is the built-in simulator.
    pub simulated: bool,
    pub frame: ReferenceFrame,
    pub step: Step,
    pub telemetry: Option<Telemetry>,
    pub telemetry_source: TelemetrySource,
    /// The telemetry's age, when it is old enough to be drawn as stale.
    pub telemetry_stale: Option<Duration>,
    pub positions_on_operator: bool,
    pub book_state: BookState,
    /// The part of the book a screen can show: the selection and up to a screen's height of
    /// names either side.
    pub positions: PositionBook,
    /// The selection's row in `positions`.
    pub selected: usize,
    /// The newest log entries, as many as a screen can show (oldest first).
    pub log: VecDeque<LogEntry>,
    /// The log shows frames in hex.
    pub hex: bool,
    pub message: Option<(String, Severity)>,
    pub overlay: Overlay,
    /// Saving the current pose can work on this link (the footer offers it).
    pub can_save: bool,
    /// The link carries an orientation jog (the footer offers the turn keys).
    pub can_turn: bool,
    /// Going to a saved position can work on this link (the footer offers it).
    pub can_go_to: bool,
    /// The help overlay's first shown line.
    pub help_scroll: usize,
    /// The last 30 s of telemetry (history panel).
    pub history: HistorySeries,
    /// Limited joints within 5 degrees of a limit, the nearest first.
    pub near_limits: Vec<NearLimit>,
    /// The estimated condition number of the Jacobian at the reported joint angles (Gen3
    /// model) when above the warning threshold; `None` below it or without telemetry.
    pub near_singularity: Option<f64>,
    /// The tool point's path over the last 10 s (base frame, m) with each point's shade, oldest
    /// first: the arm view's trail. At most [`TRAIL_CAPACITY`](super::app::TRAIL_CAPACITY)
    /// points; a still arm's is a few.
    pub trail: Vec<(TrailShade, [f64; 3])>,
}

impl View {
    pub fn new(app: &App) -> View {
        // No panel is taller than the terminal: `rows` entries either side of the selection fill
        // any of them the same way the whole book would, and no log panel shows more than
        // `rows` entries.
        let rows = usize::from(app.size().1);
        let book = app.positions();
        let selected = app.selected();
        let start = selected.saturating_sub(rows);
        let log = app.log();
        let config = app.config();
        View {
            size: app.size(),
            keymap: app.shared_keymap(),
            release_mode: app.jog().mode(),
            repeat_timing: app.jog().timing(),
            joint: app.jog().joint(),
            motion: app.motion_shown(),
            link: app.link().clone(),
            link_stale: app.link_stale(),
            latency: app.latency(),
            guard: app.guard().cloned(),
            speed: app.speed(),
            max_jog_speed: config.max_jog_speed,
            cap_watched: app.cap_watched(),
            max_angular_jog_speed: f64::from(crate::link::driver::MAX_ANGULAR_JOG_SPEED),
            frames: config.frames,
            simulated: config.simulated,
            frame: app.frame(),
            step: app.step(),
            telemetry: app.telemetry().cloned(),
            telemetry_source: app.telemetry_source(),
            telemetry_stale: app.telemetry_stale(),
            positions_on_operator: config.positions_on_operator,
            book_state: app.book_state().clone(),
            positions: book.window(start, 2 * rows + 1),
            selected: selected - start,
            log: log
                .iter()
                .skip(log.len().saturating_sub(rows))
                .cloned()
                .collect(),
            hex: app.hex(),
            message: app
                .message()
                .map(|(text, severity)| (text.to_string(), severity)),
            overlay: app.overlay().clone(),
            can_save: app.can_save_position(),
            can_turn: app.can_turn(),
            can_go_to: app.can_go_to(),
            help_scroll: app.help_scroll(),
            history: app
                .now()
                .map(|now| app.history().series(now))
                .unwrap_or_default(),
            near_limits: app.telemetry().map(near_limits).unwrap_or_default(),
            near_singularity: app.telemetry().and_then(near_singularity),
            trail: app.trail_shaded(),
        }
    }
}

impl View {
    /// Whether `self` shows the same as `shown` but for what ticks over while the arm is at
    /// rest: the measured latency, the count and latency of the telemetry polls' log line, and
    /// temperatures (they creep for minutes after a start, in steps far below the 0.1 °C
    /// shown). The frame pacer draws those at a slower rate (see [`super::pacing`]).
    pub fn differs_only_in_background(&self, shown: &View) -> bool {
        if self.log.len() != shown.log.len() {
            return false;
        }
        let mut same = self.clone();
        same.latency = shown.latency;
        if let (Some(now), Some(was)) = (same.telemetry.as_mut(), shown.telemetry.as_ref()) {
            now.arm.cpu_temperature = was.arm.cpu_temperature;
            now.arm.ambient_temperature = was.arm.ambient_temperature;
            for (joint, before) in now.joints.iter_mut().zip(&was.joints) {
                joint.temperature = before.temperature;
            }
        }
        for (entry, was) in same.log.iter_mut().zip(&shown.log) {
            if entry.poll && was.poll && entry.name == was.name && entry.outcome == was.outcome {
                entry.count = was.count;
                entry.latency = was.latency;
            }
        }
        same == *shown
    }
}
