//! The one big-endian field reader, shared by [`super::message`] and [`super::hardware`]: every
//! read is a `try_get_*`, so a short payload is a [`Short`] naming the field, never a panic.

use bytes::Buf;

/// A field the payload ended inside of.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("payload ends inside field {field}: needs {needed} bytes, {available} left")]
pub struct Short {
    pub field: &'static str,
    pub needed: usize,
    pub available: usize,
}

/// Big-endian reader over a byte slice; reads advance past what they return.
#[derive(Debug, Clone)]
pub struct BeReader<'a> {
    bytes: &'a [u8],
}

impl<'a> BeReader<'a> {
    pub fn new(bytes: &'a [u8]) -> Self {
        BeReader { bytes }
    }

    pub fn remaining(&self) -> usize {
        self.bytes.remaining()
    }

    pub fn is_empty(&self) -> bool {
        !self.bytes.has_remaining()
    }

    fn short(field: &'static str, e: bytes::TryGetError) -> Short {
        Short {
            field,
            needed: e.requested,
            available: e.available,
        }
    }

    pub fn u8(&mut self, field: &'static str) -> Result<u8, Short> {
        self.bytes.try_get_u8().map_err(|e| Self::short(field, e))
    }

    pub fn i8(&mut self, field: &'static str) -> Result<i8, Short> {
        self.bytes.try_get_i8().map_err(|e| Self::short(field, e))
    }

    pub fn u16(&mut self, field: &'static str) -> Result<u16, Short> {
        self.bytes.try_get_u16().map_err(|e| Self::short(field, e))
    }

    pub fn u32(&mut self, field: &'static str) -> Result<u32, Short> {
        self.bytes.try_get_u32().map_err(|e| Self::short(field, e))
    }

    pub fn i32(&mut self, field: &'static str) -> Result<i32, Short> {
        self.bytes.try_get_i32().map_err(|e| Self::short(field, e))
    }

    pub fn f32(&mut self, field: &'static str) -> Result<f32, Short> {
        self.bytes.try_get_f32().map_err(|e| Self::short(field, e))
    }

    /// The next `len` bytes as a slice of the input.
    pub fn slice(&mut self, field: &'static str, len: usize) -> Result<&'a [u8], Short> {
        if self.bytes.len() < len {
            return Err(Short {
                field,
                needed: len,
                available: self.bytes.len(),
            });
        }
        let (head, tail) = self.bytes.split_at(len);
        self.bytes = tail;
        Ok(head)
    }

    pub fn rest(&mut self) -> &'a [u8] {
        std::mem::take(&mut self.bytes)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_big_endian_fields_in_order() {
        let mut r = BeReader::new(&[0x12, 0x34, 0xFF, 0xFF, 0xFF, 0xFE, 0x3F, 0x80, 0, 0, 7]);
        assert_eq!(r.u16("a"), Ok(0x1234));
        assert_eq!(r.i32("b"), Ok(-2));
        assert_eq!(r.f32("c"), Ok(1.0));
        assert_eq!(r.remaining(), 1);
        assert_eq!(r.rest(), &[7]);
        assert!(r.is_empty());
    }

    #[test]
    fn short_input_names_the_field_and_the_bytes_missing() {
        let mut r = BeReader::new(&[1, 2, 3]);
        assert_eq!(
            r.u32("delay_ms"),
            Err(Short {
                field: "delay_ms",
                needed: 4,
                available: 3
            })
        );
        // A failed read consumes nothing.
        assert_eq!(r.remaining(), 3);
        assert_eq!(
            r.slice("name", 5),
            Err(Short {
                field: "name",
                needed: 5,
                available: 3
            })
        );
        assert_eq!(r.slice("name", 2), Ok(&[1u8, 2][..]));
    }
}
