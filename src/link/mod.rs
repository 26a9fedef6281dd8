//! The arm interfaces: each link owns its socket in a task; callers use channels.

pub mod command_kind;
pub mod driver;
pub mod failure;
pub mod fence;
pub mod guard;
pub mod interface;
pub mod modbus;
pub mod speed;
pub mod talos;

pub use modbus::{
    ModbusConfig, ModbusError, ModbusEvent, ModbusLink, Snapshot, StopReason, WriteReport,
};
pub use talos::{Answer, Dialect, Exchange, TalosConfig, TalosError, TalosEvent, TalosLink};
