//! This build: version, git revision (`-dirty`, `unknown`) and UTC date, from `build.rs`.

/// `VERSION (REVISION DATE)`; clap prefixes the program's name.
pub const VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (",
    env!("ARMJOG_BUILD_REVISION"),
    " ",
    env!("ARMJOG_BUILD_DATE"),
    ")"
);
