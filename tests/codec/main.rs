//! The Talos, hardware-ICD and Kortex codecs: vectors, decoders, split frames, properties.
//!
//! One test binary per folder (linking one binary per file cost most of a CI run): each module
//! is named for what it tests, so test paths read `<module>::<test>`. Helpers shared with other
//! binaries stay in `tests/<helper>/` and come in by path.

#[path = "../common/mod.rs"]
mod common;

mod hardware_icd;
mod kortex;
mod talos_checksum_fit;
mod talos_decoder;
mod talos_props;
mod talos_split_frames;
mod talos_stop_class;
mod talos_vectors;
