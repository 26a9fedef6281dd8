//! `armjog replay FILE`: the session played in the console's panels (`console::replay`).
//! `armjog replay --events FILE`: its events (keys, commands, stops and refusals, faults, the
//! link) one line each with their times, for a bug report; `--json` for scripts. A file cut
//! short or damaged is read up to its last good message, and says so.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use clap::Args;
use serde_json::Value;

use super::Outcome;
use crate::console::recorder::topics;

use crate::console::replay::recording::RECORDING_LIMIT;

#[derive(Debug, Args)]
pub struct ReplayArgs {
    /// The recording (`armjog-….mcap`, beside the audit files).
    #[arg(value_name = "FILE")]
    pub file: PathBuf,
    /// Print the session's events one line each instead of playing the session in the panels.
    #[arg(long)]
    pub events: bool,
    /// With --events: one JSON object per line (`ts`, `topic` and the message's fields).
    #[arg(long, requires = "events")]
    pub json: bool,
}

pub async fn run(args: &ReplayArgs) -> Outcome {
    if !args.events {
        return match play(args.file.clone()).await {
            Ok(()) => Outcome::printed(Vec::new()),
            Err(e) => Outcome::error(e, 1),
        };
    }
    let shown = args.file.display();
    let bytes = match crate::files::read_bytes_bounded(&args.file, RECORDING_LIMIT) {
        Ok(bytes) => bytes,
        Err(e) => return Outcome::error(format!("{shown}: cannot read it: {e}"), 1),
    };
    let stream = match crate::console::replay::recording::messages(&bytes) {
        Ok(stream) => stream,
        Err(e) => return Outcome::error(format!("{shown}: not an MCAP recording: {e}"), 1),
    };
    let mut lines = Vec::new();
    let mut faults = Value::Array(Vec::new());
    let mut skipped = std::collections::BTreeSet::new();
    let mut cut_short = None;
    let mut read_any = false;
    for message in stream {
        let message = match message {
            Ok(message) => message,
            // Nothing read: not a recording (or its very start is gone).
            Err(e) if !read_any => {
                return Outcome::error(format!("{shown}: not an MCAP recording: {e}"), 1);
            }
            Err(e) => {
                cut_short = Some(e);
                break;
            }
        };
        read_any = true;
        let topic = message.channel.topic.as_str();
        if !topics::ALL.iter().any(|t| t.topic == topic) {
            skipped.insert(topic.to_string());
            continue;
        }
        let Ok(json) = serde_json::from_slice::<Value>(&message.data) else {
            skipped.insert(format!("{topic} (not JSON)"));
            continue;
        };
        let Some(text) = event_text(topic, &json, &mut faults) else {
            continue;
        };
        let at = time_text(message.log_time);
        lines.push(if args.json {
            let mut object = serde_json::Map::new();
            object.insert("ts".into(), Value::String(at));
            object.insert("topic".into(), Value::String(topic.into()));
            if let Value::Object(fields) = json {
                object.extend(fields);
            }
            Value::Object(object).to_string()
        } else {
            crate::text::shown(&format!("{at}  {text}")).into_owned()
        });
    }
    let mut notes = Vec::new();
    if !skipped.is_empty() {
        let list: Vec<_> = skipped.into_iter().collect();
        notes.push(format!(
            "skipped channels this armjog does not know: {}",
            list.join(", ")
        ));
    }
    if let Some(why) = cut_short {
        notes.push(format!(
            "{shown}: read up to its last good message, then: {why} (cut short or damaged)"
        ));
    }
    Outcome {
        stdout: lines,
        stderr: (!notes.is_empty()).then(|| notes.join("\n")),
        exit_code: 0,
    }
}

/// Plays `file` on a thread of its own (the terminal's loop blocks); a signal ends it as `q`
/// does, the terminal given back.
async fn play(file: PathBuf) -> Result<(), String> {
    use tokio::signal::unix::SignalKind;
    let quit = Arc::new(AtomicBool::new(false));
    let told = quit.clone();
    let mut signals = crate::console::signals::forward(&[
        (SignalKind::interrupt(), ()),
        (SignalKind::terminate(), ()),
        (SignalKind::hangup(), ()),
    ])
    .map_err(|e| format!("signals: {e}"))?;
    let mut played = tokio::task::spawn_blocking(move || crate::console::replay::run(&file, &told));
    let ended = tokio::select! {
        ended = &mut played => ended,
        _ = signals.recv() => {
            quit.store(true, Ordering::Relaxed);
            played.await
        }
    };
    ended.map_err(|e| format!("playback ended early: {e}"))?
}

/// `2026-12-06 19:08:47.368 UTC`.
fn time_text(ns: u64) -> String {
    let at = time::OffsetDateTime::UNIX_EPOCH + time::Duration::nanoseconds(ns as i64);
    format!(
        "{:04}-{:02}-{:02} {:02}:{:02}:{:02}.{:03} UTC",
        at.year(),
        u8::from(at.month()),
        at.day(),
        at.hour(),
        at.minute(),
        at.second(),
        at.millisecond()
    )
}

/// The line a message makes, if it is an event (telemetry is not, but for new faults).
fn event_text(topic: &str, json: &Value, faults: &mut Value) -> Option<String> {
    let s = |v: &Value| v.as_str().unwrap_or_default().to_string();
    Some(match topic {
        "/keys" => format!("key      {} {}", s(&json["key"]), s(&json["kind"])),
        "/commands" => match s(&json["detail"]) {
            detail if detail.is_empty() => format!("command  {}", s(&json["command"])),
            detail => format!("command  {} ({detail})", s(&json["command"])),
        },
        // Telemetry polls are the link's routine: only a failed one is an event.
        "/commands/log" if json["poll"] == true && json["ok"] == true => return None,
        "/commands/log" => format!("link     {}: {}", s(&json["name"]), s(&json["outcome"])),
        "/speed" => match json["cap_mm_s"].as_f64() {
            Some(cap) => format!("speed    {} % of the {cap} mm/s cap", json["speed_percent"]),
            None => format!("speed    {} %", json["speed_percent"]),
        },
        "/fence" => match json["verdict"].as_str() {
            Some(verdict) => format!("fence    {verdict}"),
            None => "fence    clear".to_string(),
        },
        "/session" => format!(
            "session  armjog {} on {} ({}), cap {} mm/s, {}",
            s(&json["armjog"]),
            s(&json["link"]),
            if json["simulated"] == true {
                "simulated arm"
            } else {
                "real arm"
            },
            json["cap_mm_s"],
            s(&json["release_mode"])
        ),
        "/log" => {
            let level = match json["level"].as_u64() {
                Some(4 | 5) => "error",
                Some(3) => "warning",
                _ => "info",
            };
            format!("{level:<8} {}", s(&json["message"]))
        }
        "/arm/state" if json["faults"] != *faults => {
            *faults = json["faults"].clone();
            format!("faults   {}", json["faults"])
        }
        "/recorder" if json["dropped"].as_u64().is_some_and(|n| n > 0) => {
            format!("recorder {} messages dropped (queue full)", json["dropped"])
        }
        _ => return None,
    })
}
