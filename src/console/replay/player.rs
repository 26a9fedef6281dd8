//! Playback: the console's own app fed a recording's inputs at their times, on a clock of its
//! own, with no link: what the app sends goes nowhere. The panels draw from the app's view as
//! live; the message line and the fence's words are the recording's (what the technician saw).
//! Pure: the runtime hands it the time that passed and the keys, and draws its view.

use std::sync::Arc;
use std::time::{Duration, Instant};

use serde_json::Value;

use super::recording::{Happened, Recording};
use crate::console::app::{App, AppConfig, Input, KeyInput, Overlay, Severity};
use crate::console::jog::{KeyKind, ReleaseMode};
use crate::console::keymap::Keymap;
use crate::console::positions::PositionBook;
use crate::console::view::View;

/// The playback speeds `+` and `-` step through.
pub const SPEEDS: [f64; 7] = [0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0];
const NORMAL_SPEED: usize = 2;
/// A copy of the app is kept this often (recording time), so that a step back replays seconds,
/// not the whole session.
const CHECKPOINT_EVERY_NS: u64 = 10_000_000_000;
/// Ticks handled at most per step: a deadline that never moves cannot hang playback.
const MOST_TICKS: usize = 10_000;

/// What a key asks of the runtime.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Control {
    Continue,
    Quit,
}

/// The app and what the recording says at one point of it.
#[derive(Clone)]
struct Point {
    app: App,
    /// The next event to play.
    next: usize,
    at_ns: u64,
    message: Option<(String, Severity)>,
    fence: Option<String>,
}

pub struct Player {
    recording: Recording,
    size: (u16, u16),
    /// The app's clock at the recording's first message.
    base: Instant,
    point: Point,
    checkpoints: Vec<Point>,
    speed: usize,
    paused: bool,
    /// What of the file is not played (cut short, channels skipped), said while the message
    /// line is free.
    notice: Option<String>,
}

/// The app's settings from the recording's `/session` message (the defaults where it has none).
pub fn config_of(session: Option<&Value>) -> AppConfig {
    let empty = Value::Null;
    let s = session.unwrap_or(&empty);
    let flag = |name: &str| s[name].as_bool().unwrap_or(false);
    // Built in: it parses (a unit test of the keymaps says so).
    let keymap = Keymap::builtin("default").expect("the built-in keymap");
    AppConfig {
        keymap: Arc::new(keymap),
        release_mode: match s["release_mode"].as_str() {
            Some("auto-repeat") => ReleaseMode::AutoRepeat,
            _ => ReleaseMode::Reported,
        },
        refresh: Duration::from_millis(s["refresh_ms"].as_u64().unwrap_or(100).max(1)),
        positions_on_operator: flag("positions_on_operator"),
        max_jog_speed: s["cap_mm_s"]
            .as_f64()
            .filter(|v| v.is_finite() && *v > 0.0)
            .map_or(0.25, |mm| mm / 1000.0),
        joint_jog_speed: s["joint_jog_deg_s"]
            .as_f64()
            .filter(|v| v.is_finite() && *v > 0.0)
            .map_or(crate::link::speed::JOINT_JOG_SPEED, |v| v as f32),
        frames: flag("frames"),
        simulated: flag("simulated"),
        arm_name: s["arm"]
            .as_str()
            .filter(|a| !a.is_empty() && *a != "sim")
            .map(str::to_string),
        home_action: None,
        fence: None,
        config_file: None,
        new_profile: Vec::new(),
        recording_off: false,
    }
}

impl Player {
    /// Playback of `recording` on a `size` terminal, at its start, playing at ×1.
    pub fn new(recording: Recording, size: (u16, u16), base: Instant) -> Player {
        let config = config_of(recording.session.as_ref());
        let mut app = App::new(config, PositionBook::new());
        app.handle(
            Input::Resize {
                width: size.0,
                height: size.1,
            },
            base,
        );
        let point = Point {
            app,
            next: 0,
            at_ns: recording.first_ns,
            message: None,
            fence: None,
        };
        let mut player = Player {
            checkpoints: vec![point.clone()],
            recording,
            size,
            base,
            point,
            speed: NORMAL_SPEED,
            paused: false,
            notice: None,
        };
        player.notice = notice_of(&player.recording);
        player.seek(player.recording.first_ns);
        player
    }

    /// Where playback is: ns since the Unix epoch.
    pub fn at_ns(&self) -> u64 {
        self.point.at_ns
    }

    pub fn at_end(&self) -> bool {
        self.point.at_ns >= self.recording.last_ns
    }

    /// The playback speed, ×.
    pub fn speed(&self) -> f64 {
        SPEEDS[self.speed]
    }

    fn instant(&self, ns: u64) -> Instant {
        self.base + Duration::from_nanos(ns.saturating_sub(self.recording.first_ns))
    }

    /// Time passed on the runtime's clock: playback moves on by it times the speed.
    pub fn play(&mut self, elapsed: Duration) {
        if self.paused || self.at_end() {
            return;
        }
        let step = elapsed.as_secs_f64() * self.speed();
        let ns = self.point.at_ns.saturating_add((step * 1e9) as u64);
        self.seek(ns);
        if self.at_end() {
            self.paused = true;
        }
    }

    /// Playback moved to `ns` (within the recording): forwards by playing what lies between,
    /// backwards from the last copy of the app before it.
    pub fn seek(&mut self, ns: u64) {
        let ns = ns.clamp(self.recording.first_ns, self.recording.last_ns);
        if ns < self.point.at_ns {
            let kept = self.checkpoints.iter().rev().find(|c| c.at_ns <= ns);
            if let Some(kept) = kept {
                self.point = kept.clone();
            }
        }
        while let Some((event_ns, _)) = self.recording.events.get(self.point.next) {
            if *event_ns > ns {
                break;
            }
            let event_ns = *event_ns;
            self.ticks_until(event_ns);
            self.point.at_ns = event_ns;
            self.play_event();
            let last = self.checkpoints.last().map_or(0, |c| c.at_ns);
            if event_ns >= last.saturating_add(CHECKPOINT_EVERY_NS)
                && self
                    .checkpoints
                    .last()
                    .is_some_and(|c| c.next < self.point.next)
            {
                self.checkpoints.push(self.point.clone());
            }
        }
        self.ticks_until(ns);
        self.point.at_ns = ns;
    }

    /// The app's deadlines up to `ns`, as the runtime's timer would have fired them.
    fn ticks_until(&mut self, ns: u64) {
        let until = self.instant(ns);
        for _ in 0..MOST_TICKS {
            let Some(deadline) = self.point.app.next_deadline() else {
                return;
            };
            if deadline > until {
                return;
            }
            self.point.app.handle(Input::Tick, deadline);
            if self.point.app.next_deadline() == Some(deadline) {
                return;
            }
        }
    }

    fn play_event(&mut self) {
        let Some((ns, happened)) = self.recording.events.get(self.point.next) else {
            return;
        };
        let now = self.instant(*ns);
        match happened.clone() {
            // What the app sends goes nowhere: no link is open.
            Happened::Input(input) => {
                let _ = self.point.app.handle(input, now);
            }
            Happened::Message(message) => self.point.message = message,
            Happened::Fence(verdict) => self.point.fence = verdict,
        }
        self.point.next += 1;
    }

    /// A key of the technician's: playback's own, never the app's.
    pub fn on_key(&mut self, key: &KeyInput) -> Control {
        if key.kind == KeyKind::Release {
            return Control::Continue;
        }
        let name = key.key.to_string();
        let second = 1_000_000_000u64;
        let at = self.point.at_ns;
        match name.as_str() {
            "q" | "esc" | "ctrl+c" => return Control::Quit,
            // At the end, space plays it again from the start.
            "space" if self.at_end() => {
                self.seek(self.recording.first_ns);
                self.paused = false;
            }
            "space" => self.paused = !self.paused,
            "right" => self.seek(at.saturating_add(second)),
            "left" => self.seek(at.saturating_sub(second)),
            "shift+right" => self.seek(at.saturating_add(10 * second)),
            "shift+left" => self.seek(at.saturating_sub(10 * second)),
            "+" | "shift++" | "=" | "kp+" => self.speed = (self.speed + 1).min(SPEEDS.len() - 1),
            "-" | "kp-" => self.speed = self.speed.saturating_sub(1),
            "home" => self.seek(self.recording.first_ns),
            "end" => self.seek(self.recording.last_ns),
            _ => {}
        }
        Control::Continue
    }

    /// The terminal's new size.
    pub fn on_resize(&mut self, width: u16, height: u16) {
        self.size = (width, height);
        let now = self.instant(self.point.at_ns);
        self.point.app.handle(Input::Resize { width, height }, now);
    }

    /// The status bar's replay badge: `REPLAY 12:03:41.250 ×1`, paused or at the end.
    pub fn status(&self) -> String {
        let speed = match self.speed() {
            s if s >= 1.0 => format!("{s:.0}"),
            s => format!("{s}"),
        };
        let state = match (self.at_end(), self.paused) {
            (true, _) => " END",
            (false, true) => " PAUSED",
            (false, false) => "",
        };
        format!("REPLAY {} ×{speed}{state}", clock_text(self.point.at_ns))
    }

    /// What the panels draw now: the app's view, with the recording's message line and fence
    /// words, no dialog, and the replay badge.
    pub fn view(&self) -> View {
        let mut view = self.point.app.view();
        view.session.replay = Some(self.status());
        view.session.recording_off = false;
        view.screen.message = match (&self.point.message, &self.notice) {
            (Some(message), _) => Some(message.clone()),
            (None, Some(notice)) => Some((notice.clone(), Severity::Warning)),
            (None, None) => None,
        };
        view.screen.overlay = Overlay::None;
        view.arm.fence.clone_from(&self.point.fence);
        view.screen.size = self.size;
        view
    }
}

/// What of `recording` is not played, in words; `None` when it plays whole.
fn notice_of(recording: &Recording) -> Option<String> {
    let mut parts = Vec::new();
    if let Some(why) = &recording.cut_short {
        let end = clock_text(recording.last_ns);
        parts.push(format!("recording cut short ({why}): played up to {end}"));
    }
    if !recording.skipped.is_empty() {
        let skipped: Vec<&str> = recording.skipped.iter().map(String::as_str).collect();
        parts.push(format!("skipped: {}", skipped.join(", ")));
    }
    (!parts.is_empty()).then(|| parts.join("; "))
}

/// `12:03:41.250`, UTC (the recording's name and the audit's times are UTC too).
pub fn clock_text(ns: u64) -> String {
    let at = time::OffsetDateTime::from_unix_timestamp_nanos(i128::from(ns))
        .unwrap_or(time::OffsetDateTime::UNIX_EPOCH);
    format!(
        "{:02}:{:02}:{:02}.{:03}",
        at.hour(),
        at.minute(),
        at.second(),
        at.millisecond()
    )
}
