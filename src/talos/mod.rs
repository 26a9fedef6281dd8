//! The Talos API ICD (`shared/icd/talos-api-icd.md`) as a pure library: the frame and its checksums
//! ([`frame`]), typed [`Request`]s and [`Reply`]s, return codes, position names, armjog's hardware
//! companion ICD for 0x0008 ([`hardware`]), reply dialects ([`dialect`]), hex for logs ([`hex`])
//! and what each request does to the arm, with the one stop set ([`stop`]).

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
