//! Parsers of the options every command shares, listing their possible values for `--help` and
//! the shell completions.

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};

use crate::talos::{Checksum, Dialect};

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
