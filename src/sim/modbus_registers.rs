//! The simulated arm as the Kinova Modbus ICD shows it: a snapshot's register image and what writes
//! do. Pure. A twist has no watchdog, like the real arm; unlisted addresses answer "illegal data
//! address".

use crate::kortex::CodeName;
use nalgebra::Vector3;

use super::arm_model::{ArmSnapshot, SimMotion};
use super::kinematics::Pose;
use super::stored;
use super::world::World;
use crate::kortex::registers::{
    coil, discrete_input as di, holding_register as hr, input_register as ir,
};
use crate::kortex::two_registers::{f32_from_words, f32_to_words, u32_to_words};
use crate::kortex::{MoveType, ReferenceFrame};

pub use super::stored::HOME_ACTION_ID;

/// Listed address ranges (start, end exclusive), per table.
pub const DISCRETE_INPUTS: [(u16, u16); 3] = [(0, 10), (32, 63), (64, 95)];
pub const INPUT_REGISTERS: [(u16, u16); 3] = [(0, 1), (2, 14), (34, 140)];
pub const HOLDING_REGISTERS: [(u16, u16); 4] = [(0, 1), (100, 103), (104, 108), (200, 220)];
pub const COILS: [(u16, u16); 1] = [(0, 3)];
/// Only the command block can be written.
const WRITABLE: (u16, u16) = (200, 220);

/// A request that cannot be served.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refused {
    IllegalAddress,
    IllegalValue,
}

/// Whether all of `start..start+count` is listed; in u32, so a range past 65535 cannot wrap.
pub fn listed(ranges: &[(u16, u16)], start: u16, count: u16) -> bool {
    let start = u32::from(start);
    let end = start + u32::from(count);
    count > 0
        && end <= 0x1_0000
        && (start..end).all(|a| {
            ranges
                .iter()
                .any(|(s, e)| a >= u32::from(*s) && a < u32::from(*e))
        })
}

/// Input registers 0-139 of a snapshot.
pub fn input_registers(s: &ArmSnapshot) -> [u16; 140] {
    let mut r = [0u16; 140];
    let mut put = |addr: u16, words: [u16; 2]| {
        let a = usize::from(addr);
        r[a..a + 2].copy_from_slice(&words);
    };
    put(ir::FAULT_FLAGS, u32_to_words(s.faults));
    put(ir::WARNING_FLAGS, u32_to_words(s.warnings));
    let six = |a: [f64; 3], b: [f64; 3]| [a[0], a[1], a[2], b[0], b[1], b[2]];
    let pose = six(s.tcp_position, s.tcp_orientation);
    let twist = six(s.tcp_linear_velocity, s.tcp_angular_velocity);
    let wrench = six(s.tcp_force, s.tcp_torque);
    // Each block's floats end to end, two registers each.
    for (block, values) in [
        (ir::ARM_CURRENT, &[s.arm_current][..]),
        (ir::ARM_VOLTAGE, &[s.arm_voltage]),
        (ir::ARM_CPU_TEMPERATURE, &[s.cpu_temperature]),
        (ir::ARM_AMBIENT_TEMPERATURE, &[s.ambient_temperature]),
        (ir::JOINT_POSITIONS, &s.joint_position),
        (ir::JOINT_VELOCITIES, &s.joint_velocity),
        (ir::JOINT_TORQUES, &s.joint_torque),
        (ir::JOINT_CURRENTS, &s.joint_current),
        (ir::JOINT_MOTOR_TEMPERATURES, &s.joint_temperature),
        (ir::TCP_POSE, &pose),
        (ir::TCP_TWIST, &twist),
        (ir::TCP_WRENCH, &wrench),
    ] {
        for (k, v) in (0u16..).zip(values) {
            put(block + 2 * k, f32_to_words(*v as f32));
        }
    }
    r[usize::from(ir::ROBOT_STATE)] = s.robot_state.code();
    r
}

/// Discrete inputs 0-94: the state one-hot, then fault and warning bits.
pub fn discrete_inputs(s: &ArmSnapshot) -> [bool; 95] {
    let mut d = [false; 95];
    if let Some(slot) = d.get_mut(usize::from(s.robot_state.code())) {
        *slot = true;
    }
    for bit in 0..31u16 {
        d[usize::from(di::FAULT_FLAGS + bit)] = s.faults & (1 << bit) != 0;
        d[usize::from(di::WARNING_FLAGS + bit)] = s.warnings & (1 << bit) != 0;
    }
    d
}

/// Holding registers 0-219: action state, speed limits, and the command block as written.
pub fn holding_registers(s: &ArmSnapshot, command_block: &[u16; 20]) -> [u16; 220] {
    let mut h = [0u16; 220];
    h[usize::from(hr::ACTION_STATUS)] = s.action_status.code();
    h[usize::from(hr::ACTION_ID)] = s.action_id;
    h[usize::from(hr::ACTION_MOVE_TYPE)] = s.move_type;
    h[104..106].copy_from_slice(&f32_to_words(s.speed_limit_linear as f32));
    h[106..108].copy_from_slice(&f32_to_words(s.speed_limit_angular_deg as f32));
    h[200..220].copy_from_slice(command_block);
    h
}

fn float_at(block: &[u16; 20], addr: u16) -> f32 {
    let i = usize::from(addr - WRITABLE.0);
    f32_from_words([block[i], block[i + 1]])
}

/// Writes registers `start..` of the command block and carries out what they ask.
pub fn write_registers(world: &mut World, start: u16, values: &[u16]) -> Result<(), Refused> {
    let count = u16::try_from(values.len()).ok().filter(|count| *count > 0);
    let count = count.ok_or(Refused::IllegalValue)?;
    let end = u32::from(start) + u32::from(count);
    if start < WRITABLE.0 || end > u32::from(WRITABLE.1) {
        return Err(Refused::IllegalAddress);
    }
    let mut block = world.command_block;
    let at = usize::from(start - WRITABLE.0);
    block[at..at + values.len()].copy_from_slice(values);
    let touches = |addr: u16| u32::from(start) <= u32::from(addr) && u32::from(addr) < end;
    if touches(hr::DESIRED_LINEAR_SPEED_LIMIT) || touches(hr::DESIRED_ANGULAR_SPEED_LIMIT) {
        // A limit not written yet (still 0) keeps the one in force.
        let (current_linear, current_angular) = world.arm.speed_limits();
        let pick = |addr: u16, current: f64| match float_at(&block, addr) {
            0.0 => Ok(current),
            v if v.is_finite() && v > 0.0 => Ok(f64::from(v)),
            _ => Err(Refused::IllegalValue),
        };
        let linear = pick(hr::DESIRED_LINEAR_SPEED_LIMIT, current_linear)?;
        let angular = pick(hr::DESIRED_ANGULAR_SPEED_LIMIT, current_angular)?;
        world
            .arm
            .set_speed_limits(linear, angular)
            .map_err(|_| Refused::IllegalValue)?;
    }
    // Only a write the arm accepted lands in the block.
    world.command_block = block;
    if touches(hr::COMMAND) {
        execute(world);
    }
    Ok(())
}

/// Whether the pose/twist floats (registers 204-215) are all finite; logs each one that is not.
fn command_floats_finite(block: &[u16; 20]) -> bool {
    let mut finite = true;
    for addr in (204..=214).step_by(2) {
        let value = float_at(block, addr);
        if !value.is_finite() {
            tracing::warn!(
                register = addr,
                %value,
                action_type = block[2],
                "modbus: refused a start with a non-finite value in holding register {addr}: {value}"
            );
            finite = false;
        }
    }
    finite
}

/// Register 200: 0 none, 1 start what 201-215 describe, 2 stop.
fn execute(world: &mut World) {
    let block = world.command_block;
    match block[0] {
        2 => world.arm.stop(),
        1 => {
            let id = block[1];
            let move_type = MoveType::from_code(block[2]);
            let cartesian = matches!(
                move_type,
                Some(MoveType::CartesianTrajectory | MoveType::Twist)
            );
            if cartesian && !command_floats_finite(&block) {
                // Like the real arm: aborted, nothing moves (its client asked for something else).
                world.arm.stop();
                world.arm.mark_aborted();
                return;
            }
            if matches!(move_type, Some(MoveType::Action | MoveType::Sequence)) {
                start_stored(world, id, block[2]);
                return;
            }
            let v = |a: u16| f64::from(float_at(&block, a));
            let motion = match move_type {
                Some(MoveType::CartesianTrajectory) => {
                    let pose = Pose::from_position_euler_deg(
                        [v(204), v(206), v(208)],
                        [v(210), v(212), v(214)],
                    );
                    let (linear, angular) = world.arm.speed_limits();
                    SimMotion::ToPose {
                        target: pose,
                        linear_speed: linear,
                        angular_speed: angular.to_radians(),
                    }
                }
                // An unknown frame code falls back to the base frame, as before.
                Some(MoveType::Twist) => SimMotion::Twist {
                    linear: Vector3::new(v(204), v(206), v(208)),
                    angular: Vector3::new(v(210), v(212), v(214)).map(f64::to_radians),
                    frame: ReferenceFrame::from_code(block[3]).unwrap_or(ReferenceFrame::Base),
                },
                // Unknown move types: nothing to run.
                _ => return world.arm.mark_aborted(),
            };
            // Refused: aborted, no flag (as the real arm).
            if world.arm.command(motion, 0.0, false).is_err() {
                world.arm.mark_aborted();
            }
        }
        _ => {}
    }
}

/// Starts stored action (move type 0) or sequence (1) `id`. An unknown id or a refused start shows
/// as aborted naming the id and type, so a client can tell its refusal from an older status.
fn start_stored(world: &mut World, id: u16, move_type: u16) {
    let started = match stored::steps(id, move_type) {
        Some(steps) => world.arm.command_stored(id, move_type, steps).is_ok(),
        None => {
            world.arm.set_action(id, move_type);
            false
        }
    };
    if !started {
        world.arm.mark_aborted();
    }
}

/// Coils: quick stop faults, abort stops, fault reset clears; false does nothing (pulsed).
pub fn write_coil(world: &mut World, addr: u16, value: bool) -> Result<(), Refused> {
    if !listed(&COILS, addr, 1) {
        return Err(Refused::IllegalAddress);
    }
    if value {
        match addr {
            coil::QUICK_STOP => world.arm.quick_stop(),
            coil::ABORT => world.arm.stop(),
            coil::FAULT_RESET => world.arm.fault_reset(),
            _ => {}
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kortex::ActionStatus;
    use crate::kortex::Flag;

    #[test]
    fn a_linear_limit_alone_keeps_the_angular_one() {
        let mut world = World::default();
        // 0.2 m/s = 0x3E4CCCCD, low word first.
        write_registers(&mut world, 216, &[0xCCCD, 0x3E4C]).expect("accepted");
        let (linear, angular) = world.arm.speed_limits();
        assert!((linear - 0.2).abs() < 1e-6 && (angular - 100.0).abs() < 1e-9);
    }

    #[test]
    fn a_non_finite_limit_is_refused_and_not_stored() {
        let mut world = World::default();
        // NaN = 0x7FC00000.
        assert_eq!(
            write_registers(&mut world, 218, &[0x0000, 0x7FC0]),
            Err(Refused::IllegalValue)
        );
        assert_eq!(world.command_block[18..20], [0, 0]);
    }

    /// Writes a twist (type 3) or cartesian move (type 2) with `bad` in register `addr`
    /// (the others zero, or the current pose for a move) and starts it.
    fn start_with(world: &mut World, action_type: u16, addr: u16, bad: f32) {
        let mut values = [0u16; 16];
        if action_type == 2 {
            let start = world.arm.pose();
            let (x, y, z) = (start.position.x, start.position.y, start.position.z);
            let (rx, ry, rz) = start.rotation.euler_angles();
            let floats = [x, y, z, rx.to_degrees(), ry.to_degrees(), rz.to_degrees()];
            for (i, f) in floats.iter().enumerate() {
                values[4 + 2 * i..6 + 2 * i].copy_from_slice(&f32_to_words(*f as f32));
            }
        }
        let i = usize::from(addr - 200);
        values[i..i + 2].copy_from_slice(&f32_to_words(bad));
        values[0] = 1;
        values[1] = 7;
        values[2] = action_type;
        write_registers(world, 200, &values).expect("the write itself is accepted");
    }

    #[test]
    fn a_non_finite_twist_or_move_is_aborted_and_nothing_moves() {
        for action_type in [2u16, 3] {
            for addr in (204..=214).step_by(2) {
                for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
                    let mut world = World::default();
                    let before = world.arm.joints();
                    start_with(&mut world, action_type, addr, bad);
                    world.arm.advance(0.3);
                    let snap = world.arm.snapshot();
                    let case = format!("type {action_type}, register {addr}, {bad}");
                    assert_eq!(world.arm.joints(), before, "{case}: moved");
                    assert!(!world.arm.is_moving(), "{case}: still moving");
                    assert_eq!(snap.action_status, ActionStatus::Aborted, "{case}");
                    assert_eq!(
                        snap.warnings & Flag::JointFault.bit(),
                        0,
                        "{case}: joint fault"
                    );
                }
            }
        }
    }

    #[test]
    fn a_finite_twist_still_moves() {
        let mut world = World::default();
        let before = world.arm.joints();
        start_with(&mut world, 3, 204, 0.05);
        world.arm.advance(0.3);
        assert_ne!(world.arm.joints(), before);
        assert_ne!(world.arm.snapshot().action_status, ActionStatus::Aborted);
    }
}
