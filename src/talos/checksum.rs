//! The three checksum dialects a Talos link may use (see `shared/field-notes.md`).

use std::fmt;
use std::str::FromStr;

/// CRC-16/CCITT-FALSE: poly 0x1021, init 0xFFFF, no reflection, xorout 0 (check 0x29B1).
/// Slice-by-16 tables built at compile time: every frame is checksummed twice per exchange.
static CRC16: crc::Crc<u16, crc::Table<16>> =
    crc::Crc::<u16, crc::Table<16>>::new(&crc::CRC_16_IBM_3740);

/// How a frame's trailing checksum is computed and checked. Chosen per link.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub enum Checksum {
    /// 2 bytes, CRC-16/CCITT-FALSE over every byte before the field. armjog's default.
    #[default]
    Crc16,
    /// 1 byte, XOR of every header and payload byte: the deployed operator's current format.
    Xor8,
    /// 2 zero bytes, never verified: what the early clients sent.
    None,
}

impl Checksum {
    pub const ALL: [Checksum; 3] = [Checksum::Crc16, Checksum::Xor8, Checksum::None];

    /// Width of the checksum field in bytes.
    pub fn len(self) -> usize {
        match self {
            Checksum::Crc16 | Checksum::None => 2,
            Checksum::Xor8 => 1,
        }
    }

    /// Never zero-width; present for clippy's `len_without_is_empty`.
    pub fn is_empty(self) -> bool {
        false
    }

    /// The checksum value for `bytes` (header and payload), as the field's integer.
    pub fn compute(self, bytes: &[u8]) -> u16 {
        match self {
            Checksum::Crc16 => CRC16.checksum(bytes),
            Checksum::Xor8 => u16::from(bytes.iter().fold(0u8, |acc, b| acc ^ b)),
            Checksum::None => 0,
        }
    }

    /// Appends the checksum field of `out[start..]` (a frame's header and payload).
    pub fn append(self, out: &mut Vec<u8>, start: usize) {
        let value = self.compute(&out[start..]);
        match self {
            Checksum::Crc16 | Checksum::None => out.extend_from_slice(&value.to_be_bytes()),
            Checksum::Xor8 => out.push(value as u8),
        }
    }

    /// Reads the checksum field (big-endian) from exactly `self.len()` bytes.
    pub fn read_field(self, field: &[u8]) -> u16 {
        match (self, field) {
            (Checksum::Xor8, [b]) => u16::from(*b),
            (_, [hi, lo]) => u16::from_be_bytes([*hi, *lo]),
            _ => 0,
        }
    }

    /// Whether a received field matches; `None` accepts anything.
    pub fn verify(self, covered: &[u8], field: u16) -> bool {
        self == Checksum::None || self.compute(covered) == field
    }

    pub fn as_str(self) -> &'static str {
        match self {
            Checksum::Crc16 => "crc16",
            Checksum::Xor8 => "xor8",
            Checksum::None => "none",
        }
    }
}

impl fmt::Display for Checksum {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl FromStr for Checksum {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|c| c.as_str() == s)
            .ok_or_else(|| format!("unknown checksum '{s}': expected crc16, xor8 or none"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crc16_check_value_is_ccitt_false() {
        // The catalogue check value of CRC-16/CCITT-FALSE (field notes).
        assert_eq!(Checksum::Crc16.compute(b"123456789"), 0x29B1);
    }

    #[test]
    fn xor8_folds_every_byte() {
        assert_eq!(Checksum::Xor8.compute(&[0x01, 0x02, 0x04, 0x80]), 0x87);
        assert_eq!(Checksum::Xor8.compute(&[0xAA, 0xAA]), 0x00);
    }

    #[test]
    fn none_is_two_zero_bytes_and_accepts_anything() {
        let mut out = vec![1, 2, 3];
        Checksum::None.append(&mut out, 0);
        assert_eq!(out, [1, 2, 3, 0, 0]);
        assert!(Checksum::None.verify(&[1, 2, 3], 0xBEEF));
    }

    #[test]
    fn parses_names_and_rejects_others() {
        for c in Checksum::ALL {
            assert_eq!(c.as_str().parse::<Checksum>(), Ok(c));
        }
        assert!("crc32".parse::<Checksum>().unwrap_err().contains("crc32"));
    }
}
