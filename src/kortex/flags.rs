//! Fault and warning flags: one bit each in input registers 2-3 (faults) and 4-5 (warnings),
//! and one discrete input each at 32 + bit (faults) and 64 + bit (warnings).

use serde::{Serialize, Serializer};

use super::codes::{CodeName, coded_enum};
use super::registers::discrete_input;

coded_enum! {
    /// A fault or warning flag; its code is its bit number.
    Flag {
        FirmwareUpdateFailure = 0, "firmware_update_failure", "Firmware update failure";
        MaximumAmbientTemperature = 2, "maximum_ambient_temperature", "Maximum ambient temperature reached";
        MaximumCoreTemperature = 3, "maximum_core_temperature", "Maximum core temperature reached";
        JointFault = 4, "joint_fault", "Joint fault";
        AboveMaximumDof = 8, "above_maximum_dof", "Above maximum DOF";
        UnableToReachPose = 10, "unable_to_reach_pose", "Unable to reach pose";
        JointDetectionError = 11, "joint_detection_error", "Joint detection error";
        NetworkInitialisationError = 12, "network_initialisation_error", "Network initialisation error";
        MaximumCurrent = 13, "maximum_current", "Maximum current reached";
        MaximumVoltage = 14, "maximum_voltage", "Maximum voltage reached";
        MinimumVoltage = 15, "minimum_voltage", "Minimum voltage reached";
        EmergencyStop = 23, "emergency_stop", "Emergency stop activated";
        EmergencyLine = 24, "emergency_line", "Emergency line activated";
        InrushCurrentLimiterFault = 25, "inrush_current_limiter_fault", "In rush current limiter fault";
        /// Only discrete input 58 names it; the bitmask tables and the warning inputs skip bit
        /// 26, but the offsets agree, so it decodes the same from every source.
        NvramCorrupted = 26, "nvram_corrupted", "NVRAM corrupted";
        IncompatibleFirmwareVersion = 27, "incompatible_firmware_version", "Incompatible firmware version";
        PowerOnSelfTestFailure = 28, "power_on_self_test_failure", "Power on self test failure";
        DiscreteInputStuckActive = 29, "discrete_input_stuck_active", "Discrete input stuck active";
        IllegalPosition = 30, "illegal_position", "Arm is in an illegal position (singularity)";
    }
}

impl Flag {
    /// The bit of this flag in the fault and warning bitmasks.
    pub fn bit(self) -> u32 {
        1 << self.code()
    }

    /// Discrete input carrying this flag as a fault (32-62).
    pub fn fault_input(self) -> u16 {
        discrete_input::FAULT_FLAGS + self.code()
    }

    /// Discrete input carrying this flag as a warning (64-94).
    pub fn warning_input(self) -> u16 {
        discrete_input::WARNING_FLAGS + self.code()
    }
}

/// A set of raised flags. Bits the ICD does not name are kept and reported as `unknown_bit_N`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FlagSet(u32);

impl FlagSet {
    pub const EMPTY: FlagSet = FlagSet(0);

    pub fn from_bits(bits: u32) -> FlagSet {
        FlagSet(bits)
    }

    /// From a block of discrete inputs, the first being bit 0. Inputs past bit 31 are ignored.
    pub fn from_inputs(inputs: &[bool]) -> FlagSet {
        let bits = inputs
            .iter()
            .take(32)
            .enumerate()
            .filter(|(_, on)| **on)
            .fold(0u32, |bits, (bit, _)| bits | (1 << bit));
        FlagSet(bits)
    }

    pub fn bits(self) -> u32 {
        self.0
    }

    pub fn is_empty(self) -> bool {
        self.0 == 0
    }

    pub fn contains(self, flag: Flag) -> bool {
        self.0 & flag.bit() != 0
    }

    pub fn union(self, other: FlagSet) -> FlagSet {
        FlagSet(self.0 | other.0)
    }

    /// The named flags raised, in bit order.
    pub fn flags(self) -> Vec<Flag> {
        Flag::ALL
            .iter()
            .copied()
            .filter(|f| self.contains(*f))
            .collect()
    }

    /// The set [`FlagSet::names`] names; `None` if a name is not a flag's nor `unknown_bit_N`.
    pub fn from_names<'a>(names: impl IntoIterator<Item = &'a str>) -> Option<FlagSet> {
        let mut bits = 0u32;
        for name in names {
            let bit = match name.strip_prefix("unknown_bit_") {
                Some(bit) => bit.parse::<u16>().ok().filter(|b| *b < 32)?,
                None => Flag::ALL.iter().find(|f| f.key() == name)?.code(),
            };
            bits |= 1 << bit;
        }
        Some(FlagSet::from_bits(bits))
    }

    /// Every raised bit as a name, in bit order: the flag's key, or `unknown_bit_N`.
    pub fn names(self) -> Vec<String> {
        (0..32u16)
            .filter(|bit| self.0 & (1 << bit) != 0)
            .map(|bit| match Flag::from_code(bit) {
                Some(flag) => flag.key().to_string(),
                None => format!("unknown_bit_{bit}"),
            })
            .collect()
    }
}

impl Serialize for FlagSet {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_seq(self.names())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inputs_and_bits_agree() {
        let from_inputs = FlagSet::from_inputs(&[true, false, false, false, true]);
        assert_eq!(from_inputs.bits(), 0b1_0001);
        assert_eq!(
            from_inputs.flags(),
            vec![Flag::FirmwareUpdateFailure, Flag::JointFault]
        );
        assert_eq!(Flag::IllegalPosition.fault_input(), 62);
        assert_eq!(Flag::IllegalPosition.warning_input(), 94);
        assert_eq!(Flag::NvramCorrupted.fault_input(), 58);
        assert_eq!(FlagSet::from_bits(0b10).names(), vec!["unknown_bit_1"]);
    }
}
