//! The recording's channels: their topics and JSON Schemas, so that any MCAP reader can decode
//! the messages without armjog. Where Foxglove has a well-known schema, its name and fields.

/// One channel: its topic, schema name and JSON Schema.
pub struct Topic {
    pub topic: &'static str,
    pub schema: &'static str,
    pub json_schema: &'static str,
    /// A sample equal to the last one written is left out for a while (`SAME_HELD_NS`).
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
    held: true,
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
    held: false,
};

/// The tool's twist (base frame) and wrench (tool frame), as reported.
pub const TOOL_MOTION: Topic = Topic {
    topic: "/tool/twist_wrench",
    schema: "armjog.ToolMotion",
    json_schema: schema!(
        r#"{"type":"object","properties":{"#,
        r#""linear_m_s":{"type":"array","items":{"type":["number","null"]},"minItems":3,"maxItems":3},"#,
        r#""angular_deg_s":{"type":"array","items":{"type":["number","null"]},"minItems":3,"maxItems":3},"#,
        r#""force_n":{"type":"array","items":{"type":["number","null"]},"minItems":3,"maxItems":3},"#,
        r#""torque_nm":{"type":"array","items":{"type":["number","null"]},"minItems":3,"maxItems":3}"#,
        r#"},"required":["linear_m_s","angular_deg_s","force_n","torque_nm"]}"#
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
    held: false,
};

/// The arm's state, faults and warnings by name, and its action, as the telemetry reports them.
pub const ARM_STATE: Topic = Topic {
    topic: "/arm/state",
    schema: "armjog.ArmState",
    json_schema: schema!(
        r#"{"type":"object","properties":{"robot_state":{},"faults":{"type":"array"},"warnings":{"type":"array"},"action":{"type":"object"}},"#,
        r#""required":["robot_state","faults","warnings","action"]}"#
    ),
    held: true,
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

/// A command the console sent the arm: its kind (`jog`, `stop`, `fence speed`) and its fields.
pub const COMMANDS: Topic = Topic {
    topic: "/commands",
    schema: "armjog.Command",
    json_schema: schema!(
        r#"{"type":"object","properties":{"command":{"type":"string"},"class":{"enum":["stop","motion","setting","query"]},"detail":{"type":"string"}},"required":["command","class","detail"]}"#
    ),
    held: false,
};

/// What the arm's link said of a command: a log line (link, request, outcome, latency).
pub const COMMAND_LOG: Topic = Topic {
    topic: "/commands/log",
    schema: "armjog.CommandLog",
    json_schema: schema!(
        r#"{"type":"object","properties":{"name":{"type":"string"},"outcome":{"type":"string"},"ok":{"type":"boolean"},"latency_ms":{"type":["number","null"]},"id":{"type":["integer","null"]}},"required":["name","outcome","ok"]}"#
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
pub const ALL: [&Topic; 10] = [
    &JOINT_STATES,
    &TOOL_POSE,
    &TOOL_MOTION,
    &TRANSFORMS,
    &ARM_STATE,
    &KEYS,
    &COMMANDS,
    &COMMAND_LOG,
    &LOG,
    &RECORDER,
];

/// The `{sec, nsec}` schema, for the tests that check a message's time.
pub const TIME_SCHEMA: &str = TIME;
