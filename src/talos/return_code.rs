//! Return codes: the ICD defines only success; these are armjog's, emitted by the simulated
//! operator and named by the console. Unlisted codes show raw.

use std::fmt;

/// A reply's return code. 0 is success.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, serde::Serialize)]
#[serde(transparent)]
pub struct ReturnCode(pub u16);

macro_rules! codes {
    ($($konst:ident = $value:literal, $name:literal, $meaning:literal;)*) => {
        impl ReturnCode {
            $(#[doc = $meaning] pub const $konst: ReturnCode = ReturnCode($value);)*

            /// Every code armjog defines, in order.
            pub const DEFINED: &'static [ReturnCode] = &[$(ReturnCode::$konst,)*];

            /// SCREAMING_SNAKE name, or `None` for a code armjog does not define.
            pub fn name(self) -> Option<&'static str> {
                match self.0 {
                    $($value => Some($name),)*
                    _ => None,
                }
            }
        }
    };
}

codes! {
    OK = 0x0000, "OK", "success";
    UNKNOWN_COMMAND = 0x0001, "UNKNOWN_COMMAND", "the operator does not implement this command value";
    MALFORMED_PAYLOAD = 0x0002, "MALFORMED_PAYLOAD", "the payload has the wrong length or an invalid field";
    BAD_CHECKSUM = 0x0003, "BAD_CHECKSUM", "the frame's checksum did not match";
    UNKNOWN_POSITION = 0x0004, "UNKNOWN_POSITION", "no position is saved under this name";
    UNREACHABLE = 0x0005, "UNREACHABLE", "the target is outside the arm's reach";
    ARM_FAULT = 0x0006, "ARM_FAULT", "the arm is in fault; reset the fault first";
    BUSY = 0x0007, "BUSY", "the arm is executing another motion";
    OUT_OF_RANGE = 0x0008, "OUT_OF_RANGE", "a value is outside its allowed range";
    UNSUPPORTED_SUBCOMMAND = 0x0009, "UNSUPPORTED_SUBCOMMAND", "the hardware operation subcommand is not defined";
    INVALID_PARENT = 0x000A, "INVALID_PARENT", "the parent position is unknown or would form a cycle";
    JOINT_LIMIT = 0x000B, "JOINT_LIMIT", "the motion would pass a joint limit";
    INTERNAL_ERROR = 0x00FF, "INTERNAL_ERROR", "the operator failed internally";
}

impl ReturnCode {
    pub fn is_ok(self) -> bool {
        self.0 == 0
    }
}

impl fmt::Display for ReturnCode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.name() {
            Some(name) => write!(f, "0x{:04X} {name}", self.0),
            None => write!(f, "0x{:04X} (unknown code)", self.0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_codes_are_named_and_unknown_are_raw() {
        assert_eq!(ReturnCode(0).to_string(), "0x0000 OK");
        assert_eq!(ReturnCode(4).to_string(), "0x0004 UNKNOWN_POSITION");
        assert_eq!(ReturnCode(0x1234).to_string(), "0x1234 (unknown code)");
        assert!(ReturnCode::OK.is_ok() && !ReturnCode::BUSY.is_ok());
    }

    #[test]
    fn defined_codes_are_distinct() {
        let mut values: Vec<u16> = ReturnCode::DEFINED.iter().map(|c| c.0).collect();
        values.dedup();
        assert_eq!(values.len(), ReturnCode::DEFINED.len());
    }
}
