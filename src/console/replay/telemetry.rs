//! A telemetry sample rebuilt from the three channels the recorder writes it on
//! (`/joint_states`, `/tool/state`, `/arm/state`): the same values the panels had, `null`
//! read back as NaN (shown as `?`, as live).

use serde_json::Value;

use crate::kortex::Telemetry;
use crate::kortex::cartesian::{Pose, Twist, Wrench};
use crate::kortex::codes::Coded;
use crate::kortex::flags::FlagSet;
use crate::kortex::telemetry::{ActionState, ArmHealth, JointState, SpeedLimits, ToolState};

/// A recorded number as the `f32` it was (`null`: not a number).
fn number(v: &Value) -> Option<f32> {
    match v {
        Value::Null => Some(f32::NAN),
        v => v.as_f64().map(|v| v as f32),
    }
}

fn numbers<const N: usize>(v: &Value) -> Option<[f32; N]> {
    let items = v.as_array().filter(|a| a.len() == N)?;
    let mut out = [0.0; N];
    for (slot, item) in out.iter_mut().zip(items) {
        *slot = number(item)?;
    }
    Some(out)
}

fn six(a: [f32; 3], b: [f32; 3]) -> [f32; 6] {
    [a[0], a[1], a[2], b[0], b[1], b[2]]
}

/// The sample the three messages of one time make; `None` if one is not what its schema says.
pub fn rebuild(joints: &Value, tool: &Value, arm: &Value) -> Option<Telemetry> {
    let column = |name: &str| numbers::<7>(&joints[name]);
    let (position, velocity, torque, current, temperature) = (
        column("position_deg")?,
        column("velocity_deg_s")?,
        column("torque_nm")?,
        column("current_a")?,
        column("temperature_c")?,
    );
    let joints = std::array::from_fn(|i| JointState {
        position: position[i],
        velocity: velocity[i],
        torque: torque[i],
        current: current[i],
        temperature: temperature[i],
    });
    let three = |name: &str| numbers::<3>(&tool[name]);
    let tcp = ToolState {
        pose: Pose::from_array(six(three("position_m")?, three("orientation_deg")?)),
        twist: Twist::from_array(six(three("linear_m_s")?, three("angular_deg_s")?)),
        wrench: Wrench::from_array(six(three("force_n")?, three("torque_nm")?)),
    };
    let names = |name: &str| -> Option<FlagSet> {
        let names = arm[name].as_array()?;
        FlagSet::from_names(names.iter().map(|n| n.as_str().unwrap_or("?")))
    };
    let code = |v: &Value| v.as_str().map(str::to_string);
    let action = &arm["action"];
    let health = &arm["health"];
    let limits = &arm["speed_limits"];
    Some(Telemetry {
        robot_state: Coded::from_key(&code(&arm["robot_state"])?)?,
        faults: names("faults")?,
        warnings: names("warnings")?,
        arm: ArmHealth {
            current: number(&health["current"])?,
            voltage: number(&health["voltage"])?,
            cpu_temperature: number(&health["cpu_temperature"])?,
            ambient_temperature: number(&health["ambient_temperature"])?,
        },
        joints,
        tcp,
        action: ActionState {
            status: Coded::from_key(&code(&action["status"])?)?,
            id: u16::try_from(action["id"].as_u64()?).ok()?,
            move_type: Coded::from_key(&code(&action["move_type"])?)?,
        },
        speed_limits: SpeedLimits {
            linear: number(&limits["linear"])?,
            angular: number(&limits["angular"])?,
        },
        control: Coded::Unknown(0),
        state_from_inputs: None,
    })
}
