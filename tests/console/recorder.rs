//! The flight recorder on its own: a session's inputs and commands handed to it, the file read
//! back with the `mcap` crate's reader: every channel has a JSON Schema, every message is JSON
//! with the fields its schema requires, log times in nanoseconds since the Unix epoch, in order.

use std::collections::{BTreeMap, BTreeSet};
use std::time::{Duration, SystemTime};

use armjog::console::app::{Input, KeyInput, Severity};
use armjog::console::jog::{JogMotion, KeyKind};
use armjog::console::recorder::{QUEUE, Recorder, topics};
use armjog::link::driver::hw_telemetry;
use armjog::link::interface::{ArmCommand, ArmEvent, LinkStatus};
use armjog::sim::arm_model::Arm;
use armjog::sim::telemetry::{actuator_feedback, arm_state};
use serde_json::Value;

fn telemetry() -> Input {
    moved(0.0)
}

/// The arm at home with J1 turned `deg`.
fn moved(deg: f32) -> Input {
    let snapshot = Arm::default().snapshot();
    let feedback: Vec<_> = (1..=7).map(|j| actuator_feedback(&snapshot, j)).collect();
    let mut telemetry = hw_telemetry::telemetry(&arm_state(&snapshot), &feedback);
    telemetry.joints[0].position += deg;
    Input::Arm(ArmEvent::Telemetry(Box::new(telemetry)))
}

fn key(kind: KeyKind) -> Input {
    Input::Key(KeyInput {
        key: "w".parse().expect("w"),
        text: Some('w'),
        kind,
    })
}

/// Every message of the file at `path`: topic, schema name and encoding, log time, JSON.
fn read(path: &std::path::Path) -> Vec<(String, String, String, u64, Value)> {
    let bytes = std::fs::read(path).expect("the recording");
    mcap::MessageStream::new(&bytes)
        .expect("an MCAP file")
        .map(|m| {
            let m = m.expect("a message");
            let schema = m.channel.schema.as_ref().expect("a schema");
            let json: Value = serde_json::from_slice(&m.data).expect("JSON");
            (
                m.channel.topic.clone(),
                schema.name.clone(),
                schema.encoding.clone(),
                m.log_time,
                json,
            )
        })
        .collect()
}

#[test]
fn a_session_reads_back_as_json_on_schema_d_channels_in_time_order() {
    let dir = tempfile::tempdir().expect("a folder");
    let path = dir.path().join("session.mcap");
    let started = SystemTime::now();
    let mut recorder = Recorder::start(path.clone(), QUEUE).expect("recording");
    let up = LinkStatus::Up {
        description: "talos 127.0.0.1:61616".into(),
    };
    recorder.input(&Input::Arm(ArmEvent::Status(up)));
    recorder.input(&telemetry());
    recorder.input(&key(KeyKind::Press));
    recorder.command(&ArmCommand::Jog(JogMotion::Cartesian { x: 1, y: 0, z: 0 }));
    recorder.input(&telemetry());
    recorder.input(&key(KeyKind::Release));
    recorder.command(&ArmCommand::Stop);
    recorder.said(Some((
        "refused: the arm reports in fault",
        Severity::Warning,
    )));
    // The same line again is not recorded twice.
    recorder.said(Some((
        "refused: the arm reports in fault",
        Severity::Warning,
    )));
    drop(recorder);

    let messages = read(&path);
    let now = SystemTime::now();
    let ns = |t: SystemTime| {
        t.duration_since(SystemTime::UNIX_EPOCH)
            .expect("after 1970")
            .as_nanos() as u64
    };
    let mut last = 0;
    let mut counts: BTreeMap<String, usize> = BTreeMap::new();
    for (topic, schema, encoding, log_time, json) in &messages {
        assert_eq!(encoding, "jsonschema", "{topic}");
        let declared = topics::ALL
            .iter()
            .find(|t| t.topic == topic)
            .expect("a known topic");
        assert_eq!(schema, declared.schema);
        let wanted: Value = serde_json::from_str(declared.json_schema).expect("a JSON schema");
        let required = wanted["required"].as_array().cloned().unwrap_or_default();
        for field in &required {
            let field = field.as_str().expect("a name");
            assert!(json.get(field).is_some(), "{topic}: no {field} in {json}");
        }
        assert!(
            *log_time >= ns(started) && *log_time <= ns(now),
            "{topic} at {log_time}"
        );
        assert!(*log_time >= last, "in order");
        last = *log_time;
        *counts.entry(topic.clone()).or_default() += 1;
    }
    let seen: BTreeSet<&str> = counts.keys().map(String::as_str).collect();
    for topic in [
        "/joint_states",
        "/tool/pose",
        "/tool/state",
        "/tf",
        "/arm/state",
        "/keys",
        "/commands",
        "/log",
        "/console/message",
        "/link",
        "/recorder",
    ] {
        assert!(seen.contains(topic), "{topic} missing: {seen:?}");
    }
    // Every sample, the same or not: `armjog replay` plays them at their times.
    assert_eq!(counts["/joint_states"], 2);
    assert_eq!(counts["/keys"], 2);
    assert_eq!(counts["/commands"], 2);
    // The link coming up and the refusal, once.
    assert_eq!(counts["/log"], 2);
    let keys: Vec<&Value> = messages
        .iter()
        .filter(|m| m.0 == "/keys")
        .map(|m| &m.4)
        .collect();
    assert_eq!(keys[0]["kind"], "press");
    assert_eq!(keys[1]["kind"], "release");
    let stop = messages
        .iter()
        .filter(|m| m.0 == "/commands")
        .map(|m| &m.4)
        .nth(1)
        .expect("the stop");
    assert_eq!(
        (stop["command"].as_str(), stop["class"].as_str()),
        (Some("stop"), Some("stop"))
    );
    // Home's tool point, as Foxglove reads a pose: metres, a unit quaternion.
    let pose = &messages
        .iter()
        .find(|m| m.0 == "/tool/pose")
        .expect("a pose")
        .4["pose"];
    assert!(
        (pose["position"]["z"].as_f64().expect("z") - 0.4338).abs() < 0.001,
        "{pose}"
    );
    let q = &pose["orientation"];
    let norm: f64 = ["x", "y", "z", "w"]
        .iter()
        .map(|k| q[k].as_f64().expect("a number").powi(2))
        .sum();
    assert!((norm - 1.0).abs() < 1e-9);
    // The chain base → link1 … link7 → tool.
    let tf = &messages
        .iter()
        .find(|m| m.0 == "/tf")
        .expect("transforms")
        .4["transforms"];
    assert_eq!(tf.as_array().expect("an array").len(), 8);
    assert_eq!(tf[7]["child_frame_id"], "tool");
    let dropped = messages
        .iter()
        .rev()
        .find(|m| m.0 == "/recorder")
        .expect("the count");
    assert_eq!(dropped.4["dropped"], 0);
}

#[test]
fn a_full_queue_drops_and_counts_and_the_count_is_recorded() {
    let dir = tempfile::tempdir().expect("a folder");
    let path = dir.path().join("flood.mcap");
    let mut recorder = Recorder::start(path.clone(), 1).expect("recording");
    // Each report different: none is left out as the same as the last. Handed over after each,
    // as the event loop does after each input.
    for i in 0..2000 {
        recorder.input(&moved(i as f32 * 0.01));
        recorder.hand_over();
    }
    let dropped = recorder.dropped();
    assert!(dropped > 0, "a queue of one kept up with 2000 reports");
    drop(recorder);
    let messages = read(&path);
    let recorded = messages.iter().filter(|m| m.0 == "/joint_states").count() as u64;
    assert_eq!(recorded + dropped, 2000);
    let last = messages
        .iter()
        .rev()
        .find(|m| m.0 == "/recorder")
        .expect("the count");
    assert_eq!(last.4["dropped"], dropped);
}

#[test]
fn chunks_are_closed_each_second_so_an_unfinished_file_reads_up_to_then() {
    let dir = tempfile::tempdir().expect("a folder");
    let path = dir.path().join("killed.mcap");
    let mut recorder = Recorder::start(path.clone(), QUEUE).expect("recording");
    recorder.input(&telemetry());
    recorder.hand_over();
    std::thread::sleep(Duration::from_millis(1500));
    // Read while still recording, as after a SIGKILL: no summary yet, the first chunk closed.
    let bytes = std::fs::read(&path).expect("the file so far");
    let readable = mcap::MessageStream::new(&bytes)
        .expect("an MCAP start")
        .take_while(Result::is_ok)
        .count();
    assert!(readable >= 5, "{readable} messages readable before the end");
    drop(recorder);
}

#[test]
fn the_status_bar_says_rec_off_when_the_session_is_not_recorded() {
    use armjog::console::app::{App, AppConfig};
    use armjog::console::positions::PositionBook;
    use armjog::console::view::View;
    let line = |recording_off: bool| {
        let config = AppConfig {
            recording_off,
            ..crate::app_support::config()
        };
        let mut app = App::new(config, PositionBook::new());
        let up = LinkStatus::Up {
            description: "test".into(),
        };
        app.handle(Input::Arm(ArmEvent::Status(up)), std::time::Instant::now());
        crate::event_loop::status_line_0(&View::new(&app))
    };
    assert!(line(true).contains(" REC OFF "), "{}", line(true));
    assert!(!line(false).contains("REC"), "{}", line(false));
}

#[test]
fn the_fence_s_words_are_recorded_on_each_change() {
    let dir = tempfile::tempdir().expect("a folder");
    let path = dir.path().join("fence.mcap");
    let mut recorder = Recorder::start(path.clone(), QUEUE).expect("recording");
    recorder.fence(None);
    recorder.fence(Some("SLOWED: table 34 mm".into()));
    recorder.fence(Some("SLOWED: table 34 mm".into()));
    recorder.fence(Some("AT FENCE: table".into()));
    recorder.fence(None);
    drop(recorder);
    let verdicts: Vec<Value> = read(&path)
        .into_iter()
        .filter(|m| m.0 == "/fence")
        .map(|m| m.4["verdict"].clone())
        .collect();
    // Nothing at first (clear is where a session starts), then each change once.
    assert_eq!(
        verdicts,
        [
            Value::from("SLOWED: table 34 mm"),
            Value::from("AT FENCE: table"),
            Value::Null
        ]
    );
}
