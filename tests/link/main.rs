//! The links and the arm driver against fakes and the simulator: Talos, Modbus, stops, speed
//! settings.
//!
//! One test binary per folder (linking one binary per file cost most of a CI run): each module
//! is named for what it tests, so test paths read `<module>::<test>`. Helpers shared with other
//! binaries stay in `tests/<helper>/` and come in by path.

#[path = "../common/mod.rs"]
mod common;
#[path = "../modbus_fake/mod.rs"]
mod modbus_fake;

mod driver_orientation;
mod driver_speed_settings;
mod driver_stall;
mod driver_stop;
mod driver_stored;
mod modbus;
mod modbus_capped_moves;
mod modbus_paused;
mod modbus_polls;
mod modbus_reconnects;
mod modbus_speed_cap;
mod modbus_stops;
mod stop_paths;
mod talos;
mod talos_batch;
mod talos_first_exchange;
mod talos_paused;
mod talos_speed_scale;
mod talos_split;
mod talos_stall;
