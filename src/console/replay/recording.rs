//! A recording read back as what the console's app took in: the session's facts, then each
//! input at its time (telemetry rebuilt, keys, the link, the command log), and what the screen
//! said (the message line, the fence). A file cut short plays up to its last good message.

use std::collections::BTreeSet;
use std::path::Path;
use std::time::Duration;

use serde_json::Value;

use super::telemetry;
use crate::console::app::{Input, KeyInput, Severity};
use crate::console::jog::KeyKind;
use crate::console::recorder::topics;
use crate::link::interface::{
    ArmError, ArmEvent, CommandKind, GuardStatus, LinkStatus, LogEntry, TelemetrySource,
};

/// The largest recording read: some days of jogging.
pub const RECORDING_LIMIT: u64 = 1 << 30;

/// What happened at one time of a recording.
#[derive(Debug, Clone, PartialEq)]
pub enum Happened {
    /// Fed to the app, as live.
    Input(Input),
    /// The message line as live showed it (`None`: cleared).
    Message(Option<(String, Severity)>),
    /// What the fence said of the tool.
    Fence(Option<String>),
}

/// A recording read back.
#[derive(Debug, Clone, Default)]
pub struct Recording {
    /// The `/session` message; `None` in a file from before it was written.
    pub session: Option<Value>,
    /// In time order: ns since the Unix epoch, and what happened.
    pub events: Vec<(u64, Happened)>,
    /// Channels read but not played (unknown topics, messages not as their schema says).
    pub skipped: BTreeSet<String>,
    /// Why the file ends before its end (cut short, damaged), in words.
    pub cut_short: Option<String>,
    pub first_ns: u64,
    pub last_ns: u64,
}

/// Why a file cannot be played at all.
#[derive(Debug, thiserror::Error)]
pub enum RecordingError {
    #[error("{0}: cannot read it: {1}")]
    Unreadable(String, std::io::Error),
    #[error("{0}: not an MCAP recording: {1}")]
    NotMcap(String, String),
    #[error("{0}: no armjog messages in it")]
    Empty(String),
}

/// A telemetry sample's parts: `/joint_states` comes with every sample and times it; the tool's
/// and the arm's come when they changed (the recorder leaves out repeats), else the last ones.
#[derive(Default)]
struct Sample {
    /// The sample being read: its time and joints.
    joints: Option<(u64, Value)>,
    tool: Option<Value>,
    arm: Option<Value>,
}

impl Recording {
    /// Reads `path`: refused when it is not a recording; played up to a damaged part.
    pub fn read(path: &Path) -> Result<Recording, RecordingError> {
        let shown = path.display().to_string();
        let bytes = crate::files::read_bytes_bounded(path, RECORDING_LIMIT)
            .map_err(|e| RecordingError::Unreadable(shown.clone(), e))?;
        Recording::parse(&bytes).map_err(|e| match e {
            RecordingError::NotMcap(_, why) => RecordingError::NotMcap(shown, why),
            RecordingError::Empty(_) => RecordingError::Empty(shown),
            other => other,
        })
    }

    /// [`Recording::read`] on the file's bytes.
    pub fn parse(bytes: &[u8]) -> Result<Recording, RecordingError> {
        let stream = messages(bytes).map_err(|e| RecordingError::NotMcap(String::new(), e))?;
        let mut recording = Recording::default();
        let mut sample = Sample::default();
        let mut read_any = false;
        for message in stream {
            let message = match message {
                Ok(message) => message,
                Err(e) if !read_any => {
                    return Err(RecordingError::NotMcap(String::new(), e));
                }
                Err(e) => {
                    recording.cut_short = Some(e);
                    break;
                }
            };
            read_any = true;
            let topic = message.channel.topic.as_str();
            let ns = message.log_time;
            let Ok(json) = serde_json::from_slice::<Value>(&message.data) else {
                recording.skipped.insert(format!("{topic} (not JSON)"));
                continue;
            };
            // A sample's messages come together: another of armjog's, or a later time, ends it
            // (a channel from elsewhere in between does not).
            let part = [
                &topics::JOINT_STATES,
                &topics::TOOL_STATE,
                &topics::ARM_STATE,
            ]
            .iter()
            .any(|t| t.topic == topic);
            let known = topics::ALL.iter().any(|t| t.topic == topic);
            let later = sample.joints.as_ref().is_some_and(|(at, _)| *at != ns);
            if (known && !part) || later || topic == topics::JOINT_STATES.topic {
                recording.end_sample(&mut sample);
            }
            match topic {
                t if t == topics::JOINT_STATES.topic => sample.joints = Some((ns, json)),
                t if t == topics::TOOL_STATE.topic => sample.tool = Some(json),
                t if t == topics::ARM_STATE.topic => sample.arm = Some(json),
                t if t == topics::SESSION.topic => recording.session = Some(json),
                t => {
                    if let Some(happened) = happened(t, &json) {
                        recording.events.push((ns, happened));
                    } else if !topics::ALL.iter().any(|known| known.topic == t) {
                        recording.skipped.insert(t.to_string());
                    }
                }
            }
        }
        recording.end_sample(&mut sample);
        if recording.events.is_empty() && recording.session.is_none() {
            return Err(RecordingError::Empty(String::new()));
        }
        // Written in time order by one thread; a sort keeps a hand-made file playable.
        recording.events.sort_by_key(|(ns, _)| *ns);
        recording.first_ns = recording.events.first().map_or(0, |(ns, _)| *ns);
        recording.last_ns = recording.events.last().map_or(0, |(ns, _)| *ns);
        Ok(recording)
    }

    /// The sample read so far plays (the tool's and arm's parts are kept for the next).
    fn end_sample(&mut self, sample: &mut Sample) {
        let Some((ns, joints)) = sample.joints.take() else {
            return;
        };
        let (Some(tool), Some(arm)) = (&sample.tool, &sample.arm) else {
            self.skipped.insert("telemetry samples not whole".into());
            return;
        };
        match telemetry::rebuild(&joints, tool, arm) {
            Some(t) => {
                let input = Input::Arm(ArmEvent::Telemetry(Box::new(t)));
                self.events.push((ns, Happened::Input(input)));
            }
            None => {
                self.skipped
                    .insert("telemetry not as its schema says".into());
            }
        }
    }
}

/// The messages of an MCAP file's bytes, each or why the file ends there; the first error ends
/// it. A reader that fails on damaged bytes by panicking (the `mcap` crate's arithmetic on a
/// chunk's sizes, in a debug build) ends it the same way, as damage.
pub fn messages(
    bytes: &[u8],
) -> Result<impl Iterator<Item = Result<mcap::Message<'_>, String>>, String> {
    let (sound, damage) = super::chunks::sound_prefix(bytes);
    let mut stream = mcap::MessageStream::new(&bytes[..sound]).map_err(|e| e.to_string())?;
    let mut damage = damage;
    let mut ended = false;
    Ok(std::iter::from_fn(move || {
        if ended {
            return None;
        }
        let next = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| stream.next()));
        let next = match next {
            Ok(Some(Ok(message))) => Ok(message),
            // Where the sound part ends, the damage is why.
            Ok(Some(Err(e))) => Err(damage.take().unwrap_or_else(|| e.to_string())),
            Ok(None) => Err(damage.take()?),
            Err(_) => Err("damaged: the MCAP reader could not make sense of a chunk".to_string()),
        };
        ended = next.is_err();
        Some(next)
    }))
}

/// What a message of a non-telemetry channel makes; `None` for one that plays no part (or is
/// not as its schema says).
fn happened(topic: &str, json: &Value) -> Option<Happened> {
    let text = |name: &str| json[name].as_str().map(str::to_string);
    let input = |event: ArmEvent| Some(Happened::Input(Input::Arm(event)));
    match topic {
        t if t == topics::KEYS.topic => {
            let key = text("key")?;
            let kind = match json["kind"].as_str()? {
                "press" => KeyKind::Press,
                "repeat" => KeyKind::Repeat,
                "release" => KeyKind::Release,
                _ => return None,
            };
            let mut chars = key.chars();
            let typed = match (chars.next(), chars.next()) {
                (Some(c), None) => Some(c),
                _ => None,
            };
            Some(Happened::Input(Input::Key(KeyInput {
                key: key.parse().ok()?,
                text: typed,
                kind,
            })))
        }
        t if t == topics::COMMAND_LOG.topic => {
            let entry = LogEntry {
                id: json["id"].as_u64().and_then(|id| u32::try_from(id).ok()),
                poll: json["poll"].as_bool().unwrap_or(false),
                count: json["count"]
                    .as_u64()
                    .and_then(|n| u32::try_from(n).ok())
                    .unwrap_or(1),
                name: text("name")?,
                outcome: text("outcome")?,
                ok: json["ok"].as_bool()?,
                latency: json["latency_ms"]
                    .as_f64()
                    .and_then(|ms| Duration::try_from_secs_f64(ms / 1000.0).ok()),
                ..LogEntry::default()
            };
            input(ArmEvent::Log(entry))
        }
        t if t == topics::LINK.topic => link(json),
        t if t == topics::SPEED.topic => {
            let percent = json["speed_percent"].as_u64()?;
            input(ArmEvent::Speed(u8::try_from(percent).ok()?))
        }
        t if t == topics::MESSAGE.topic => {
            let severity = match json["severity"].as_str() {
                Some("info") => Severity::Info,
                Some("warning") => Severity::Warning,
                Some("error") => Severity::Error,
                _ => return Some(Happened::Message(None)),
            };
            Some(Happened::Message(text("text").map(|t| (t, severity))))
        }
        t if t == topics::FENCE.topic => Some(Happened::Fence(text("verdict"))),
        t if t == topics::LOG.topic => match json["message"].as_str()? {
            crate::console::recorder::FOCUS_LOST => Some(Happened::Input(Input::FocusLost)),
            _ => None,
        },
        _ => None,
    }
}

/// A `/link` message: the link's state, its telemetry, the guard or the round trip.
fn link(json: &Value) -> Option<Happened> {
    let text = json["text"].as_str().unwrap_or_default().to_string();
    let event = if let Some(status) = json["status"].as_str() {
        ArmEvent::Status(match status {
            "connecting" => LinkStatus::Connecting,
            "up" => LinkStatus::Up { description: text },
            "down" => LinkStatus::Down { reason: text },
            _ => return None,
        })
    } else if let Some(source) = json["telemetry_source"].as_str() {
        ArmEvent::TelemetrySource(match source {
            "modbus" => TelemetrySource::Modbus,
            "talos_hardware" => TelemetrySource::TalosHardware,
            "none" => TelemetrySource::None,
            _ => return None,
        })
    } else if let Some(guard) = json["guard"].as_str() {
        ArmEvent::Guard(match guard {
            "starting" => GuardStatus::Starting,
            "ready" => GuardStatus::Ready {
                pid: json["guard_pid"]
                    .as_u64()
                    .and_then(|p| u32::try_from(p).ok())
                    .unwrap_or(0),
            },
            "down" => GuardStatus::Down { reason: text },
            _ => return None,
        })
    } else if let Some(stop) = json["stop"].as_str() {
        match stop {
            "confirmed" => ArmEvent::StopConfirmed,
            _ => ArmEvent::StopUnconfirmed { reason: text },
        }
    } else if let Some(kind) = json["failed"].as_str() {
        ArmEvent::Failed {
            command: CommandKind::from_label(kind)?,
            error: ArmError::Replayed(text),
        }
    } else if let Some(notice) = json["notice"].as_str() {
        ArmEvent::Notice(notice.to_string())
    } else {
        let ms = json["latency_ms"].as_f64()?;
        ArmEvent::Latency(Duration::try_from_secs_f64(ms / 1000.0).ok()?)
    };
    Some(Happened::Input(Input::Arm(event)))
}
