//! Field checks and the hardware view of the shared big-endian reader.

use std::cmp::Ordering;

use super::{HwError, JOINT_COUNT};
use crate::talos::reader::{BeReader, Short};

pub(super) fn check_joint(joint: u8) -> Result<(), HwError> {
    ensure(
        (1..=JOINT_COUNT).contains(&joint),
        HwError::JointOutOfRange(joint),
    )
}

pub(super) fn check_selector(selector: u8) -> Result<(), HwError> {
    ensure(
        selector <= JOINT_COUNT,
        HwError::SelectorOutOfRange(selector),
    )
}

pub(super) fn check_order(previous: u8, joint: u8) -> Result<(), HwError> {
    ensure(joint > previous, HwError::JointOrder { previous, joint })
}

pub(super) fn check_finite(field: &'static str, value: f32) -> Result<(), HwError> {
    ensure(value.is_finite(), HwError::NonFinite { field })
}

fn ensure(holds: bool, error: HwError) -> Result<(), HwError> {
    holds.then_some(()).ok_or(error)
}

/// The shared reader ([`crate::talos::reader`]) over a payload of checked length.
pub(super) struct Reader<'a> {
    bytes: BeReader<'a>,
    subcommand: u16,
    len: usize,
}

impl<'a> Reader<'a> {
    /// A reader over `payload`, or TooShort/TooLong if it is not exactly `expected` bytes.
    pub(super) fn exact(
        subcommand: u16,
        payload: &'a [u8],
        expected: usize,
    ) -> Result<Self, HwError> {
        let got = payload.len();
        match got.cmp(&expected) {
            Ordering::Less => Err(HwError::TooShort {
                subcommand,
                expected,
                got,
            }),
            Ordering::Greater => Err(HwError::TooLong {
                subcommand,
                expected,
                got,
            }),
            Ordering::Equal => Ok(Reader {
                bytes: BeReader::new(payload),
                subcommand,
                len: got,
            }),
        }
    }

    /// Unreachable after `exact`, but reported rather than assumed.
    fn too_short(&self, short: Short) -> HwError {
        HwError::TooShort {
            subcommand: self.subcommand,
            expected: self.len - short.available + short.needed,
            got: self.len,
        }
    }

    pub(super) fn u8(&mut self) -> Result<u8, HwError> {
        self.bytes.u8("u8").map_err(|s| self.too_short(s))
    }

    pub(super) fn u16(&mut self) -> Result<u16, HwError> {
        self.bytes.u16("u16").map_err(|s| self.too_short(s))
    }

    pub(super) fn u32(&mut self) -> Result<u32, HwError> {
        self.bytes.u32("u32").map_err(|s| self.too_short(s))
    }

    /// A finite big-endian f32.
    pub(super) fn f32(&mut self, field: &'static str) -> Result<f32, HwError> {
        let value = self.bytes.f32(field).map_err(|s| self.too_short(s))?;
        check_finite(field, value)?;
        Ok(value)
    }

    /// `N` finite f32s, named by the next `N` entries of `names`.
    pub(super) fn f32s<const N: usize>(
        &mut self,
        names: &mut impl Iterator<Item = &'static str>,
    ) -> Result<[f32; N], HwError> {
        let mut out = [0f32; N];
        for slot in &mut out {
            *slot = self.f32(names.next().unwrap_or("arm_state"))?;
        }
        Ok(out)
    }
}
