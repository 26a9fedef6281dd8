//! Position names: UINT8-length-prefixed, not null terminated, 1-255 bytes. armjog allows printable
//! ASCII only (0x20-0x7E), no leading or trailing space, so names stay readable, safe in JSON and
//! unambiguous typed back; anything else is refused before sending (the simulated operator answers
//! MALFORMED_PAYLOAD).

use std::fmt;

/// The rule is the sanitiser's ([`crate::text`]): one for typed, file and peer names.
pub const MAX_NAME_LEN: usize = crate::text::MAX_NAME_BYTES;

/// Why a name is not valid.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum NameError {
    #[error("is empty (a name needs 1 to 255 characters)")]
    Empty,
    #[error("is {0} bytes long (at most 255)")]
    TooLong(usize),
    #[error("has byte 0x{byte:02X} at offset {offset} (only printable ASCII is allowed)")]
    BadByte { byte: u8, offset: usize },
    #[error("starts or ends with a space")]
    OuterSpace,
}

/// A validated position name.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
#[serde(transparent)]
pub struct PositionName(String);

impl PositionName {
    pub fn new(name: impl Into<String>) -> Result<Self, NameError> {
        let name = name.into();
        Self::validate(name.as_bytes())?;
        Ok(PositionName(name))
    }

    /// Validates raw bytes, as received in a payload.
    pub fn from_bytes(bytes: &[u8]) -> Result<Self, NameError> {
        Self::validate(bytes)?;
        // validate() admits ASCII only, which is always valid UTF-8: nothing is replaced.
        Ok(PositionName(String::from_utf8_lossy(bytes).into_owned()))
    }

    pub fn into_string(self) -> String {
        self.0
    }

    /// Checks a name against the rule without keeping it (no allocation).
    pub fn validate(bytes: &[u8]) -> Result<(), NameError> {
        if bytes.is_empty() {
            return Err(NameError::Empty);
        }
        if bytes.len() > MAX_NAME_LEN {
            return Err(NameError::TooLong(bytes.len()));
        }
        if let Some((offset, &byte)) = bytes
            .iter()
            .enumerate()
            .find(|&(_, &b)| !crate::text::name_byte(b))
        {
            return Err(NameError::BadByte { byte, offset });
        }
        if bytes.first() == Some(&b' ') || bytes.last() == Some(&b' ') {
            return Err(NameError::OuterSpace);
        }
        Ok(())
    }

    pub fn as_str(&self) -> &str {
        &self.0
    }
}

impl fmt::Display for PositionName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::str::FromStr for PositionName {
    type Err = NameError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        PositionName::new(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn accepts_printable_ascii_up_to_255() {
        assert!(PositionName::new("pick 1").is_ok());
        assert!(PositionName::new("a".repeat(255)).is_ok());
        assert!(PositionName::new("x_y-z.1:~").is_ok());
    }

    #[test]
    fn refuses_what_the_rule_excludes() {
        assert_eq!(PositionName::new(""), Err(NameError::Empty));
        assert_eq!(
            PositionName::new("a".repeat(256)),
            Err(NameError::TooLong(256))
        );
        assert_eq!(
            PositionName::new("ab\tc"),
            Err(NameError::BadByte {
                byte: 0x09,
                offset: 2
            })
        );
        assert_eq!(
            PositionName::new("é"),
            Err(NameError::BadByte {
                byte: 0xC3,
                offset: 0
            })
        );
        assert_eq!(PositionName::new(" a"), Err(NameError::OuterSpace));
        assert_eq!(PositionName::new("a "), Err(NameError::OuterSpace));
    }

    #[test]
    fn encodes_with_a_length_prefix_and_no_terminator() {
        let mut out = Vec::new();
        let go_to = crate::talos::Request::GoToPosition {
            name: "home2".into(),
        };
        go_to.encode_payload(&mut out).unwrap();
        assert_eq!(out, [0x05, b'h', b'o', b'm', b'e', b'2']);
    }
}
