//! The ICD's command values. A reply's value is its request's value | 0x8000.

use std::fmt;

/// Bit set on every reply's command value.
pub const REPLY_BIT: u16 = 0x8000;

macro_rules! commands {
    // `$title`: the ICD's section title, the variant's doc.
    ($($variant:ident = $value:literal, $name:literal, $title:literal;)*) => {
        /// One ICD command, request side. [`CommandValue::reply_value`] gives its reply's value.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
        #[repr(u16)]
        pub enum CommandValue {
            $(#[doc = $title] $variant = $value,)*
        }

        impl CommandValue {
            pub const ALL: [CommandValue; 18] = [$(CommandValue::$variant,)*];

            /// The command for a request value (no reply bit), if the ICD defines it.
            pub fn from_request_value(value: u16) -> Option<Self> {
                match value {
                    $($value => Some(CommandValue::$variant),)*
                    _ => None,
                }
            }

            /// snake_case name used in logs and `--json` output.
            pub fn name(self) -> &'static str {
                match self {
                    $(CommandValue::$variant => $name,)*
                }
            }
        }
    };
}

commands! {
    Handshake = 0x0000, "handshake", "Handshake";
    PolarPanDiscrete = 0x0001, "polar_pan", "Polar Pan (Discrete)";
    Home = 0x0002, "home", "Home";
    PolarPanStart = 0x0003, "polar_start", "Polar Pan (Continuous START)";
    PolarPanStop = 0x0004, "polar_stop", "Polar Pan (Continuous STOP)";
    CartesianMoveDiscrete = 0x0005, "cart_move", "Cartesian Move (Discrete)";
    CartesianMoveStart = 0x0006, "cart_start", "Cartesian Move (Continuous START)";
    CartesianMoveStop = 0x0007, "cart_stop", "Cartesian Move (Continuous STOP)";
    ExecuteHardwareOperation = 0x0008, "hw_op", "Execute Hardware Operation";
    GetSpeed = 0x0009, "get_speed", "Get Speed";
    SetSpeed = 0x000A, "set_speed", "Set Speed";
    SavePosition = 0x000B, "save", "Save Position";
    DeletePosition = 0x000C, "delete", "Delete Position";
    GoToPosition = 0x000D, "goto", "Go to Position";
    SetPolarPosition = 0x000E, "set_polar", "Set Polar Position";
    GetPolarPosition = 0x000F, "get_polar", "Get Polar Position";
    SetCartesianPosition = 0x0010, "set_cart", "Set Cartesian Position";
    GetCartesianPosition = 0x0011, "get_cart", "Get Cartesian Position";
}

impl CommandValue {
    pub fn request_value(self) -> u16 {
        self as u16
    }

    pub fn reply_value(self) -> u16 {
        self as u16 | REPLY_BIT
    }

    /// The command for a reply value (reply bit set), if the ICD defines it.
    pub fn from_reply_value(value: u16) -> Option<Self> {
        if value & REPLY_BIT == 0 {
            return None;
        }
        Self::from_request_value(value & !REPLY_BIT)
    }

    /// Whether the ICD allows a payload of `length` bytes for this command's request
    /// (`reply == false`) or reply. Names are 1-255 bytes; a reply may also be a bare 2-byte
    /// return code, as error replies can be.
    pub fn allows_payload_len(self, reply: bool, length: usize) -> bool {
        use CommandValue as C;
        const NAME: usize = 1 + 255;
        if reply {
            return length == 2
                || match self {
                    C::Handshake => length == 4,
                    C::ExecuteHardwareOperation => length >= 4,
                    C::GetSpeed => length == 3,
                    C::GetPolarPosition | C::GetCartesianPosition => length == 14,
                    _ => false,
                };
        }
        let range = match self {
            // The ICD's 2-byte OID, or the empty payload deployed clients send.
            C::Handshake => return length == 0 || length == 2,
            C::PolarPanDiscrete => 16..=16,
            C::Home => 4..=4,
            C::PolarPanStart => 2..=2,
            C::PolarPanStop | C::CartesianMoveStop | C::GetSpeed => 0..=0,
            C::CartesianMoveDiscrete => 20..=20,
            C::CartesianMoveStart => 3..=3,
            C::ExecuteHardwareOperation => 6..=usize::MAX,
            C::SetSpeed => 1..=1,
            C::SavePosition => 4..=NAME + 1 + NAME,
            C::DeletePosition | C::GoToPosition | C::GetPolarPosition | C::GetCartesianPosition => {
                2..=NAME
            }
            C::SetPolarPosition | C::SetCartesianPosition => 14..=NAME + 12,
        };
        range.contains(&length)
    }

    /// Whether the ICD allows payload `length` for command `value` (either direction).
    pub fn is_plausible(value: u16, length: usize) -> bool {
        let reply = value & REPLY_BIT != 0;
        Self::from_request_value(value & !REPLY_BIT)
            .is_some_and(|c| c.allows_payload_len(reply, length))
    }

    /// Whether a command value (either direction) is one the ICD defines.
    pub fn is_known_value(value: u16) -> bool {
        Self::from_request_value(value & !REPLY_BIT).is_some()
    }
}

impl fmt::Display for CommandValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_are_the_icds() {
        assert_eq!(CommandValue::Handshake.request_value(), 0x0000);
        assert_eq!(
            CommandValue::ExecuteHardwareOperation.request_value(),
            0x0008
        );
        assert_eq!(CommandValue::SetSpeed.request_value(), 0x000A);
        assert_eq!(CommandValue::GetCartesianPosition.request_value(), 0x0011);
        assert_eq!(CommandValue::GetCartesianPosition.reply_value(), 0x8011);
        for (i, c) in CommandValue::ALL.iter().enumerate() {
            assert_eq!(c.request_value(), i as u16);
        }
    }

    #[test]
    fn lookups_respect_the_reply_bit() {
        assert_eq!(
            CommandValue::from_request_value(0x0003),
            Some(CommandValue::PolarPanStart)
        );
        assert_eq!(CommandValue::from_request_value(0x8003), None);
        assert_eq!(
            CommandValue::from_reply_value(0x8003),
            Some(CommandValue::PolarPanStart)
        );
        assert_eq!(CommandValue::from_reply_value(0x0003), None);
        assert_eq!(CommandValue::from_request_value(0x0012), None);
        assert!(CommandValue::is_known_value(0x8011));
        assert!(!CommandValue::is_known_value(0x8012));
    }

    #[test]
    fn plausible_lengths_follow_the_icd_tables() {
        assert!(CommandValue::is_plausible(0x0006, 3));
        assert!(!CommandValue::is_plausible(0x0006, 4));
        assert!(CommandValue::is_plausible(0x0004, 0));
        assert!(CommandValue::is_plausible(0x000B, 4)); // 1-byte name, anchor, empty parent
        assert!(CommandValue::is_plausible(0x000B, 513));
        assert!(!CommandValue::is_plausible(0x000B, 514));
        assert!(CommandValue::is_plausible(0x8011, 14));
        assert!(CommandValue::is_plausible(0x8011, 2)); // bare error reply
        assert!(!CommandValue::is_plausible(0x8011, 13));
        assert!(!CommandValue::is_plausible(0x0042, 0));
    }

    #[test]
    fn a_handshake_may_carry_the_icd_oid_or_nothing() {
        assert!(CommandValue::is_plausible(0x0000, 2));
        assert!(CommandValue::is_plausible(0x0000, 0));
        assert!(!CommandValue::is_plausible(0x0000, 1));
        assert!(!CommandValue::is_plausible(0x0000, 3));
    }
}
