//! What is recorded, as JSON: made on the recorder's thread from what the event loop handed it.

use nalgebra::{Matrix3, Rotation3, UnitQuaternion};
use serde_json::{Value, json};

use super::topics::{self, Topic};
use crate::console::app::{Input, Severity};
use crate::console::jog::KeyKind;
use crate::kortex::Telemetry;
use crate::kortex::gen3;
use crate::link::interface::{ArmCommand, ArmEvent, CommandClass, GuardStatus, LinkStatus};

/// What the event loop hands the recorder: cheap to clone, turned into JSON off the loop.
#[derive(Debug, Clone)]
pub enum Recorded {
    Input(Input),
    Command(ArmCommand),
    /// The console's message line, when it changed.
    Said(String, Severity),
    /// Messages dropped so far, written once the queue has room again and at the end.
    Dropped(u64),
}

fn time(ns: u64) -> Value {
    json!({"sec": ns / 1_000_000_000, "nsec": ns % 1_000_000_000})
}

/// A number, or null for one that is not (JSON has no NaN).
fn number(v: f32) -> Value {
    if v.is_finite() { json!(v) } else { Value::Null }
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
            vec![(&topics::LOG, log(ns, 2, "terminal focus lost".into()))]
        }
        Recorded::Input(Input::Signal(name)) => {
            vec![(
                &topics::LOG,
                log(ns, 3, format!("{name}: stopping and quitting")),
            )]
        }
        Recorded::Input(_) => Vec::new(),
        Recorded::Command(command) => {
            let class = match command.class() {
                CommandClass::Stop => "stop",
                CommandClass::Motion { .. } => "motion",
                CommandClass::Setting => "setting",
                CommandClass::Query => "query",
            };
            let detail = format!("{command:?}");
            let label = command.kind().label();
            vec![(
                &topics::COMMANDS,
                json!({"command": label, "class": class, "detail": detail}),
            )]
        }
        Recorded::Said(text, severity) => {
            let level = match severity {
                Severity::Info => 2,
                Severity::Warning => 3,
                Severity::Error => 4,
            };
            vec![(&topics::LOG, log(ns, level, text.clone()))]
        }
        Recorded::Dropped(count) => vec![(&topics::RECORDER, json!({"dropped": count}))],
    }
}

fn arm_event(event: &ArmEvent, ns: u64, with_links: bool) -> Vec<(&'static Topic, Value)> {
    match event {
        ArmEvent::Telemetry(t) => telemetry(t, ns, with_links),
        ArmEvent::Log(entry) if !entry.poll => vec![(
            &topics::COMMAND_LOG,
            json!({
                "name": entry.name,
                "outcome": entry.outcome,
                "ok": entry.ok,
                "latency_ms": entry.latency.map(|l| l.as_secs_f64() * 1000.0),
                "id": entry.id,
            }),
        )],
        ArmEvent::Status(LinkStatus::Up { description }) => {
            vec![(&topics::LOG, log(ns, 2, format!("link up: {description}")))]
        }
        ArmEvent::Status(LinkStatus::Down { reason }) => {
            vec![(&topics::LOG, log(ns, 4, format!("link down: {reason}")))]
        }
        ArmEvent::Failed { command, error } => {
            vec![(
                &topics::LOG,
                log(ns, 4, format!("{command} failed: {error}")),
            )]
        }
        ArmEvent::Notice(text) => vec![(&topics::LOG, log(ns, 3, text.clone()))],
        ArmEvent::Guard(GuardStatus::Down { reason }) => {
            vec![(
                &topics::LOG,
                log(ns, 4, format!("stop guard down: {reason}")),
            )]
        }
        ArmEvent::StopUnconfirmed { .. } => {
            vec![(
                &topics::LOG,
                log(ns, 4, "STOP not confirmed: the arm may be moving".into()),
            )]
        }
        _ => Vec::new(),
    }
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
    let motion = json!({
        "linear_m_s": [number(v.x), number(v.y), number(v.z)],
        "angular_deg_s": [number(v.theta_x), number(v.theta_y), number(v.theta_z)],
        "force_n": [number(w.force_x), number(w.force_y), number(w.force_z)],
        "torque_nm": [number(w.torque_x), number(w.torque_y), number(w.torque_z)],
    });
    let arm = json!({
        "robot_state": t.robot_state,
        "faults": t.faults,
        "warnings": t.warnings,
        "action": t.action,
    });
    let mut out = vec![
        (&topics::JOINT_STATES, states),
        (&topics::TOOL_MOTION, motion),
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
