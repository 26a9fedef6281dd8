//! The links and the arm driver against fakes and the simulator: Talos, Modbus, the hardware ICD,
//! stops.
//!
//! One test binary for several former ones (linking one binary per file cost most of a CI
//! run): each module is one former `tests/<name>.rs`, so test paths read `<name>::<test>`.
//! Helpers shared with other binaries stay in `tests/<helper>/` and come in by path.

#[path = "../common/mod.rs"]
mod common;
#[path = "../modbus_fake/mod.rs"]
mod modbus_fake;

mod driver_stall;
mod driver_stop;
mod hardware_icd;
mod modbus_capped_moves;
mod modbus_link;
mod modbus_link_paused;
mod modbus_speed_cap;
mod orientation_jog;
mod stop_paths;
mod talos_first_exchange;
mod talos_link;
mod talos_link_paused;
mod talos_link_split;
mod talos_link_stall;
mod talos_speed_scale;
