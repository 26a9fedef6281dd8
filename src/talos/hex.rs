//! Frames as text for people: the byte dumps of `armjog send --hex` and the console's log.

/// Bytes as upper-case hex pairs separated by spaces: `[0x00, 0xAB]` is `"00 AB"`.
pub fn spaced_hex(bytes: &[u8]) -> String {
    bytes
        .iter()
        .map(|b| hex::encode_upper([*b]))
        .collect::<Vec<_>>()
        .join(" ")
}

#[cfg(test)]
mod tests {
    use super::spaced_hex;

    #[test]
    fn pairs_are_upper_case_and_single_spaced() {
        assert_eq!(spaced_hex(&[0x00, 0xAB, 0x0F]), "00 AB 0F");
        assert_eq!(spaced_hex(&[0x41]), "41");
        assert_eq!(spaced_hex(&[]), "");
    }
}
