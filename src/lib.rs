//! armjog: a terminal console to jog a robot arm, with the protocol libraries it speaks.
#![forbid(unsafe_code)]

pub mod cli;
pub mod console;
pub mod files;
pub mod kortex;
pub mod link;
pub mod logging;
pub mod net;
pub mod sim;
pub mod talos;
pub mod text;
