//! [`HwRequest`] and [`HwReply`]: subcommand dispatch, validation and payload encode/decode.

use serde::Serialize;

use crate::talos::Request;

use super::reader::{Reader, check_joint, check_order, check_selector};
use super::{
    ACTUATOR_COMMAND_LEN, ARM_STATE_LEN, ActuatorCommand, ActuatorFeedback, ArmState, CommandFlags,
    FEEDBACK_BLOCK_LEN, HwError, JOINT_COUNT, subcommand,
};

/// A hardware operation request: the Talos 0x0008 Subcommand Value and Payload.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum HwRequest {
    /// `selector`: 0 ([`ALL_JOINTS`](super::ALL_JOINTS)) or a joint 1..=7.
    GetActuatorFeedback {
        selector: u8,
    },
    /// `joint`: 1..=7.
    SendActuatorCommand {
        joint: u8,
        command: ActuatorCommand,
    },
    GetArmState,
    StopAllJoints,
    ClearAllFaults,
}

impl HwRequest {
    pub fn subcommand(&self) -> u16 {
        match self {
            HwRequest::GetActuatorFeedback { .. } => subcommand::GET_ACTUATOR_FEEDBACK,
            HwRequest::SendActuatorCommand { .. } => subcommand::SEND_ACTUATOR_COMMAND,
            HwRequest::GetArmState => subcommand::GET_ARM_STATE,
            HwRequest::StopAllJoints => subcommand::STOP_ALL_JOINTS,
            HwRequest::ClearAllFaults => subcommand::CLEAR_ALL_FAULTS,
        }
    }

    /// Every field in range: selector 0..=7, joint 1..=7, defined flag bits, finite floats.
    pub fn validate(&self) -> Result<(), HwError> {
        match self {
            HwRequest::GetActuatorFeedback { selector } => check_selector(*selector),
            HwRequest::SendActuatorCommand { joint, command } => {
                check_joint(*joint)?;
                command.validate()
            }
            HwRequest::GetArmState | HwRequest::StopAllJoints | HwRequest::ClearAllFaults => Ok(()),
        }
    }

    /// The inner Payload bytes, after [`HwRequest::validate`].
    pub fn encode_payload(&self) -> Result<Vec<u8>, HwError> {
        self.validate()?;
        Ok(self.payload_bytes())
    }

    /// The Talos request (0x0008) for this operation, after [`HwRequest::validate`].
    pub fn to_request(&self) -> Result<Request, HwError> {
        self.validate()?;
        Ok(self.carried())
    }

    /// STOP_ALL_JOINTS as its request: no fields, so nothing can fail (the stop set needs it).
    pub fn stop_all_joints_request() -> Request {
        HwRequest::StopAllJoints.carried()
    }

    /// The request carrying this operation, as it is (validated or without fields).
    fn carried(&self) -> Request {
        Request::HardwareOperation {
            subcommand: self.subcommand(),
            reserved: 0,
            payload: self.payload_bytes(),
        }
    }

    /// The payload bytes of a validated request.
    fn payload_bytes(&self) -> Vec<u8> {
        let mut out = Vec::new();
        match self {
            HwRequest::GetActuatorFeedback { selector } => out.push(*selector),
            HwRequest::SendActuatorCommand { joint, command } => {
                out.push(*joint);
                out.extend_from_slice(&command.flags.0.to_be_bytes());
                for value in command.setpoints() {
                    out.extend_from_slice(&value.to_be_bytes());
                }
            }
            HwRequest::GetArmState | HwRequest::StopAllJoints | HwRequest::ClearAllFaults => {}
        }
        out
    }

    /// Parses and validates the inner Payload of a request with this subcommand.
    pub fn decode(subcommand: u16, payload: &[u8]) -> Result<HwRequest, HwError> {
        use subcommand::*;
        match subcommand {
            GET_ACTUATOR_FEEDBACK => {
                let selector = Reader::exact(subcommand, payload, 1)?.u8()?;
                check_selector(selector)?;
                Ok(HwRequest::GetActuatorFeedback { selector })
            }
            SEND_ACTUATOR_COMMAND => {
                let mut r = Reader::exact(subcommand, payload, ACTUATOR_COMMAND_LEN)?;
                let joint = r.u8()?;
                check_joint(joint)?;
                let flags = CommandFlags(r.u32()?);
                let command = ActuatorCommand {
                    flags,
                    position_deg: r.f32("position_deg")?,
                    velocity_deg_s: r.f32("velocity_deg_s")?,
                    torque_nm: r.f32("torque_nm")?,
                    current_a: r.f32("current_a")?,
                };
                command.validate()?;
                Ok(HwRequest::SendActuatorCommand { joint, command })
            }
            GET_ARM_STATE => empty(subcommand, payload, HwRequest::GetArmState),
            STOP_ALL_JOINTS => empty(subcommand, payload, HwRequest::StopAllJoints),
            CLEAR_ALL_FAULTS => empty(subcommand, payload, HwRequest::ClearAllFaults),
            other => Err(HwError::UnknownSubcommand(other)),
        }
    }
}

/// `value` for a subcommand whose payload is empty, as it must be.
fn empty<T>(subcommand: u16, payload: &[u8], value: T) -> Result<T, HwError> {
    Reader::exact(subcommand, payload, 0).map(|_| value)
}

/// A reply payload with return code OK; any other code has an empty payload.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum HwReply {
    /// 0..=7 blocks, joints strictly ascending.
    GetActuatorFeedback {
        actuators: Vec<ActuatorFeedback>,
    },
    /// The commanded actuator's feedback after the command was applied.
    SendActuatorCommand {
        feedback: ActuatorFeedback,
    },
    GetArmState {
        state: ArmState,
    },
    StopAllJoints,
    ClearAllFaults,
}

impl HwReply {
    pub fn subcommand(&self) -> u16 {
        match self {
            HwReply::GetActuatorFeedback { .. } => subcommand::GET_ACTUATOR_FEEDBACK,
            HwReply::SendActuatorCommand { .. } => subcommand::SEND_ACTUATOR_COMMAND,
            HwReply::GetArmState { .. } => subcommand::GET_ARM_STATE,
            HwReply::StopAllJoints => subcommand::STOP_ALL_JOINTS,
            HwReply::ClearAllFaults => subcommand::CLEAR_ALL_FAULTS,
        }
    }

    /// What [`HwReply::decode`] checks: at most 7 blocks, joints 1..=7 strictly ascending,
    /// finite floats. A server calls this before [`HwReply::encode_payload`].
    pub fn validate(&self) -> Result<(), HwError> {
        match self {
            HwReply::GetActuatorFeedback { actuators } => {
                if actuators.len() > usize::from(JOINT_COUNT) {
                    return Err(HwError::CountOutOfRange(actuators.len()));
                }
                let mut previous = 0;
                for feedback in actuators {
                    feedback.validate()?;
                    check_order(previous, feedback.joint)?;
                    previous = feedback.joint;
                }
                Ok(())
            }
            HwReply::SendActuatorCommand { feedback } => feedback.validate(),
            HwReply::GetArmState { state } => state.validate(),
            HwReply::StopAllJoints | HwReply::ClearAllFaults => Ok(()),
        }
    }

    /// The inner Payload bytes. Writes what it is given (at most 255 blocks); values that
    /// [`HwReply::validate`] rejects produce bytes [`HwReply::decode`] rejects.
    pub fn encode_payload(&self) -> Vec<u8> {
        let mut out = Vec::new();
        match self {
            HwReply::GetActuatorFeedback { actuators } => {
                let count = u8::try_from(actuators.len()).unwrap_or(u8::MAX);
                out.push(count);
                for feedback in actuators.iter().take(usize::from(count)) {
                    feedback.write(&mut out);
                }
            }
            HwReply::SendActuatorCommand { feedback } => feedback.write(&mut out),
            HwReply::GetArmState { state } => state.write(&mut out),
            HwReply::StopAllJoints | HwReply::ClearAllFaults => {}
        }
        out
    }

    /// Parses and validates the inner Payload of an OK reply with this subcommand.
    pub fn decode(subcommand: u16, payload: &[u8]) -> Result<HwReply, HwError> {
        use subcommand::*;
        match subcommand {
            GET_ACTUATOR_FEEDBACK => {
                let Some((&count, _)) = payload.split_first() else {
                    return Err(HwError::TooShort {
                        subcommand,
                        expected: 1,
                        got: 0,
                    });
                };
                if count > JOINT_COUNT {
                    return Err(HwError::CountOutOfRange(usize::from(count)));
                }
                let expected = 1 + usize::from(count) * FEEDBACK_BLOCK_LEN;
                if payload.len() != expected {
                    return Err(HwError::CountMismatch {
                        subcommand,
                        count,
                        expected,
                        got: payload.len(),
                    });
                }
                let mut r = Reader::exact(subcommand, payload, expected)?;
                r.u8()?;
                let mut actuators = Vec::with_capacity(usize::from(count));
                let mut previous = 0;
                for _ in 0..count {
                    let feedback = ActuatorFeedback::read(&mut r)?;
                    check_order(previous, feedback.joint)?;
                    previous = feedback.joint;
                    actuators.push(feedback);
                }
                Ok(HwReply::GetActuatorFeedback { actuators })
            }
            SEND_ACTUATOR_COMMAND => {
                let mut r = Reader::exact(subcommand, payload, FEEDBACK_BLOCK_LEN)?;
                let feedback = ActuatorFeedback::read(&mut r)?;
                Ok(HwReply::SendActuatorCommand { feedback })
            }
            GET_ARM_STATE => {
                let mut r = Reader::exact(subcommand, payload, ARM_STATE_LEN)?;
                let state = ArmState::read(&mut r)?;
                Ok(HwReply::GetArmState { state })
            }
            STOP_ALL_JOINTS => empty(subcommand, payload, HwReply::StopAllJoints),
            CLEAR_ALL_FAULTS => empty(subcommand, payload, HwReply::ClearAllFaults),
            other => Err(HwError::UnknownSubcommand(other)),
        }
    }
}
