//! The register image a poll fills, and the reads that fill it.

use std::fmt;

use super::registers::{Table, discrete_input as di, holding_register as hr, input_register as ir};
use super::two_registers;

/// One read request: `count` items of `table` from `start`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ReadBlock {
    pub table: Table,
    pub start: u16,
    pub count: u16,
}

impl ReadBlock {
    pub const fn new(table: Table, start: u16, end: u16) -> ReadBlock {
        ReadBlock {
            table,
            start,
            count: end - start,
        }
    }

    /// One past the last item read.
    pub fn end(self) -> u16 {
        self.start + self.count
    }
}

impl fmt::Display for ReadBlock {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "read {} {}-{} (FC{:02})",
            self.table.name(),
            self.start,
            self.end().saturating_sub(1),
            self.table.read_function_code()
        )
    }
}

use Table::{DiscreteInputs as DI, HoldingRegisters as HR, InputRegisters as IR};

/// Which reads make up one complete snapshot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PollPlan {
    /// The fewest requests the 125-register limit allows (4), spanning unlisted addresses.
    #[default]
    Compact,
    /// One read per ICD block (9), for an arm that refuses reads over unlisted addresses.
    IcdBlocks,
}

const COMPACT: [ReadBlock; 4] = [
    ReadBlock::new(DI, 0, di::END),
    ReadBlock::new(IR, ir::ROBOT_STATE, ir::ARM_CURRENT + 8),
    ReadBlock::new(IR, ir::JOINT_POSITIONS, ir::END),
    ReadBlock::new(HR, hr::CONTROL, hr::READ_END),
];

const ICD_BLOCKS: [ReadBlock; 9] = [
    ReadBlock::new(DI, di::ROBOT_STATES, di::ROBOT_STATE_COUNT),
    ReadBlock::new(DI, di::FAULT_FLAGS, di::FAULT_FLAGS + 31),
    ReadBlock::new(DI, di::WARNING_FLAGS, di::END),
    ReadBlock::new(IR, ir::ROBOT_STATE, 1),
    ReadBlock::new(IR, ir::FAULT_FLAGS, ir::ARM_CURRENT + 8),
    ReadBlock::new(IR, ir::JOINT_POSITIONS, ir::END),
    ReadBlock::new(HR, hr::CONTROL, 1),
    ReadBlock::new(HR, hr::ACTION_STATUS, hr::ACTION_MOVE_TYPE + 1),
    ReadBlock::new(HR, hr::LINEAR_SPEED_LIMIT, hr::READ_END),
];

/// Blocks that need not be read in every snapshot: the robot-state and warning flag inputs (input
/// registers 0 and 4-5 say the same), the control register, and the speed limits (the integrator's;
/// the link reads them afresh around a capped move). A strict arm's plan reads them every
/// [`SLOW_REFRESH`]; the fault flags are read in every snapshot.
const ICD_SLOW: [ReadBlock; 4] = [ICD_BLOCKS[0], ICD_BLOCKS[2], ICD_BLOCKS[6], ICD_BLOCKS[8]];

/// How often the slow blocks are read.
pub const SLOW_REFRESH: std::time::Duration = std::time::Duration::from_secs(1);

impl PollPlan {
    /// Whether `block` may be read less often than each snapshot (see [`SLOW_REFRESH`]).
    pub fn is_slow(self, block: ReadBlock) -> bool {
        self == PollPlan::IcdBlocks && ICD_SLOW.contains(&block)
    }

    pub fn blocks(self) -> &'static [ReadBlock] {
        match self {
            PollPlan::Compact => &COMPACT,
            PollPlan::IcdBlocks => &ICD_BLOCKS,
        }
    }
}

/// What a read returned that cannot be stored.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ImageError {
    #[error("{block}: {got} values in the reply, expected {expected}")]
    WrongCount {
        block: ReadBlock,
        expected: u16,
        got: usize,
    },
    #[error("{block}: outside the ICD's addresses")]
    OutsideImage { block: ReadBlock },
    #[error("{block}: {table} carry {kind}")]
    WrongKind {
        block: ReadBlock,
        table: &'static str,
        kind: &'static str,
    },
}

/// Every readable address of the ICD, as last read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RegisterImage {
    pub discrete_inputs: [bool; di::END as usize],
    pub input_registers: [u16; ir::END as usize],
    pub holding_registers: [u16; hr::READ_END as usize],
}

impl Default for RegisterImage {
    fn default() -> Self {
        RegisterImage {
            discrete_inputs: [false; di::END as usize],
            input_registers: [0; ir::END as usize],
            holding_registers: [0; hr::READ_END as usize],
        }
    }
}

impl RegisterImage {
    /// Stores the registers one read returned. The reply must hold exactly `block.count`.
    pub fn store_words(&mut self, block: ReadBlock, values: &[u16]) -> Result<(), ImageError> {
        let target: &mut [u16] = match block.table {
            Table::InputRegisters => &mut self.input_registers,
            Table::HoldingRegisters => &mut self.holding_registers,
            Table::Coils | Table::DiscreteInputs => {
                return Err(ImageError::WrongKind {
                    block,
                    table: block.table.name(),
                    kind: "bits, not registers",
                });
            }
        };
        if values.len() != usize::from(block.count) {
            return Err(ImageError::WrongCount {
                block,
                expected: block.count,
                got: values.len(),
            });
        }
        let slot = target
            .get_mut(usize::from(block.start)..usize::from(block.end()))
            .ok_or(ImageError::OutsideImage { block })?;
        slot.copy_from_slice(values);
        Ok(())
    }

    /// Stores one read's bits; the up to 7 padding bits Modbus adds are dropped.
    pub fn store_bits(&mut self, block: ReadBlock, values: &[bool]) -> Result<(), ImageError> {
        if block.table != Table::DiscreteInputs {
            return Err(ImageError::WrongKind {
                block,
                table: block.table.name(),
                kind: "registers, not the polled bits",
            });
        }
        let count = usize::from(block.count);
        if values.len() < count || values.len() > count.div_ceil(8) * 8 {
            return Err(ImageError::WrongCount {
                block,
                expected: block.count,
                got: values.len(),
            });
        }
        let slot = self
            .discrete_inputs
            .get_mut(usize::from(block.start)..usize::from(block.end()))
            .ok_or(ImageError::OutsideImage { block })?;
        slot.copy_from_slice(&values[..count]);
        Ok(())
    }

    /// The float at input register `addr` (and `addr + 1`).
    pub fn input_f32(&self, addr: u16) -> f32 {
        two_registers::f32_from_words(pair(&self.input_registers, addr))
    }

    /// The uint32 at input register `addr` (and `addr + 1`).
    pub fn input_u32(&self, addr: u16) -> u32 {
        two_registers::u32_from_words(pair(&self.input_registers, addr))
    }

    /// The float at holding register `addr` (and `addr + 1`).
    pub fn holding_f32(&self, addr: u16) -> f32 {
        two_registers::f32_from_words(pair(&self.holding_registers, addr))
    }

    /// The discrete inputs `start..start + count`.
    pub fn inputs(&self, start: u16, count: u16) -> &[bool] {
        let start = usize::from(start);
        self.discrete_inputs
            .get(start..start + usize::from(count))
            .unwrap_or(&[])
    }
}

/// Two registers from a table; a miss (a bug, never network data) reads zero, not a panic.
fn pair(table: &[u16], addr: u16) -> [u16; 2] {
    let at = |a: usize| table.get(a).copied().unwrap_or(0);
    [at(usize::from(addr)), at(usize::from(addr) + 1)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plans_respect_the_read_limits_and_cover_the_icd() {
        for plan in [PollPlan::Compact, PollPlan::IcdBlocks] {
            let mut image = RegisterImage::default();
            for block in plan.blocks() {
                assert!(block.count >= 1 && block.count <= block.table.max_read());
                match block.table {
                    Table::DiscreteInputs => image
                        .store_bits(*block, &vec![true; usize::from(block.count)])
                        .unwrap(),
                    _ => image
                        .store_words(*block, &vec![1; usize::from(block.count)])
                        .unwrap(),
                }
            }
            let covered = |table: &[u16], a: u16| table[usize::from(a)] == 1;
            for a in (0..14).filter(|a| *a != 1).chain(34..140) {
                assert!(covered(&image.input_registers, a), "{plan:?} IR {a}");
            }
            for a in [0].into_iter().chain(100..103).chain(104..108) {
                assert!(covered(&image.holding_registers, a), "{plan:?} HR {a}");
            }
            for a in (0..10).chain(32..63).chain(64..95) {
                assert!(image.discrete_inputs[a], "{plan:?} DI {a}");
            }
        }
        assert_eq!(PollPlan::Compact.blocks().len(), 4);
    }

    #[test]
    fn only_the_strict_plans_state_warning_control_and_limit_blocks_are_slow() {
        assert!(
            PollPlan::Compact
                .blocks()
                .iter()
                .all(|b| !PollPlan::Compact.is_slow(*b))
        );
        let slow: Vec<(Table, u16, u16)> = PollPlan::IcdBlocks
            .blocks()
            .iter()
            .filter(|b| PollPlan::IcdBlocks.is_slow(**b))
            .map(|b| (b.table, b.start, b.count))
            .collect();
        assert_eq!(
            slow,
            [
                (Table::DiscreteInputs, 0, 10),
                (Table::DiscreteInputs, 64, 31),
                (Table::HoldingRegisters, 0, 1),
                (Table::HoldingRegisters, 104, 4)
            ]
        );
    }

    #[test]
    fn short_and_misdirected_replies_are_refused() {
        let mut image = RegisterImage::default();
        let block = ReadBlock::new(Table::InputRegisters, 0, 14);
        assert!(matches!(
            image.store_words(block, &[0; 13]),
            Err(ImageError::WrongCount { got: 13, .. })
        ));
        let bits = ReadBlock::new(Table::DiscreteInputs, 0, 10);
        assert!(image.store_bits(bits, &[false; 16]).is_ok());
        assert!(image.store_bits(bits, &[false; 17]).is_err());
        assert!(image.store_words(bits, &[0; 10]).is_err());
        let beyond = ReadBlock::new(Table::HoldingRegisters, 100, 120);
        assert!(matches!(
            image.store_words(beyond, &[0; 20]),
            Err(ImageError::OutsideImage { .. })
        ));
    }
}
