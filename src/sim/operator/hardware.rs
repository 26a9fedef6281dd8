//! The hardware companion ICD's operations (docs/hardware-icd.md) on the simulated arm.

use super::continuous;
use crate::sim::arm_model::{Arm, SimMotion};
use crate::sim::telemetry;
use crate::talos::ReturnCode;
use crate::talos::hardware::{self, HwReply, HwRequest};

/// The hardware ICD's operations on the arm; `cap` bounds a joint jog's tool speed, m/s.
pub(super) fn hardware_operation(
    arm: &mut Arm,
    request: HwRequest,
    cap: f64,
) -> Result<HwReply, ReturnCode> {
    let snapshot = arm.snapshot();
    match request {
        HwRequest::GetActuatorFeedback { selector } => {
            let joints: Vec<u8> = if selector == hardware::ALL_JOINTS {
                (1..=hardware::JOINT_COUNT).collect()
            } else {
                vec![selector]
            };
            Ok(HwReply::GetActuatorFeedback {
                actuators: joints
                    .into_iter()
                    .map(|j| telemetry::actuator_feedback(&snapshot, j))
                    .collect(),
            })
        }
        HwRequest::SendActuatorCommand { joint, command } => {
            use hardware::CommandFlags as F;
            let flags = command.flags;
            if flags.contains(F::CLEAR_MAJOR_FAULT) || flags.contains(F::CLEAR_MINOR_FAULT) {
                arm.fault_reset();
            }
            if flags.contains(F::SERVO_ENABLE) {
                let index = usize::from(joint.saturating_sub(1));
                let velocity = f64::from(command.velocity_deg_s).to_radians();
                let motion = SimMotion::JointVelocity {
                    joint: index,
                    velocity,
                };
                if velocity == 0.0 {
                    arm.stop();
                } else {
                    continuous(arm, motion, cap)?;
                }
            }
            Ok(HwReply::SendActuatorCommand {
                feedback: telemetry::actuator_feedback(&arm.snapshot(), joint),
            })
        }
        HwRequest::GetArmState => Ok(HwReply::GetArmState {
            state: telemetry::arm_state(&snapshot),
        }),
        HwRequest::StopAllJoints => {
            arm.stop();
            Ok(HwReply::StopAllJoints)
        }
        HwRequest::ClearAllFaults => {
            arm.fault_reset();
            Ok(HwReply::ClearAllFaults)
        }
    }
}
