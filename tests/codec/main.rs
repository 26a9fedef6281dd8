//! The Talos and Kortex codecs: vectors, decoders, split frames, properties.
//!
//! One test binary for several former ones (linking one binary per file cost most of a CI
//! run): each module is one former `tests/<name>.rs`, so test paths read `<name>::<test>`.
//! Helpers shared with other binaries stay in `tests/<helper>/` and come in by path.

#[path = "../common/mod.rs"]
mod common;

mod kortex_codec;
mod talos_checksum_fit;
mod talos_decoder;
mod talos_props;
mod talos_split_frames;
mod talos_vectors;
