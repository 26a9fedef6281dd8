//! The Talos API ICD (`shared/icd/talos-api-icd.md`) as a pure library: no IO.
//!
//! - [`frame`]: the command wrapper and its checksum dialects, plus a streaming codec.
//! - [`request`] / [`reply`]: one typed [`Request`] per ICD command and one [`Reply`] per reply;
//!   [`message`] holds their shared errors and field reader.
//! - [`reader`]: the one big-endian reader, shared with [`hardware`].
//! - [`return_code`]: the return codes armjog emits and understands.
//! - [`name`]: position names and the character rule armjog enforces.
//! - [`hardware`]: armjog's companion ICD for Execute Hardware Operation (0x0008).
//! - [`dialect`]: how an operator answers (typed replies or bare ACKs).
//! - [`hex`]: frames as spaced hex, for logs and `armjog send --hex`.
//! - [`stop`]: what each request does to the arm (stop, motion, still), and the one set of
//!   requests that stops every motion, per dialect.

pub mod ack;
pub mod checksum;
pub mod command;
pub mod dialect;
pub mod frame;
pub mod hardware;
pub mod hex;
pub mod message;
pub mod name;
pub mod reader;
pub mod reply;
pub mod request;
pub mod return_code;
pub mod stop;

pub use checksum::Checksum;
pub use command::CommandValue;
pub use dialect::Dialect;
pub use frame::{ChecksumFit, FrameCodec, RejectReason, Rejection, TalosFrame, checksum_that_fits};
pub use name::PositionName;
pub use reply::Reply;
pub use request::Request;
pub use return_code::ReturnCode;
pub use stop::{RequestClass, may_move, stop_requests};
