//! A recorded session read back WITHOUT the `mcap` crate that wrote it (`crate::mcap_spec`, a
//! reader written from the specification), every message validated against its channel's JSON
//! Schema as stored in the file. The session is the console's state machine and real arm driver
//! on the simulator over Modbus, the recorder fed as `console::run`'s event loop feeds it: a jog,
//! its release and stop, a quick stop that faults the arm, a jog refused in fault, focus lost and
//! a signal.

use std::collections::BTreeMap;
use std::path::Path;
use std::time::{Duration, Instant, SystemTime};

use serde_json::Value;
use tokio::sync::mpsc::UnboundedReceiver;

use armjog::console::app::{App, Effect, Input};
use armjog::console::jog::KeyKind;
use armjog::console::positions::PositionBook;
use armjog::console::recorder::{QUEUE, Recorder, topics};
use armjog::link::ModbusConfig;
use armjog::link::driver::{Driver, DriverConfig};
use armjog::link::interface::{ArmEvent, LinkStatus};
use armjog::sim::{SimConfig, Simulator};

use crate::event_loop::{self, Drives};
use crate::mcap_spec::{self, Recording};

struct Session {
    app: App,
    driver: Driver,
    events: UnboundedReceiver<ArmEvent>,
    sim: Simulator,
    recorder: Option<Recorder>,
}

impl Drives for Session {
    fn app(&self) -> &App {
        &self.app
    }
    fn events(&mut self) -> &mut UnboundedReceiver<ArmEvent> {
        &mut self.events
    }
    /// As `console::run`'s event loop: the recorder sees the input, then each command sent, then
    /// the message line, and hands it all over.
    fn input(&mut self, input: Input) {
        let recorder = self.recorder.as_mut().expect("recording");
        recorder.input(&input);
        for effect in self.app.handle(input, Instant::now()) {
            if let Effect::Arm(command) = effect {
                recorder.command(&command);
                assert!(self.driver.send(command), "driver alive");
            }
        }
        recorder.said(self.app.message());
        recorder.fence(self.app.fence_text());
        recorder.hand_over();
    }
}

impl Session {
    /// Recording into `path`, over Modbus to the simulator, link up and telemetry in.
    async fn start(path: &Path) -> Session {
        let sim = Simulator::start(SimConfig::ephemeral())
            .await
            .expect("simulator");
        let modbus = ModbusConfig::new(sim.modbus_addr.expect("modbus server").to_string());
        let config = DriverConfig::new(None, Some(modbus));
        let app = event_loop::app_for(&config, PositionBook::new());
        let mut recorder = Recorder::start(path.to_path_buf(), QUEUE).expect("recording");
        // As `console::run`: the session's facts first.
        recorder.session(app.config(), &config.target());
        recorder.hand_over();
        let (driver, events) = Driver::spawn(config);
        let mut session = Session {
            app,
            driver,
            events,
            sim,
            recorder: Some(recorder),
        };
        session
            .run_until(Duration::from_secs(10), |s| {
                matches!(s.app.link(), LinkStatus::Up { .. }) && s.app.telemetry().is_some()
            })
            .await;
        session
    }

    async fn moving(&self) -> bool {
        self.sim.arm.snapshot().await.expect("sim").moving
    }

    /// Runs the loop until the simulated arm's motion is `moving`; panics after 5 s.
    async fn until_moving(&mut self, moving: bool) {
        let until = Instant::now() + Duration::from_secs(5);
        while self.moving().await != moving {
            assert!(
                Instant::now() < until,
                "the arm never got to moving={moving}"
            );
            self.run_for(Duration::from_millis(10)).await;
        }
    }

    fn message(&self) -> String {
        self.app
            .message()
            .map(|m| m.0.to_string())
            .unwrap_or_default()
    }
}

/// Nanoseconds since the Unix epoch.
fn ns(t: SystemTime) -> u64 {
    let since = t
        .duration_since(SystemTime::UNIX_EPOCH)
        .expect("after 1970");
    u64::try_from(since.as_nanos()).expect("before 2554")
}

/// Each schema of the file compiled once, by its id, as the file states it (draft 2020-12, which
/// Foxglove's own JSON schemas use).
pub struct Validators {
    schemas: boon::Schemas,
    compiled: BTreeMap<u16, boon::SchemaIndex>,
}

impl Validators {
    pub fn new() -> Validators {
        Validators {
            schemas: boon::Schemas::new(),
            compiled: BTreeMap::new(),
        }
    }

    /// Compiles schema `id` from its text (the compiler checks it against the metaschema too).
    pub fn add(&mut self, id: u16, text: &[u8]) -> Result<(), String> {
        let json: Value = serde_json::from_slice(text).map_err(|e| format!("not JSON: {e}"))?;
        let url = format!("file:///schema/{id}.json");
        let mut compiler = boon::Compiler::new();
        compiler.set_default_draft(boon::Draft::V2020_12);
        compiler
            .add_resource(&url, json)
            .map_err(|e| format!("{e:#}"))?;
        let index = compiler
            .compile(&url, &mut self.schemas)
            .map_err(|e| format!("{e:#}"))?;
        self.compiled.insert(id, index);
        Ok(())
    }

    /// `message` against schema `id`, or why not.
    pub fn check(&self, id: u16, message: &Value) -> Result<(), String> {
        let index = self.compiled.get(&id).ok_or("no such schema")?;
        self.schemas
            .validate(message, *index)
            .map_err(|e| format!("{e:#}"))
    }
}

/// Every message of `file` as (topic, log time, JSON), each validated against its channel's
/// schema from the file; panics naming the first that does not fit.
fn validated(file: &Recording) -> Vec<(String, u64, Value)> {
    let mut validators = Validators::new();
    for (id, schema) in &file.schemas {
        assert_eq!(schema.encoding, "jsonschema", "schema {}", schema.name);
        validators
            .add(*id, &schema.data)
            .unwrap_or_else(|e| panic!("schema {} does not compile: {e}", schema.name));
    }
    let mut out = Vec::new();
    for message in &file.messages {
        let (channel, schema) = file.schema_of(message).expect("a channel with a schema");
        assert_eq!(channel.message_encoding, "json", "{}", channel.topic);
        let json: Value = serde_json::from_slice(&message.data).expect("a JSON message");
        if let Err(why) = validators.check(schema.id, &json) {
            panic!("{} breaks {}: {json}\n{why}", channel.topic, schema.name);
        }
        out.push((channel.topic.clone(), message.log_time, json));
    }
    out
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_session_reads_back_without_the_mcap_crate_and_every_message_fits_its_schema() {
    let started = ns(SystemTime::now());
    let dir = tempfile::tempdir().expect("a folder");
    let path = dir.path().join("session.mcap");
    let mut session = Session::start(&path).await;

    // A jog, released: the arm moves, then stops.
    session.key("w", KeyKind::Press);
    session.until_moving(true).await;
    session.run_for(Duration::from_millis(200)).await;
    session.key("w", KeyKind::Release);
    session.until_moving(false).await;
    // A quick stop: the arm goes to fault, and a second passes in fault (a chunk closes).
    session.key("x", KeyKind::Press);
    session.key("x", KeyKind::Release);
    session
        .run_until(Duration::from_secs(5), |s| {
            s.app.telemetry().is_some_and(|t| t.faults.bits() != 0)
        })
        .await;
    session.run_for(Duration::from_millis(1100)).await;
    // A jog in fault: refused, nothing moves.
    session.key("w", KeyKind::Press);
    let refusal = session.message();
    assert!(refusal.starts_with("refused: "), "{refusal}");
    session.run_for(Duration::from_millis(100)).await;
    assert!(!session.moving().await, "a refused jog moved the arm");
    session.key("w", KeyKind::Release);
    session.input(Input::FocusLost);
    session.input(Input::Signal("SIGTERM"));
    drop(session.recorder.take());
    let ended = ns(SystemTime::now());

    let bytes = std::fs::read(&path).expect("the recording");
    let file = mcap_spec::read(&bytes).unwrap_or_else(|e| panic!("not a good MCAP file: {e}"));
    // No well-known profile (ros1, ros2: none is JSON), and the writer names itself.
    assert_eq!(file.profile, "");
    assert!(!file.library.is_empty());
    let data_crc = file.data_section_crc.expect("a Data End");
    assert_ne!(data_crc, 0, "the writer gave no data section CRC");
    assert_ne!(file.summary_crc, 0, "the writer gave no summary CRC");
    assert!(
        file.chunks.len() >= 2,
        "{} chunks in 1.1 s",
        file.chunks.len()
    );
    assert!(file.chunks.iter().all(|c| c.compression == "zstd"));
    let summary = file.summary.as_ref().expect("a summary (a clean end)");
    let statistics = summary.statistics.as_ref().expect("Statistics");
    assert_eq!(statistics.message_count, file.messages.len() as u64);
    assert_eq!(summary.chunk_indexes.len(), file.chunks.len());
    // One channel per topic, named and schema'd as armjog declares them.
    let declared: BTreeMap<&str, &str> = topics::ALL.iter().map(|t| (t.topic, t.schema)).collect();
    let in_file: BTreeMap<&str, &str> = (file.channels.values())
        .map(|c| (c.topic.as_str(), file.schemas[&c.schema_id].name.as_str()))
        .collect();
    assert_eq!(in_file, declared);

    let messages = validated(&file);
    // Every channel has messages: the session touched every topic but the fence's (its arm has
    // none; `recorder::the_fence_s_words_are_recorded_on_each_change` writes it).
    for topic in topics::ALL
        .iter()
        .filter(|t| t.topic != topics::FENCE.topic)
    {
        assert!(
            messages.iter().any(|m| m.0 == topic.topic),
            "nothing on {}",
            topic.topic
        );
    }
    // Log times: in file order, since the Unix epoch, within the test; publish time the same.
    let mut last = 0;
    for (m, (topic, log_time, _)) in file.messages.iter().zip(&messages) {
        assert!(
            (started..=ended).contains(log_time),
            "{topic} at {log_time}"
        );
        assert!(*log_time >= last, "{topic} at {log_time} before {last}");
        assert_eq!(m.publish_time, m.log_time);
        last = *log_time;
    }
    let sequences: Vec<u32> = file.messages.iter().map(|m| m.sequence).collect();
    assert!(sequences.windows(2).all(|w| w[1] > w[0]), "{sequences:?}");
    what_happened_is_there(&messages, &refusal);
}

/// The session's events, in order, with the values known of them.
fn what_happened_is_there(messages: &[(String, u64, Value)], refusal: &str) {
    let at = |what: &str, found: &dyn Fn(&str, &Value) -> bool| {
        messages
            .iter()
            .position(|(topic, _, json)| found(topic, json))
            .unwrap_or_else(|| panic!("no {what}"))
    };
    let key = |kind: &'static str| {
        move |topic: &str, json: &Value| {
            topic == "/keys" && json["key"] == "w" && json["kind"] == kind
        }
    };
    let command = |name: &'static str| {
        move |topic: &str, json: &Value| topic == "/commands" && json["command"] == name
    };
    let press = at("w pressed", &key("press"));
    let jog = at("jog", &command("jog"));
    let jog_log = at("the jog's log line", &|topic, json| {
        topic == "/commands/log" && json["name"] == "jog" && json["ok"] == true
    });
    let release = at("w released", &key("release"));
    let stop = at("stop", &command("stop"));
    let quick_stop = at("quick stop", &command("quick stop"));
    let fault = at("fault", &|topic, json| {
        let faults = json["faults"].as_array().map(Vec::as_slice);
        topic == "/arm/state"
            && json["robot_state"] == "in_fault"
            && faults.is_some_and(|f| f.iter().any(|f| f == "emergency_stop"))
    });
    let refused = at("the refusal", &|topic, json| {
        topic == "/log" && json["message"] == refusal && json["level"] == 3
    });
    let focus = at("focus lost", &|topic, json| {
        topic == "/log" && json["message"] == "terminal focus lost"
    });
    let signal = at("the signal", &|topic, json| {
        topic == "/log" && json["message"] == "SIGTERM: stopping and quitting"
    });
    let order = [
        press, jog, jog_log, release, stop, quick_stop, fault, refused, focus, signal,
    ];
    assert!(
        order.windows(2).all(|w| w[0] < w[1]),
        "out of order: {order:?}"
    );
    assert_eq!(messages[jog].2["class"], "motion");
    assert_eq!(messages[stop].2["class"], "stop");
    assert_eq!(messages[quick_stop].2["class"], "stop");
    // Refused: no jog went out after the fault.
    assert!(!messages[fault..].iter().any(|m| command("jog")(&m.0, &m.2)));
    // A foxglove.Log's timestamp is its log time.
    let (_, log_time, json) = &messages[refused];
    let stamp = json["timestamp"]["sec"].as_u64().expect("sec") * 1_000_000_000
        + json["timestamp"]["nsec"].as_u64().expect("nsec");
    assert_eq!(stamp, *log_time);
    let dropped = messages.iter().rev().find(|m| m.0 == "/recorder");
    assert_eq!(dropped.expect("the count").2["dropped"], 0);
}

#[test]
fn the_validator_rejects_what_breaks_a_schema() {
    let mut validators = Validators::new();
    validators
        .add(1, topics::KEYS.json_schema.as_bytes())
        .expect("the keys' schema");
    validators
        .add(2, topics::LOG.json_schema.as_bytes())
        .expect("the log's schema");
    let ok = serde_json::json!({"key": "w", "kind": "press"});
    assert_eq!(validators.check(1, &ok), Ok(()));
    for bad in [
        serde_json::json!({"key": "w"}),
        serde_json::json!({"key": "w", "kind": "hold"}),
        serde_json::json!({"key": 7, "kind": "press"}),
    ] {
        assert!(validators.check(1, &bad).is_err(), "{bad} passed");
    }
    let log = |nsec: i64| {
        serde_json::json!({"timestamp": {"sec": 1, "nsec": nsec}, "level": 2, "message": "m",
            "name": "armjog", "file": "", "line": 0})
    };
    assert_eq!(validators.check(2, &log(5)), Ok(()));
    assert!(validators.check(2, &log(1_000_000_000)).is_err());
    let mut no_timestamp = log(5);
    no_timestamp
        .as_object_mut()
        .expect("an object")
        .remove("timestamp");
    assert!(validators.check(2, &no_timestamp).is_err());
    // A schema that is not one is refused, not taken as "anything goes".
    assert!(validators.add(3, br#"{"type": "objekt"}"#).is_err());
}
