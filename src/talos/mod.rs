//! The Talos API ICD (`shared/icd/talos-api-icd.md`) as a pure library: no IO.
//!
//! - [`frame`]: the command wrapper and its checksum dialects, plus a streaming codec.
//! - [`message`]: one typed [`Request`] per ICD command and one [`Reply`] per reply.
//! - [`return_code`]: the return codes armjog emits and understands.
//! - [`name`]: position names and the character rule armjog enforces.
//! - [`hardware`]: armjog's companion ICD for Execute Hardware Operation (0x0008).

pub mod ack;
pub mod checksum;
pub mod command;
pub mod frame;
pub mod hardware;
pub mod message;
pub mod name;
pub mod return_code;

pub use checksum::Checksum;
pub use command::CommandValue;
pub use frame::{Frame, FrameCodec, RejectReason, Rejection};
pub use message::{Reply, Request};
pub use name::PositionName;
pub use return_code::ReturnCode;
