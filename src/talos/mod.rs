//! The Talos API ICD (`shared/icd/talos-api-icd.md`) as a pure library: no IO.
//!
//! - [`frame`]: the command wrapper and its checksum dialects, plus a streaming codec.
//! - [`message`]: one typed [`Request`] per ICD command and one [`Reply`] per reply.
//! - [`return_code`]: the return codes armjog emits and understands.
//! - [`name`]: position names and the character rule armjog enforces.
//! - [`hardware`]: armjog's companion ICD for Execute Hardware Operation (0x0008).
//! - [`dialect`]: how an operator answers (typed replies or bare ACKs).
//! - [`hex`]: frames as spaced hex, for logs and `armjog send --hex`.

pub mod ack;
pub mod checksum;
pub mod command;
pub mod dialect;
pub mod frame;
pub mod hardware;
pub mod hex;
pub mod message;
pub mod name;
pub mod return_code;

pub use checksum::Checksum;
pub use command::CommandValue;
pub use dialect::Dialect;
pub use frame::{Frame, FrameCodec, RejectReason, Rejection};
pub use message::{Reply, Request};
pub use name::PositionName;
pub use return_code::ReturnCode;
