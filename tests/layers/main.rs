//! The layering of `src/`: no module imports a layer above it, and the pure layers do no IO.
//! A source scan (`scan.rs`) rather than a test of one module, so a binary of its own.

mod imports;
mod scan;
