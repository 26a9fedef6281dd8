//! What is recorded, as JSON: made on the recorder's thread from what the event loop handed it.

use nalgebra::{Matrix3, Rotation3, UnitQuaternion};
use serde_json::{Value, json};

use super::topics::{self, Topic};
use crate::console::app::{Input, Severity};
use crate::console::jog::KeyKind;
use crate::kortex::Telemetry;
use crate::kortex::gen3;
use crate::link::interface::{
    ArmCommand, ArmEvent, CommandClass, GuardStatus, LinkStatus, LogEntry, StepMove,
    TelemetrySource,
};

/// The `/log` line a lost focus writes (`armjog replay` plays it as one).
pub const FOCUS_LOST: &str = "terminal focus lost";

/// What the event loop hands the recorder: cheap to clone, turned into JSON off the loop.
#[derive(Debug, Clone)]
pub enum Recorded {
    Input(Input),
    Command(ArmCommand),
    /// The console's message line, when it changed; `None`: it cleared.
    Said(Option<(String, Severity)>),
    /// The session's facts (`topics::SESSION`), made once at the start.
    Session(Value),
    /// The speed in force, percent, and the cap it is of (mm/s), once known.
    Speed {
        percent: u8,
        cap_mm_s: Option<f64>,
    },
    /// Telemetry polls folded as the command log folds them: the last one and how many.
    Polls(LogEntry, u32),
    /// The round trip of the latest request, at most a few a second.
    Latency(std::time::Duration),
    /// What the fence says of the tool, when it changed.
    Fence(Option<String>),
    /// Messages dropped so far, written once the queue has room again and at the end.
    Dropped(u64),
}

fn time(ns: u64) -> Value {
    json!({"sec": ns / 1_000_000_000, "nsec": ns % 1_000_000_000})
}

/// A number, or null for one that is not (JSON has no NaN). Written with the digits an `f32`
/// needs (`0.1`, not the `0.10000000149011612` of its `f64`): read back as `f32`, it is the same.
pub fn number(v: f32) -> Value {
    if !v.is_finite() {
        return Value::Null;
    }
    v.to_string()
        .parse::<f64>()
        .ok()
        .and_then(serde_json::Number::from_f64)
        .map_or(Value::Null, Value::Number)
}

/// To a millionth (a micrometre, a microradian): the model's own digits beyond are noise that
/// compresses badly.
fn micro(v: f64) -> f64 {
    (v * 1e6).round() / 1e6
}

fn quaternion(m: &Matrix3<f64>) -> Value {
    let q = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(*m));
    json!({"x": micro(q.i), "y": micro(q.j), "z": micro(q.k), "w": micro(q.w)})
}

/// The arm's links and the tool's pose are recorded at most this often (ns): Foxglove's 3D panel
/// needs no more, and they are most of a sample's bytes (`/joint_states` has every sample).
pub const TRANSFORMS_EVERY_NS: u64 = 100_000_000;

/// What a message says, without its time: a held channel's message is left out when this is the
/// same as its last one's (`SAME_HELD_NS`).
pub fn content(message: &Value) -> String {
    match message {
        Value::Object(fields) => {
            let mut fields = fields.clone();
            fields.remove("timestamp");
            if let Some(Value::Array(transforms)) = fields.get_mut("transforms") {
                for t in transforms.iter_mut().filter_map(Value::as_object_mut) {
                    t.remove("timestamp");
                }
            }
            Value::Object(fields).to_string()
        }
        other => other.to_string(),
    }
}

fn log(ns: u64, level: u8, message: String) -> Value {
    json!({"timestamp": time(ns), "level": level, "message": message, "name": "armjog", "file": "", "line": 0})
}

/// The messages `recorded` makes at `ns` (ns since the Unix epoch), each with its channel.
/// `with_links`: the arm's links (`/tf`) are recorded with this sample.
pub fn messages(recorded: &Recorded, ns: u64, with_links: bool) -> Vec<(&'static Topic, Value)> {
    match recorded {
        Recorded::Input(Input::Arm(event)) => arm_event(event, ns, with_links),
        Recorded::Input(Input::Key(key)) => {
            let kind = match key.kind {
                KeyKind::Press => "press",
                KeyKind::Repeat => "repeat",
                KeyKind::Release => "release",
            };
            vec![(
                &topics::KEYS,
                json!({"key": key.key.to_string(), "kind": kind}),
            )]
        }
        Recorded::Input(Input::FocusLost) => {
            vec![(&topics::LOG, log(ns, 2, FOCUS_LOST.into()))]
        }
        Recorded::Input(_) => Vec::new(),
        Recorded::Command(command) => {
            let class = match command.class() {
                CommandClass::Stop => "stop",
                CommandClass::Motion { .. } => "motion",
                CommandClass::Setting => "setting",
                CommandClass::Query => "query",
            };
            let detail = detail(command);
            let label = command.kind().label();
            vec![(
                &topics::COMMANDS,
                json!({"command": label, "class": class, "detail": detail}),
            )]
        }
        Recorded::Said(None) => {
            vec![(&topics::MESSAGE, json!({"text": null, "severity": null}))]
        }
        Recorded::Said(Some((text, severity))) => {
            let (level, name) = match severity {
                Severity::Info => (2, "info"),
                Severity::Warning => (3, "warning"),
                Severity::Error => (4, "error"),
            };
            vec![
                (&topics::MESSAGE, json!({"text": text, "severity": name})),
                (&topics::LOG, log(ns, level, text.clone())),
            ]
        }
        Recorded::Session(facts) => vec![(&topics::SESSION, facts.clone())],
        Recorded::Speed { percent, cap_mm_s } => vec![(
            &topics::SPEED,
            json!({"speed_percent": percent, "cap_mm_s": cap_mm_s}),
        )],
        Recorded::Polls(entry, count) => vec![(&topics::COMMAND_LOG, log_entry(entry, *count))],
        Recorded::Latency(latency) => {
            vec![(&topics::LINK, json!({"latency_ms": milliseconds(*latency)}))]
        }
        Recorded::Fence(verdict) => vec![(&topics::FENCE, json!({"verdict": verdict}))],
        Recorded::Dropped(count) => vec![(&topics::RECORDER, json!({"dropped": count}))],
    }
}

fn arm_event(event: &ArmEvent, ns: u64, with_links: bool) -> Vec<(&'static Topic, Value)> {
    match event {
        ArmEvent::Telemetry(t) => telemetry(t, ns, with_links),
        ArmEvent::Log(entry) => vec![(&topics::COMMAND_LOG, log_entry(entry, entry.count))],
        ArmEvent::Status(LinkStatus::Connecting) => {
            vec![(&topics::LINK, json!({"status": "connecting"}))]
        }
        ArmEvent::Status(LinkStatus::Up { description }) => vec![
            (&topics::LINK, json!({"status": "up", "text": description})),
            (&topics::LOG, log(ns, 2, format!("link up: {description}"))),
        ],
        ArmEvent::Status(LinkStatus::Down { reason }) => vec![
            (&topics::LINK, json!({"status": "down", "text": reason})),
            (&topics::LOG, log(ns, 4, format!("link down: {reason}"))),
        ],
        ArmEvent::TelemetrySource(source) => {
            let source = match source {
                TelemetrySource::Modbus => "modbus",
                TelemetrySource::TalosHardware => "talos_hardware",
                TelemetrySource::None => "none",
            };
            vec![(&topics::LINK, json!({"telemetry_source": source}))]
        }
        ArmEvent::Guard(GuardStatus::Starting) => {
            vec![(&topics::LINK, json!({"guard": "starting"}))]
        }
        ArmEvent::Guard(GuardStatus::Ready { pid }) => {
            vec![(&topics::LINK, json!({"guard": "ready", "guard_pid": pid}))]
        }
        ArmEvent::Failed { command, error } => vec![
            (
                &topics::LINK,
                json!({"failed": command.label(), "text": error.to_string()}),
            ),
            (
                &topics::LOG,
                log(ns, 4, format!("{command} failed: {error}")),
            ),
        ],
        ArmEvent::Notice(text) => vec![
            (&topics::LINK, json!({"notice": text})),
            (&topics::LOG, log(ns, 3, text.clone())),
        ],
        ArmEvent::StopConfirmed => vec![(&topics::LINK, json!({"stop": "confirmed"}))],
        ArmEvent::Guard(GuardStatus::Down { reason }) => vec![
            (&topics::LINK, json!({"guard": "down", "text": reason})),
            (
                &topics::LOG,
                log(ns, 4, format!("stop guard down: {reason}")),
            ),
        ],
        ArmEvent::StopUnconfirmed { reason } => vec![
            (
                &topics::LINK,
                json!({"stop": "unconfirmed", "text": reason}),
            ),
            (
                &topics::LOG,
                log(ns, 4, "STOP not confirmed: the arm may be moving".into()),
            ),
        ],
        _ => Vec::new(),
    }
}

/// A command's fields in words: `+X`, `30 %`, `bench`, `dx 10.0 mm`.
fn detail(command: &ArmCommand) -> String {
    let mm = |tenths: i32| format!("{:.1} mm", f64::from(tenths) / 10.0);
    match command {
        ArmCommand::Jog(motion) => crate::console::coords::describe_motion(*motion),
        ArmCommand::Step(StepMove::Cartesian { dx, dy, dz }) => {
            format!("dx {} dy {} dz {}", mm(*dx), mm(*dy), mm(*dz))
        }
        ArmCommand::Step(StepMove::Polar { azimuth, altitude }) => {
            format!("azimuth {azimuth} deg altitude {altitude} deg")
        }
        ArmCommand::MoveToPose(p) => format!(
            "x {:.1} y {:.1} z {:.1} mm, {:.1} {:.1} {:.1} deg",
            p.x * 1000.0,
            p.y * 1000.0,
            p.z * 1000.0,
            p.theta_x,
            p.theta_y,
            p.theta_z
        ),
        ArmCommand::SetSpeed(percent) => format!("{percent} %"),
        ArmCommand::FenceSpeed(permille) => format!("{permille} per mille"),
        ArmCommand::SetFrame(frame) => format!("{frame:?}").to_lowercase(),
        ArmCommand::SavePosition { name, .. }
        | ArmCommand::DeletePosition { name }
        | ArmCommand::GoToPosition { name }
        | ArmCommand::GetPosition { name } => name.clone(),
        ArmCommand::SetPolarPosition {
            name,
            delta,
            azimuth,
            radius,
        } => format!(
            "{name}: altitude {:.1} deg, azimuth {:.1} deg, radius {}",
            f64::from(*delta) / 10.0,
            f64::from(*azimuth) / 10.0,
            mm(*radius)
        ),
        ArmCommand::SetCartesianPosition { name, x, y, z } => {
            format!("{name}: x {} y {} z {}", mm(*x), mm(*y), mm(*z))
        }
        ArmCommand::StartStored(stored) => {
            format!("{:?} {}", stored.motion, stored.id).to_lowercase()
        }
        ArmCommand::Stop | ArmCommand::Home | ArmCommand::QuickStop | ArmCommand::FaultReset => {
            String::new()
        }
    }
}

/// To the microsecond: `0.27`, not `0.26972999999999997`.
fn milliseconds(d: std::time::Duration) -> f64 {
    (d.as_secs_f64() * 1e6).round() / 1000.0
}

fn log_entry(entry: &LogEntry, count: u32) -> Value {
    json!({
        "name": entry.name,
        "outcome": entry.outcome,
        "ok": entry.ok,
        "latency_ms": entry.latency.map(milliseconds),
        "id": entry.id,
        "poll": entry.poll,
        "count": count.max(1),
    })
}

fn telemetry(t: &Telemetry, ns: u64, with_links: bool) -> Vec<(&'static Topic, Value)> {
    let joints = |f: fn(&crate::kortex::JointState) -> f32| -> Vec<Value> {
        t.joints.iter().map(|j| number(f(j))).collect()
    };
    let states = json!({
        "position_deg": joints(|j| j.position),
        "velocity_deg_s": joints(|j| j.velocity),
        "torque_nm": joints(|j| j.torque),
        "current_a": joints(|j| j.current),
        "temperature_c": joints(|j| j.temperature),
    });
    let (p, v, w) = (t.tcp.pose, t.tcp.twist, t.tcp.wrench);
    let tool = json!({
        "position_m": [number(p.x), number(p.y), number(p.z)],
        "orientation_deg": [number(p.theta_x), number(p.theta_y), number(p.theta_z)],
        "linear_m_s": [number(v.x), number(v.y), number(v.z)],
        "angular_deg_s": [number(v.theta_x), number(v.theta_y), number(v.theta_z)],
        "force_n": [number(w.force_x), number(w.force_y), number(w.force_z)],
        "torque_nm": [number(w.torque_x), number(w.torque_y), number(w.torque_z)],
    });
    let h = t.arm;
    let arm = json!({
        "robot_state": t.robot_state,
        "faults": t.faults,
        "warnings": t.warnings,
        "action": t.action,
        "health": {
            "current": number(h.current),
            "voltage": number(h.voltage),
            "cpu_temperature": number(h.cpu_temperature),
            "ambient_temperature": number(h.ambient_temperature),
        },
        "speed_limits": {
            "linear": number(t.speed_limits.linear),
            "angular": number(t.speed_limits.angular),
        },
    });
    let mut out = vec![
        (&topics::JOINT_STATES, states),
        (&topics::TOOL_STATE, tool),
        (&topics::ARM_STATE, arm),
    ];
    let pose = [p.x, p.y, p.z, p.theta_x, p.theta_y, p.theta_z];
    // With the links: what Foxglove's 3D panel draws, at its rate.
    if with_links && pose.iter().all(|v| v.is_finite()) {
        // Extrinsic XYZ degrees, as Kinova reports the tool's orientation.
        let [rx, ry, rz] = [p.theta_x, p.theta_y, p.theta_z].map(|d| f64::from(d).to_radians());
        let q = UnitQuaternion::from_euler_angles(rx, ry, rz);
        let orientation =
            json!({"x": micro(q.i), "y": micro(q.j), "z": micro(q.k), "w": micro(q.w)});
        let position = json!({"x": p.x, "y": p.y, "z": p.z});
        let message = json!({
            "timestamp": time(ns),
            "frame_id": "base",
            "pose": {"position": position, "orientation": orientation},
        });
        out.push((&topics::TOOL_POSE, message));
    }
    let q = t.joints.map(|j| f64::from(j.position).to_radians());
    if with_links && q.iter().all(|a| a.is_finite()) {
        out.push((&topics::TRANSFORMS, transforms(&q, ns)));
    }
    out
}

/// The arm's links as frames `base` → `link1` … `link7` → `tool`, each relative to the one before.
fn transforms(q: &[f64; 7], ns: u64) -> Value {
    let (before, tool) = gen3::frames(q);
    let names = [
        "base", "link1", "link2", "link3", "link4", "link5", "link6", "link7", "tool",
    ];
    let mut absolute: Vec<nalgebra::Matrix4<f64>> = before.to_vec();
    absolute.push(tool);
    let mut transforms = Vec::with_capacity(8);
    let mut parent = nalgebra::Matrix4::identity();
    for (i, frame) in absolute.iter().enumerate() {
        let relative = parent
            .try_inverse()
            .unwrap_or_else(nalgebra::Matrix4::identity)
            * frame;
        let rotation: Matrix3<f64> = relative.fixed_view::<3, 3>(0, 0).into();
        transforms.push(json!({
            "timestamp": time(ns),
            "parent_frame_id": names[i],
            "child_frame_id": names[i + 1],
            "translation": {
                "x": micro(relative[(0, 3)]),
                "y": micro(relative[(1, 3)]),
                "z": micro(relative[(2, 3)]),
            },
            "rotation": quaternion(&rotation),
        }));
        parent = *frame;
    }
    json!({"transforms": transforms})
}
