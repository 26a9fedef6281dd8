//! Field checks and the big-endian payload reader shared by the payload and message layers.

use super::{HwError, JOINT_COUNT};

pub(super) fn check_joint(joint: u8) -> Result<(), HwError> {
    if (1..=JOINT_COUNT).contains(&joint) {
        Ok(())
    } else {
        Err(HwError::JointOutOfRange(joint))
    }
}

pub(super) fn check_selector(selector: u8) -> Result<(), HwError> {
    if selector <= JOINT_COUNT {
        Ok(())
    } else {
        Err(HwError::SelectorOutOfRange(selector))
    }
}

pub(super) fn check_order(previous: u8, joint: u8) -> Result<(), HwError> {
    if joint > previous {
        Ok(())
    } else {
        Err(HwError::JointOrder { previous, joint })
    }
}

pub(super) fn check_finite(field: &'static str, value: f32) -> Result<(), HwError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(HwError::NonFinite { field })
    }
}

/// Big-endian reader over a payload whose exact length was checked by [`Reader::exact`].
pub(super) struct Reader<'a> {
    rest: &'a [u8],
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
        if got < expected {
            Err(HwError::TooShort {
                subcommand,
                expected,
                got,
            })
        } else if got > expected {
            Err(HwError::TooLong {
                subcommand,
                expected,
                got,
            })
        } else {
            Ok(Reader {
                rest: payload,
                subcommand,
                len: got,
            })
        }
    }

    fn take<const N: usize>(&mut self) -> Result<[u8; N], HwError> {
        match self.rest.split_first_chunk::<N>() {
            Some((head, rest)) => {
                self.rest = rest;
                Ok(*head)
            }
            // Unreachable after `exact`, but reported rather than assumed.
            None => Err(HwError::TooShort {
                subcommand: self.subcommand,
                expected: self.len - self.rest.len() + N,
                got: self.len,
            }),
        }
    }

    pub(super) fn u8(&mut self) -> Result<u8, HwError> {
        self.take::<1>().map(|[b]| b)
    }

    pub(super) fn u16(&mut self) -> Result<u16, HwError> {
        self.take().map(u16::from_be_bytes)
    }

    pub(super) fn u32(&mut self) -> Result<u32, HwError> {
        self.take().map(u32::from_be_bytes)
    }

    /// A finite big-endian f32.
    pub(super) fn f32(&mut self, field: &'static str) -> Result<f32, HwError> {
        let value = self.take().map(f32::from_be_bytes)?;
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
