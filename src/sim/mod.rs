//! The simulated Kinova Gen3 arm and the servers in front of it.

pub mod arm;
pub mod kinematics;
pub mod operator;
pub mod telemetry;

#[cfg(test)]
mod operator_tests;
