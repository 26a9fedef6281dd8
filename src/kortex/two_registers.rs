//! Two-register values, CDAB: low word first. 1.0f32 is `[0x0000, 0x3F80]`.

/// A 32-bit value as the two registers that carry it, low word first.
pub fn u32_to_words(value: u32) -> [u16; 2] {
    [(value & 0xFFFF) as u16, (value >> 16) as u16]
}

/// The 32-bit value carried by two registers, low word first.
pub fn u32_from_words(words: [u16; 2]) -> u32 {
    (u32::from(words[1]) << 16) | u32::from(words[0])
}

/// An IEEE-754 single as two registers, low word first.
pub fn f32_to_words(value: f32) -> [u16; 2] {
    u32_to_words(value.to_bits())
}

/// The IEEE-754 single carried by two registers, low word first.
pub fn f32_from_words(words: [u16; 2]) -> f32 {
    f32::from_bits(u32_from_words(words))
}

/// Floats laid end to end, two registers each, as a write payload.
pub fn f32s_to_words(values: &[f32]) -> Vec<u16> {
    values.iter().flat_map(|v| f32_to_words(*v)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn low_word_comes_first() {
        assert_eq!(f32_to_words(1.0), [0x0000, 0x3F80]);
        assert_eq!(u32_to_words(0x1234_5678), [0x5678, 0x1234]);
        assert_eq!(u32_from_words([0x5678, 0x1234]), 0x1234_5678);
        assert_eq!(f32_from_words([0x0000, 0xBF00]), -0.5);
        assert_eq!(f32s_to_words(&[1.0, -0.5]), vec![0, 0x3F80, 0, 0xBF00]);
    }
}
