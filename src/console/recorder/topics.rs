//! The recording's channels: their topics and JSON Schemas, so that any MCAP reader can decode
//! the messages without armjog. Where Foxglove has a well-known schema, its name and fields.

/// One channel: its topic, schema name and JSON Schema.
pub struct Topic {
    pub topic: &'static str,
    pub schema: &'static str,
    pub json_schema: &'static str,
    /// A message that says what the last one said is left out for up to a second
    /// (`SAME_HELD_NS`): what a still arm repeats. `/joint_states`, never held, times each sample.
    pub held: bool,
}

const TIME: &str = r#"{"type":"object","properties":{"sec":{"type":"integer","minimum":0},"nsec":{"type":"integer","minimum":0,"maximum":999999999}},"required":["sec","nsec"]}"#;

macro_rules! schema {
    ($($body:tt)*) => { concat!($($body)*) };
}

/// Joint states: per joint (J1..J7) position (deg), velocity (deg/s), torque (N·m), current (A),
/// temperature (°C).
pub const JOINT_STATES: Topic = Topic {
    topic: "/joint_states",
    schema: "armjog.JointStates",
    json_schema: schema!(
        r#"{"type":"object","properties":{"#,
        r#""position_deg":{"type":"array","items":{"type":["number","null"]},"minItems":7,"maxItems":7},"#,
        r#""velocity_deg_s":{"type":"array","items":{"type":["number","null"]},"minItems":7,"maxItems":7},"#,
        r#""torque_nm":{"type":"array","items":{"type":["number","null"]},"minItems":7,"maxItems":7},"#,
        r#""current_a":{"type":"array","items":{"type":["number","null"]},"minItems":7,"maxItems":7},"#,
        r#""temperature_c":{"type":"array","items":{"type":["number","null"]},"minItems":7,"maxItems":7}"#,
        r#"},"required":["position_deg","velocity_deg_s","torque_nm","current_a","temperature_c"]}"#
    ),
    held: false,
};

/// The tool's pose in the base frame (foxglove.PoseInFrame), metres and a unit quaternion.
pub const TOOL_POSE: Topic = Topic {
    topic: "/tool/pose",
    schema: "foxglove.PoseInFrame",
    json_schema: schema!(
        r#"{"title":"foxglove.PoseInFrame","type":"object","properties":{"timestamp":"#,
        r#"{"type":"object","properties":{"sec":{"type":"integer","minimum":0},"nsec":{"type":"integer","minimum":0,"maximum":999999999}},"required":["sec","nsec"]},"#,
        r#""frame_id":{"type":"string"},"pose":{"type":"object","properties":{"#,
        r#""position":{"type":"object","properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"}},"required":["x","y","z"]},"#,
        r#""orientation":{"type":"object","properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"},"w":{"type":"number"}},"required":["x","y","z","w"]}"#,
        r#"},"required":["position","orientation"]}},"required":["timestamp","frame_id","pose"]}"#
    ),
    held: true,
};

/// The tool's pose as reported (base frame, metres and extrinsic XYZ degrees), twist (base
/// frame) and wrench (tool frame): every sample, so that `armjog replay` shows what the panels showed.
pub const TOOL_STATE: Topic = Topic {
    topic: "/tool/state",
    schema: "armjog.ToolState",
    json_schema: schema!(
        r#"{"type":"object","properties":{"#,
        r#""position_m":{"type":"array","items":{"type":["number","null"]},"minItems":3,"maxItems":3},"#,
        r#""orientation_deg":{"type":"array","items":{"type":["number","null"]},"minItems":3,"maxItems":3},"#,
        r#""linear_m_s":{"type":"array","items":{"type":["number","null"]},"minItems":3,"maxItems":3},"#,
        r#""angular_deg_s":{"type":"array","items":{"type":["number","null"]},"minItems":3,"maxItems":3},"#,
        r#""force_n":{"type":"array","items":{"type":["number","null"]},"minItems":3,"maxItems":3},"#,
        r#""torque_nm":{"type":"array","items":{"type":["number","null"]},"minItems":3,"maxItems":3}"#,
        r#"},"required":["position_m","orientation_deg","linear_m_s","angular_deg_s","force_n","torque_nm"]}"#
    ),
    held: true,
};

/// The arm's links from the forward kinematics (foxglove.FrameTransforms): Foxglove's 3D panel
/// shows the arm move.
pub const TRANSFORMS: Topic = Topic {
    topic: "/tf",
    schema: "foxglove.FrameTransforms",
    json_schema: schema!(
        r#"{"title":"foxglove.FrameTransforms","type":"object","properties":{"transforms":{"type":"array","items":"#,
        r#"{"type":"object","properties":{"timestamp":{"type":"object","properties":{"sec":{"type":"integer","minimum":0},"nsec":{"type":"integer","minimum":0,"maximum":999999999}},"required":["sec","nsec"]},"#,
        r#""parent_frame_id":{"type":"string"},"child_frame_id":{"type":"string"},"#,
        r#""translation":{"type":"object","properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"}},"required":["x","y","z"]},"#,
        r#""rotation":{"type":"object","properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"},"w":{"type":"number"}},"required":["x","y","z","w"]}},"#,
        r#""required":["timestamp","parent_frame_id","child_frame_id","translation","rotation"]}}},"required":["transforms"]}"#
    ),
    held: true,
};

/// The arm's state, faults and warnings by name, its action, its health (A, V, °C) and the
/// speed limits in force (m/s, deg/s), as the telemetry reports them.
pub const ARM_STATE: Topic = Topic {
    topic: "/arm/state",
    schema: "armjog.ArmState",
    json_schema: schema!(
        r#"{"type":"object","properties":{"robot_state":{"type":"string"},"#,
        r#""faults":{"type":"array","items":{"type":"string"}},"warnings":{"type":"array","items":{"type":"string"}},"#,
        r#""action":{"type":"object","properties":{"status":{"type":"string"},"id":{"type":"integer","minimum":0},"move_type":{"type":"string"}},"required":["status","id","move_type"]},"#,
        r#""health":{"type":"object","properties":{"current":{"type":["number","null"]},"voltage":{"type":["number","null"]},"cpu_temperature":{"type":["number","null"]},"ambient_temperature":{"type":["number","null"]}},"required":["current","voltage","cpu_temperature","ambient_temperature"]},"#,
        r#""speed_limits":{"type":"object","properties":{"linear":{"type":["number","null"]},"angular":{"type":["number","null"]}},"required":["linear","angular"]}},"#,
        r#""required":["robot_state","faults","warnings","action","health","speed_limits"]}"#
    ),
    held: true,
};

/// The session: what the console was started with (first message of a file).
pub const SESSION: Topic = Topic {
    topic: "/session",
    schema: "armjog.Session",
    json_schema: schema!(
        r#"{"type":"object","properties":{"armjog":{"type":"string"},"arm":{"type":"string"},"link":{"type":"string"},"#,
        r#""simulated":{"type":"boolean"},"release_mode":{"enum":["reported","auto-repeat"]},"refresh_ms":{"type":"integer","minimum":1},"#,
        r#""cap_mm_s":{"type":"number","exclusiveMinimum":0},"joint_jog_deg_s":{"type":"number","exclusiveMinimum":0},"#,
        r#""frames":{"type":"boolean"},"positions_on_operator":{"type":"boolean"},"fence":{"type":"boolean"}},"#,
        r#""required":["armjog","arm","link","simulated","release_mode","refresh_ms","cap_mm_s","joint_jog_deg_s","frames","positions_on_operator","fence"]}"#
    ),
    held: false,
};

/// The link: its state, which telemetry it carries, the stop guard, the round trip, whether a
/// STOP was confirmed, a command that failed (`failed`: its kind, `text`: why), a notice.
pub const LINK: Topic = Topic {
    topic: "/link",
    schema: "armjog.Link",
    json_schema: schema!(
        r#"{"type":"object","properties":{"status":{"enum":["connecting","up","down"]},"text":{"type":"string"},"#,
        r#""telemetry_source":{"enum":["modbus","talos_hardware","none"]},"guard":{"enum":["starting","ready","down"]},"#,
        r#""guard_pid":{"type":"integer","minimum":0},"latency_ms":{"type":"number","minimum":0},"#,
        r#""stop":{"enum":["confirmed","unconfirmed"]},"failed":{"type":"string"},"notice":{"type":"string"}},"minProperties":1}"#
    ),
    held: false,
};

/// The speed in force (percent of the cap) as the link reports it, and the cap it is of (`null`
/// before the session's facts are recorded).
pub const SPEED: Topic = Topic {
    topic: "/speed",
    schema: "armjog.Speed",
    json_schema: schema!(
        r#"{"type":"object","properties":{"speed_percent":{"type":"integer","minimum":0,"maximum":100},"cap_mm_s":{"type":["number","null"],"exclusiveMinimum":0}},"required":["speed_percent","cap_mm_s"]}"#
    ),
    held: false,
};

/// The console's message line as the technician saw it: each change, `null` when it cleared.
pub const MESSAGE: Topic = Topic {
    topic: "/console/message",
    schema: "armjog.Message",
    json_schema: schema!(
        r#"{"type":"object","properties":{"text":{"type":["string","null"]},"severity":{"enum":["info","warning","error",null]}},"required":["text","severity"]}"#
    ),
    held: false,
};

/// The fence (when the arm has one): what it says of the tool, on each change (`SLOWED: table
/// 34 mm`, `AT FENCE: table`, `null` when clear).
pub const FENCE: Topic = Topic {
    topic: "/fence",
    schema: "armjog.Fence",
    json_schema: schema!(
        r#"{"type":"object","properties":{"verdict":{"type":["string","null"]}},"required":["verdict"]}"#
    ),
    held: false,
};

/// A jog key's press, repeat or release.
pub const KEYS: Topic = Topic {
    topic: "/keys",
    schema: "armjog.Key",
    json_schema: schema!(
        r#"{"type":"object","properties":{"key":{"type":"string"},"kind":{"enum":["press","repeat","release"]}},"required":["key","kind"]}"#
    ),
    held: false,
};

/// A command the console sent the arm: its kind (`jog`, `stop`, `fence speed`), class, and its
/// fields as words.
pub const COMMANDS: Topic = Topic {
    topic: "/commands",
    schema: "armjog.Command",
    json_schema: schema!(
        r#"{"type":"object","properties":{"command":{"type":"string"},"class":{"enum":["stop","motion","setting","query"]},"detail":{"type":"string"}},"required":["command","class","detail"]}"#
    ),
    held: false,
};

/// What the arm's link said of a command: a log line (link, request, outcome, latency). Telemetry
/// polls, which the panel folds into one line, are written folded: `count` polls at most a second.
pub const COMMAND_LOG: Topic = Topic {
    topic: "/commands/log",
    schema: "armjog.CommandLog",
    json_schema: schema!(
        r#"{"type":"object","properties":{"name":{"type":"string"},"outcome":{"type":"string"},"ok":{"type":"boolean"},"latency_ms":{"type":["number","null"]},"id":{"type":["integer","null"]},"poll":{"type":"boolean"},"count":{"type":"integer","minimum":1}},"required":["name","outcome","ok","poll","count"]}"#
    ),
    held: false,
};

/// Messages (foxglove.Log): the console's message line (stops and refusals with their reasons),
/// the link's state, failures and notices.
pub const LOG: Topic = Topic {
    topic: "/log",
    schema: "foxglove.Log",
    json_schema: schema!(
        r#"{"title":"foxglove.Log","type":"object","properties":{"timestamp":{"type":"object","properties":{"sec":{"type":"integer","minimum":0},"nsec":{"type":"integer","minimum":0,"maximum":999999999}},"required":["sec","nsec"]},"#,
        r#""level":{"type":"integer","minimum":0,"maximum":5},"message":{"type":"string"},"name":{"type":"string"},"file":{"type":"string"},"line":{"type":"integer","minimum":0}},"#,
        r#""required":["timestamp","level","message","name","file","line"]}"#
    ),
    held: false,
};

/// The recorder itself: messages dropped so far because its queue was full.
pub const RECORDER: Topic = Topic {
    topic: "/recorder",
    schema: "armjog.Recorder",
    json_schema: schema!(
        r#"{"type":"object","properties":{"dropped":{"type":"integer","minimum":0}},"required":["dropped"]}"#
    ),
    held: false,
};

/// Every channel, in the order they are added to a file.
pub const ALL: [&Topic; 15] = [
    &SESSION,
    &JOINT_STATES,
    &TOOL_POSE,
    &TOOL_STATE,
    &TRANSFORMS,
    &ARM_STATE,
    &KEYS,
    &COMMANDS,
    &COMMAND_LOG,
    &LOG,
    &MESSAGE,
    &LINK,
    &SPEED,
    &FENCE,
    &RECORDER,
];

/// The `{sec, nsec}` schema, for the tests that check a message's time.
pub const TIME_SCHEMA: &str = TIME;
