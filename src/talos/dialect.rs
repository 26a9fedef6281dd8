//! How a Talos operator answers: the ICD's typed replies, or the deployed operator's bare ACKs.

use std::fmt;
use std::str::FromStr;

use super::CommandValue;

/// How the operator answers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Dialect {
    /// Typed replies as the ICD defines them.
    #[default]
    Icd,
    /// The deployed operator: "ACK\0" for every frame, commands 0x0000-0x0004 only.
    Ack,
}

impl Dialect {
    pub const ALL: [Dialect; 2] = [Dialect::Icd, Dialect::Ack];

    /// Whether this dialect can carry `command` at all.
    pub fn supports(self, command: CommandValue) -> bool {
        match self {
            Dialect::Icd => true,
            Dialect::Ack => command.request_value() <= CommandValue::PolarPanStop.request_value(),
        }
    }

    pub fn as_str(self) -> &'static str {
        match self {
            Dialect::Icd => "icd",
            Dialect::Ack => "ack",
        }
    }
}

impl fmt::Display for Dialect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl FromStr for Dialect {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|d| d.as_str() == s)
            .ok_or_else(|| format!("unknown dialect '{s}': expected icd or ack"))
    }
}
