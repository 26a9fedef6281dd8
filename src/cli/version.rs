//! What this build is: `0.1.0 (508af6a 2026-12-01)`, the version, the git revision it was built
//! from (`-dirty` when tracked files were modified, `unknown` outside a git checkout) and the UTC
//! build date. Stamped by `build.rs`; `armjog --version` and the man page print it.

/// `VERSION (REVISION DATE)`; clap prefixes the program's name.
pub const VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (",
    env!("ARMJOG_BUILD_REVISION"),
    " ",
    env!("ARMJOG_BUILD_DATE"),
    ")"
);
