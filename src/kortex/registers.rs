//! Every address of the Kinova Kortex Modbus ICD; two-register values name their first.

/// The four Modbus data tables.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Table {
    /// Read/write bits: function codes 01, 05, 15.
    Coils,
    /// Read-only bits: function code 02.
    DiscreteInputs,
    /// Read-only registers: function code 04.
    InputRegisters,
    /// Read/write registers: function codes 03, 06, 16.
    HoldingRegisters,
}

impl Table {
    /// The function code that reads this table.
    pub fn read_function_code(self) -> u8 {
        match self {
            Table::Coils => 0x01,
            Table::DiscreteInputs => 0x02,
            Table::HoldingRegisters => 0x03,
            Table::InputRegisters => 0x04,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Table::Coils => "coils",
            Table::DiscreteInputs => "discrete inputs",
            Table::InputRegisters => "input registers",
            Table::HoldingRegisters => "holding registers",
        }
    }

    /// The most items one read may ask for (Modbus application protocol, section 6).
    pub fn max_read(self) -> u16 {
        match self {
            Table::Coils | Table::DiscreteInputs => 2000,
            Table::InputRegisters | Table::HoldingRegisters => 125,
        }
    }
}

/// The most registers one write-multiple-registers request (FC16) may carry.
pub const MAX_REGISTERS_PER_WRITE: u16 = 123;

/// Discrete inputs (function code 02).
pub mod discrete_input {
    /// Robot state 0-9, one input per [`RobotState`](crate::kortex::RobotState) code.
    pub const ROBOT_STATES: u16 = 0;
    pub const ROBOT_STATE_COUNT: u16 = 10;
    /// Fault flags 32-62: input 32 + the flag's bit number.
    pub const FAULT_FLAGS: u16 = 32;
    /// Warning flags 64-94: input 64 + the flag's bit number.
    pub const WARNING_FLAGS: u16 = 64;
    /// One past the last flag input of either block (bit 30 is the highest the ICD names).
    pub const FLAG_COUNT: u16 = 31;
    /// One past the last discrete input of the ICD.
    pub const END: u16 = 95;
}

/// Coils (function codes 01, 05, 15): see [`ControlCoil`](crate::kortex::ControlCoil).
pub mod coil {
    pub const QUICK_STOP: u16 = 0;
    pub const ABORT: u16 = 1;
    pub const FAULT_RESET: u16 = 2;
    pub const END: u16 = 3;
}

/// Input registers (function code 04).
pub mod input_register {
    use crate::kortex::Axis;

    /// uint16: the [`RobotState`](crate::kortex::RobotState) code.
    pub const ROBOT_STATE: u16 = 0;
    /// uint32 bitmask (2-3): fault flags by bit.
    pub const FAULT_FLAGS: u16 = 2;
    /// uint32 bitmask (4-5): warning flags, same bits as the faults.
    pub const WARNING_FLAGS: u16 = 4;
    /// float, A (6-7).
    pub const ARM_CURRENT: u16 = 6;
    /// float, V (8-9).
    pub const ARM_VOLTAGE: u16 = 8;
    /// float, deg C (10-11).
    pub const ARM_CPU_TEMPERATURE: u16 = 10;
    /// float, deg C (12-13).
    pub const ARM_AMBIENT_TEMPERATURE: u16 = 12;
    /// Seven floats per block, joint 1 first.
    pub const JOINT_POSITIONS: u16 = 34;
    pub const JOINT_VELOCITIES: u16 = 48;
    pub const JOINT_TORQUES: u16 = 62;
    pub const JOINT_CURRENTS: u16 = 76;
    pub const JOINT_MOTOR_TEMPERATURES: u16 = 90;
    /// Six floats per block in [`Axis`] order: x, y, z (m, m/s, N), then theta x, y, z
    /// (deg, deg/s, N m).
    pub const TCP_POSE: u16 = 104;
    pub const TCP_TWIST: u16 = 116;
    pub const TCP_WRENCH: u16 = 128;
    /// One past the last input register of the ICD.
    pub const END: u16 = 140;

    /// The seven joints of a Gen3 (a 6-DOF arm leaves joint 7 at zero).
    pub const JOINTS: u16 = 7;

    /// First register of a joint's value in a per-joint block; `joint` counts from 1.
    pub const fn joint(block: u16, joint: u16) -> u16 {
        block + 2 * (joint - 1)
    }

    /// First register of one axis in a TCP block.
    pub const fn tcp(block: u16, axis: Axis) -> u16 {
        block + 2 * axis as u16
    }
}

/// Holding registers (function codes 03, 06, 16).
pub mod holding_register {
    use crate::kortex::Axis;

    /// uint16, read only: the coils' control actions (0 quick stop, 1 abort, 2 fault reset).
    pub const CONTROL: u16 = 0;
    /// uint16, read only: [`ActionStatus`](crate::kortex::ActionStatus) of the running action.
    pub const ACTION_STATUS: u16 = 100;
    /// uint16, read only: id of the active action or sequence.
    pub const ACTION_ID: u16 = 101;
    /// uint16, read only: [`MoveType`](crate::kortex::MoveType) of the active motion.
    pub const ACTION_MOVE_TYPE: u16 = 102;
    /// float, m/s, read only (104-105).
    pub const LINEAR_SPEED_LIMIT: u16 = 104;
    /// float, deg/s, read only (106-107).
    pub const ANGULAR_SPEED_LIMIT: u16 = 106;
    /// One past the last read-only holding register.
    pub const READ_END: u16 = 108;

    /// uint16: an [`ActionCommand`](crate::kortex::ActionCommand): 0 none, 1 start, 2 stop.
    pub const COMMAND: u16 = 200;
    /// uint16: id of the action or sequence to start.
    pub const COMMAND_ID: u16 = 201;
    /// uint16: [`MoveType`](crate::kortex::MoveType) to start.
    pub const COMMAND_MOVE_TYPE: u16 = 202;
    /// uint16: [`ReferenceFrame`](crate::kortex::ReferenceFrame) of 204-215.
    pub const REFERENCE_FRAME: u16 = 203;
    /// Six floats (204-215) in [`Axis`] order: a pose (m, deg) for a cartesian trajectory, a
    /// velocity (m/s, deg/s) for a twist. The ICD's "m" unit on 210-215 is a typo for deg.
    pub const TARGET: u16 = 204;
    /// float, m/s (216-217).
    pub const DESIRED_LINEAR_SPEED_LIMIT: u16 = 216;
    /// float, deg/s (218-219).
    pub const DESIRED_ANGULAR_SPEED_LIMIT: u16 = 218;
    /// One past the last holding register of the ICD.
    pub const END: u16 = 220;

    /// First register of one axis of the target.
    pub const fn target(axis: Axis) -> u16 {
        TARGET + 2 * axis as u16
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kortex::Axis;

    #[test]
    fn block_arithmetic_matches_the_icd_tables() {
        assert_eq!(
            input_register::joint(input_register::JOINT_POSITIONS, 7),
            46
        );
        assert_eq!(
            input_register::joint(input_register::JOINT_VELOCITIES, 1),
            48
        );
        assert_eq!(input_register::joint(input_register::JOINT_TORQUES, 7), 74);
        assert_eq!(input_register::joint(input_register::JOINT_CURRENTS, 1), 76);
        assert_eq!(
            input_register::joint(input_register::JOINT_MOTOR_TEMPERATURES, 7),
            102
        );
        assert_eq!(
            input_register::tcp(input_register::TCP_POSE, Axis::ThetaZ),
            114
        );
        assert_eq!(input_register::tcp(input_register::TCP_TWIST, Axis::X), 116);
        assert_eq!(
            input_register::tcp(input_register::TCP_WRENCH, Axis::ThetaZ),
            138
        );
        assert_eq!(holding_register::target(Axis::ThetaZ), 214);
    }
}
