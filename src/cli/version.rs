//! What this build is: `0.1.0 (508af6a 2026-12-01)`, the version, git revision (`-dirty`, `unknown`
//! outside git) and UTC build date, stamped by `build.rs`.

/// `VERSION (REVISION DATE)`; clap prefixes the program's name.
pub const VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (",
    env!("ARMJOG_BUILD_REVISION"),
    " ",
    env!("ARMJOG_BUILD_DATE"),
    ")"
);
