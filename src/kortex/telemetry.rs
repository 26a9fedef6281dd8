//! One decoded snapshot of the arm; serialises to `armjog status --json`.

use serde::Serialize;

use super::cartesian::{Axis, Pose, Twist, Wrench};
use super::codes::{ActionStatus, CodeName, Coded, ControlCoil, MoveType, RobotState};
use super::flags::FlagSet;
use super::image::RegisterImage;
use super::registers::{discrete_input as di, holding_register as hr, input_register as ir};

/// Arm-level health (input registers 6-13).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct ArmHealth {
    /// A.
    pub current: f32,
    /// V.
    pub voltage: f32,
    /// deg C.
    pub cpu_temperature: f32,
    /// deg C.
    pub ambient_temperature: f32,
}

/// One joint (input registers 34-103).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct JointState {
    /// deg, reported 0-360.
    pub position: f32,
    /// deg/s.
    pub velocity: f32,
    /// N m.
    pub torque: f32,
    /// A.
    pub current: f32,
    /// Motor temperature, deg C.
    pub temperature: f32,
}

/// The tool centre point (input registers 104-139).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct ToolState {
    pub pose: Pose,
    pub twist: Twist,
    pub wrench: Wrench,
}

/// The running action or sequence (holding registers 100-102).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ActionState {
    pub status: Coded<ActionStatus>,
    pub id: u16,
    pub move_type: Coded<MoveType>,
}

/// The cartesian speed limits in force (holding registers 104-107).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct SpeedLimits {
    /// m/s.
    pub linear: f32,
    /// deg/s.
    pub angular: f32,
}

/// A complete snapshot. Every readable address of the ICD lands in one field.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Telemetry {
    /// Input register 0; discrete inputs 0-9 stand in when it holds a number the ICD does not
    /// list (unless they only say "unspecified": the unknown number then shows).
    pub robot_state: Coded<RobotState>,
    /// Input registers 2-3 and discrete inputs 32-62 together: a flag raised in either shows.
    pub faults: FlagSet,
    /// Input registers 4-5 and discrete inputs 64-94 together.
    pub warnings: FlagSet,
    pub arm: ArmHealth,
    pub joints: [JointState; ir::JOINTS as usize],
    pub tcp: ToolState,
    pub action: ActionState,
    pub speed_limits: SpeedLimits,
    /// Holding register 0 (read only), the control coils' list. Not in the JSON.
    #[serde(skip)]
    pub control: Coded<ControlCoil>,
    /// The state discrete inputs 0-9 report (the first one on), to compare with register 0.
    #[serde(skip)]
    pub state_from_inputs: Option<RobotState>,
}

impl Telemetry {
    /// Decodes a snapshot; every bit pattern decodes (NaN, `Coded::Unknown`, unknown bits).
    pub fn decode(image: &RegisterImage) -> Telemetry {
        let state_from_inputs = image
            .inputs(di::ROBOT_STATES, di::ROBOT_STATE_COUNT)
            .iter()
            .position(|on| *on)
            .and_then(|code| RobotState::from_code(code as u16));
        let robot_state = match (
            Coded::<RobotState>::from_code(image.input_registers[usize::from(ir::ROBOT_STATE)]),
            state_from_inputs,
        ) {
            // "Unspecified" from the inputs says nothing: the register's own number shows.
            (Coded::Unknown(_), Some(state)) if state != RobotState::Unspecified => {
                Coded::Known(state)
            }
            (from_register, _) => from_register,
        };

        let flags = |register: u16, inputs: u16| {
            FlagSet::from_bits(image.input_u32(register))
                .union(FlagSet::from_inputs(image.inputs(inputs, di::FLAG_COUNT)))
        };

        let joint = |j: u16| JointState {
            position: image.input_f32(ir::joint(ir::JOINT_POSITIONS, j)),
            velocity: image.input_f32(ir::joint(ir::JOINT_VELOCITIES, j)),
            torque: image.input_f32(ir::joint(ir::JOINT_TORQUES, j)),
            current: image.input_f32(ir::joint(ir::JOINT_CURRENTS, j)),
            temperature: image.input_f32(ir::joint(ir::JOINT_MOTOR_TEMPERATURES, j)),
        };

        let six = |block: u16| {
            use Axis::{ThetaX, ThetaY, ThetaZ, X, Y, Z};
            [X, Y, Z, ThetaX, ThetaY, ThetaZ].map(|axis| image.input_f32(ir::tcp(block, axis)))
        };

        let holding = |addr: u16| image.holding_registers[usize::from(addr)];

        Telemetry {
            robot_state,
            faults: flags(ir::FAULT_FLAGS, di::FAULT_FLAGS),
            warnings: flags(ir::WARNING_FLAGS, di::WARNING_FLAGS),
            arm: ArmHealth {
                current: image.input_f32(ir::ARM_CURRENT),
                voltage: image.input_f32(ir::ARM_VOLTAGE),
                cpu_temperature: image.input_f32(ir::ARM_CPU_TEMPERATURE),
                ambient_temperature: image.input_f32(ir::ARM_AMBIENT_TEMPERATURE),
            },
            joints: [1, 2, 3, 4, 5, 6, 7].map(joint),
            tcp: ToolState {
                pose: Pose::from_array(six(ir::TCP_POSE)),
                twist: Twist::from_array(six(ir::TCP_TWIST)),
                wrench: Wrench::from_array(six(ir::TCP_WRENCH)),
            },
            action: ActionState {
                status: Coded::from_code(holding(hr::ACTION_STATUS)),
                id: holding(hr::ACTION_ID),
                move_type: Coded::from_code(holding(hr::ACTION_MOVE_TYPE)),
            },
            speed_limits: SpeedLimits {
                linear: image.holding_f32(hr::LINEAR_SPEED_LIMIT),
                angular: image.holding_f32(hr::ANGULAR_SPEED_LIMIT),
            },
            control: Coded::from_code(holding(hr::CONTROL)),
            state_from_inputs,
        }
    }
}
