//! Parsers of the shared options, listing their values for `--help` and completions and checking
//! ranges. Profiles use the same parsers (`profiles::file`), so a value is refused alike wherever
//! written; messages name no option (clap names the option, a profile its key).

use std::ops::RangeInclusive;

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};

use crate::kortex::commands::{CommandError, stored_id};
use crate::link::speed::{SpeedCap, SpeedCapError};
use crate::talos::name::NameError;
use crate::talos::{Checksum, Dialect};

/// What is wrong with an option's value.
#[derive(Debug, thiserror::Error)]
pub enum BadValue {
    #[error("'{0}' is not a number")]
    NotANumber(String),
    #[error("'{0}' is not a whole number")]
    NotAWholeNumber(String),
    #[error(transparent)]
    ToolSpeed(#[from] SpeedCapError),
    #[error("must be 2.5 to 100 (re-sending well inside the 500 ms watchdog)")]
    RefreshHz,
    #[error("must be 1 to 200")]
    TelemetryHz,
    #[error(transparent)]
    StoredId(#[from] CommandError),
    #[error("'{0}' is not a rate in (0, 100] Hz")]
    NotARate(String),
    #[error("name {0}")]
    Name(#[from] NameError),
    #[error("not hex bytes: {0}")]
    NotHex(#[from] hex::FromHexError),
}

/// A number as typed.
fn number(text: &str) -> Result<f64, BadValue> {
    text.parse::<f64>()
        .map_err(|_| BadValue::NotANumber(text.into()))
}

/// A tool speed in mm/s that a cap may be ([`SpeedCap::new`]).
pub fn tool_speed(text: &str) -> Result<f64, BadValue> {
    let mm_s = number(text)?;
    SpeedCap::new(mm_s / 1000.0)?;
    Ok(mm_s)
}

/// `--refresh-hz`: how often a held jog is re-sent, well inside the operator's 500 ms watchdog.
pub fn refresh_hz(text: &str) -> Result<f64, BadValue> {
    within(text, 2.5..=100.0, BadValue::RefreshHz)
}

/// `--telemetry-hz`: Modbus polls per second.
pub fn telemetry_hz(text: &str) -> Result<f64, BadValue> {
    within(text, 1.0..=200.0, BadValue::TelemetryHz)
}

/// A number as typed, in `range`; `outside` if it is not.
fn within(text: &str, range: RangeInclusive<f64>, outside: BadValue) -> Result<f64, BadValue> {
    Some(number(text)?)
        .filter(|n| range.contains(n))
        .ok_or(outside)
}

/// A stored action or sequence id, in [`crate::kortex::commands::STORED_IDS`].
pub fn stored_action_id(text: &str) -> Result<u16, BadValue> {
    let whole: i128 = text
        .parse()
        .map_err(|_| BadValue::NotAWholeNumber(text.into()))?;
    Ok(stored_id(whole)?)
}

/// `--checksum`: the checksum dialect of every Talos frame.
pub fn checksum_parser() -> impl TypedValueParser<Value = Checksum> {
    PossibleValuesParser::new(Checksum::ALL.map(|c| {
        PossibleValue::new(c.as_str()).help(match c {
            Checksum::Crc16 => "2 bytes of CRC-16/CCITT-FALSE (armjog's default)",
            Checksum::Xor8 => "1 byte, XOR of every byte (the deployed operator)",
            Checksum::None => "2 zero bytes, never verified (early clients)",
        })
    }))
    .try_map(|s| s.parse::<Checksum>())
}

/// `--dialect`: how the Talos operator replies.
pub fn dialect_parser() -> impl TypedValueParser<Value = Dialect> {
    PossibleValuesParser::new(Dialect::ALL.map(|d| {
        PossibleValue::new(d.as_str()).help(match d {
            Dialect::Icd => "typed replies as the ICD defines them",
            Dialect::Ack => {
                "the deployed operator's \"ACK\\0\" for every frame (commands 0-4 only)"
            }
        })
    }))
    .try_map(|s| s.parse::<Dialect>())
}
