//! armjog's hardware companion ICD (`docs/hardware-icd.md`) through the public API of
//! `armjog::talos::hardware`: hand-written byte vectors, every rejection, flag and state names,
//! JSON shape, and property round trips.

use crate::common;
use common::hex;

use armjog::kortex::Flag;
use armjog::talos::hardware::*;
use proptest::prelude::*;

// Hand-computed IEEE-754 big-endian values used below:
//   0.125 3E000000   0.25 3E800000   0.5 3F000000   1.0 3F800000   1.5 3FC00000
//   10.0 41200000   24.0 41C00000   25.0 41C80000   30.0 41F00000   40.0 42200000
//   45.0 42340000   50.0 42480000   90.0 42B40000   180.0 43340000
//   -0.125 BE000000 -1.0 BF800000   -2.5 C0200000   -9.5 C1180000
//   NaN 7FC00000    +inf 7F800000   -inf FF800000

/// Joint 2 in servoing: the doc's worked reply block.
const BLOCK_J2: &str = "02 00000830 0000000C 42B40000 C0200000 3F800000 3F000000
                        41C00000 41F00000 42200000 00000000 00000000 00000000 00000000";
/// Joint 7 braking with a major fault and non-zero banks.
const BLOCK_J7: &str = "07 00001400 000001F4 43340000 00000000 BF800000 3E800000
                        41C00000 42480000 42340000 00000002 80000000 00010000 00000001";

fn feedback_j2() -> ActuatorFeedback {
    ActuatorFeedback {
        joint: 2,
        status: StatusFlags(0x0000_0830),
        jitter_us: 12,
        position_deg: 90.0,
        velocity_deg_s: -2.5,
        torque_nm: 1.0,
        current_a: 0.5,
        voltage_v: 24.0,
        motor_temp_c: 30.0,
        core_temp_c: 40.0,
        fault_bank_a: 0,
        fault_bank_b: 0,
        warning_bank_a: 0,
        warning_bank_b: 0,
    }
}

fn feedback_j7() -> ActuatorFeedback {
    ActuatorFeedback {
        joint: 7,
        status: StatusFlags::MAJOR_FAULT | StatusFlags::BRAKING,
        jitter_us: 500,
        position_deg: 180.0,
        velocity_deg_s: 0.0,
        torque_nm: -1.0,
        current_a: 0.25,
        voltage_v: 24.0,
        motor_temp_c: 50.0,
        core_temp_c: 45.0,
        fault_bank_a: 2,
        fault_bank_b: 0x8000_0000,
        warning_bank_a: 0x0001_0000,
        warning_bank_b: 1,
    }
}

const ARM_STATE_HEX: &str = "0007 00800000 00000400
    3FC00000 41C00000 42200000 41C80000
    3F000000 00000000 3E800000  42B40000 00000000 43340000
    3E000000 BE000000 00000000  00000000 00000000 41200000
    00000000 00000000 C1180000  00000000 00000000 3F800000";

fn arm_state() -> ArmState {
    ArmState {
        robot_state: RobotState::READY,
        faults: ArmFlags::from(Flag::EmergencyStop),
        warnings: ArmFlags::from(Flag::UnableToReachPose),
        current_a: 1.5,
        voltage_v: 24.0,
        cpu_temp_c: 40.0,
        ambient_temp_c: 25.0,
        tcp_position_m: [0.5, 0.0, 0.25],
        tcp_orientation_deg: [90.0, 0.0, 180.0],
        linear_velocity_m_s: [0.125, -0.125, 0.0],
        angular_velocity_deg_s: [0.0, 0.0, 10.0],
        force_n: [0.0, 0.0, -9.5],
        torque_nm: [0.0, 0.0, 1.0],
    }
}

fn jog_j2() -> HwRequest {
    HwRequest::SendActuatorCommand {
        joint: 2,
        command: ActuatorCommand::jog(90.0, -2.5),
    }
}

/// (subcommand, request, hand-written payload)
fn request_vectors() -> Vec<(u16, HwRequest, Vec<u8>)> {
    vec![
        (
            0x0001,
            HwRequest::GetActuatorFeedback { selector: 0 },
            hex("00"),
        ),
        (
            0x0001,
            HwRequest::GetActuatorFeedback { selector: 7 },
            hex("07"),
        ),
        (
            0x0002,
            jog_j2(),
            hex("02 00000001 42B40000 C0200000 00000000 00000000"),
        ),
        (
            0x0002,
            HwRequest::SendActuatorCommand {
                joint: 4,
                // Both fault flags cleared without moving: servoing off, setpoints at rest.
                command: ActuatorCommand {
                    flags: CommandFlags::CLEAR_MAJOR_FAULT | CommandFlags::CLEAR_MINOR_FAULT,
                    ..ActuatorCommand::jog(-2.5, 0.0)
                },
            },
            hex("04 0000000C C0200000 00000000 00000000 00000000"),
        ),
        (
            0x0002,
            HwRequest::SendActuatorCommand {
                joint: 7,
                command: ActuatorCommand {
                    flags: CommandFlags(0x0000_0301),
                    position_deg: 180.0,
                    velocity_deg_s: 10.0,
                    torque_nm: -9.5,
                    current_a: 1.5,
                },
            },
            hex("07 00000301 43340000 41200000 C1180000 3FC00000"),
        ),
        (0x0003, HwRequest::GetArmState, vec![]),
        (0x0004, HwRequest::StopAllJoints, vec![]),
        (0x0005, HwRequest::ClearAllFaults, vec![]),
    ]
}

/// (subcommand, reply, hand-written payload)
fn reply_vectors() -> Vec<(u16, HwReply, Vec<u8>)> {
    let mut j1 = feedback_j2();
    j1.joint = 1;
    vec![
        (
            0x0001,
            HwReply::GetActuatorFeedback { actuators: vec![] },
            hex("00"),
        ),
        (
            0x0001,
            HwReply::GetActuatorFeedback {
                actuators: vec![feedback_j2()],
            },
            hex(&format!("01 {BLOCK_J2}")),
        ),
        (
            0x0001,
            HwReply::GetActuatorFeedback {
                actuators: vec![j1, feedback_j7()],
            },
            hex(&format!("02 01{} {BLOCK_J7}", &BLOCK_J2.trim()[2..])),
        ),
        (
            0x0002,
            HwReply::SendActuatorCommand {
                feedback: feedback_j2(),
            },
            hex(BLOCK_J2),
        ),
        (
            0x0003,
            HwReply::GetArmState { state: arm_state() },
            hex(ARM_STATE_HEX),
        ),
        (0x0004, HwReply::StopAllJoints, vec![]),
        (0x0005, HwReply::ClearAllFaults, vec![]),
    ]
}

#[test]
fn subcommand_values_and_names() {
    assert_eq!(subcommand::GET_ACTUATOR_FEEDBACK, 0x0001);
    assert_eq!(subcommand::SEND_ACTUATOR_COMMAND, 0x0002);
    assert_eq!(subcommand::GET_ARM_STATE, 0x0003);
    assert_eq!(subcommand::STOP_ALL_JOINTS, 0x0004);
    assert_eq!(subcommand::CLEAR_ALL_FAULTS, 0x0005);
    assert_eq!(subcommand::name(0x0003), Some("get_arm_state"));
    assert_eq!(subcommand::name(0x0000), None);
    assert_eq!(subcommand::name(0x0006), None);
}

#[test]
fn layout_lengths_match_the_doc() {
    assert_eq!(hex(BLOCK_J2).len(), FEEDBACK_BLOCK_LEN);
    assert_eq!(FEEDBACK_BLOCK_LEN, 53);
    assert_eq!(ACTUATOR_COMMAND_LEN, 21);
    assert_eq!(hex(ARM_STATE_HEX).len(), ARM_STATE_LEN);
    assert_eq!(ARM_STATE_LEN, 98);
}

#[test]
fn requests_encode_and_decode_to_known_bytes() {
    for (sub, request, bytes) in request_vectors() {
        assert_eq!(request.subcommand(), sub, "{request:?}");
        assert_eq!(request.encode_payload().unwrap(), bytes, "{request:?}");
        assert_eq!(HwRequest::decode(sub, &bytes).unwrap(), request);
    }
}

#[test]
fn replies_encode_and_decode_to_known_bytes() {
    for (sub, reply, bytes) in reply_vectors() {
        assert_eq!(reply.subcommand(), sub, "{reply:?}");
        reply.validate().unwrap();
        assert_eq!(reply.encode_payload(), bytes, "{reply:?}");
        assert_eq!(HwReply::decode(sub, &bytes).unwrap(), reply);
    }
}

fn short(subcommand: u16, expected: usize, got: usize) -> HwError {
    HwError::TooShort {
        subcommand,
        expected,
        got,
    }
}

fn long(subcommand: u16, expected: usize, got: usize) -> HwError {
    HwError::TooLong {
        subcommand,
        expected,
        got,
    }
}

fn mismatch(count: u8, expected: usize, got: usize) -> HwError {
    let subcommand = subcommand::GET_ACTUATOR_FEEDBACK;
    HwError::CountMismatch {
        subcommand,
        count,
        expected,
        got,
    }
}

#[test]
fn every_payload_one_byte_short_or_long_is_rejected() {
    for (sub, _, bytes) in request_vectors() {
        let n = bytes.len();
        let longer = [bytes.as_slice(), &[0]].concat();
        assert_eq!(HwRequest::decode(sub, &longer), Err(long(sub, n, n + 1)));
        if n > 0 {
            assert_eq!(
                HwRequest::decode(sub, &bytes[..n - 1]),
                Err(short(sub, n, n - 1))
            );
        }
    }
    for (sub, _, bytes) in reply_vectors() {
        let n = bytes.len();
        let longer = [bytes.as_slice(), &[0]].concat();
        let shorter = &bytes[..n.saturating_sub(1)];
        if sub == subcommand::GET_ACTUATOR_FEEDBACK {
            // The count byte fixes the length: extra or missing bytes are a count mismatch.
            let count = bytes[0];
            assert_eq!(
                HwReply::decode(sub, &longer),
                Err(mismatch(count, n, n + 1))
            );
            let expected = if n == 1 {
                short(sub, 1, 0)
            } else {
                mismatch(count, n, n - 1)
            };
            assert_eq!(HwReply::decode(sub, shorter), Err(expected));
        } else {
            assert_eq!(HwReply::decode(sub, &longer), Err(long(sub, n, n + 1)));
            if n > 0 {
                assert_eq!(HwReply::decode(sub, shorter), Err(short(sub, n, n - 1)));
            }
        }
    }
}

#[test]
fn error_messages_name_the_problem() {
    let e = HwRequest::decode(0x0002, &hex("02 00000001")).unwrap_err();
    assert_eq!(
        e.to_string(),
        "payload too short for subcommand 0x0002 (send_actuator_command): expected 21 bytes, got 5"
    );
    assert_eq!(
        HwRequest::decode(0x0006, &[]).unwrap_err().to_string(),
        "unknown hardware subcommand 0x0006"
    );
    let e = HwReply::decode(0x0001, &hex("01 02")).unwrap_err();
    assert_eq!(
        e.to_string(),
        "count mismatch for subcommand 0x0001 (get_actuator_feedback): count byte says 1 actuator blocks (54 bytes) but the payload has 2 bytes"
    );
}

#[test]
fn unknown_subcommands_are_rejected_both_ways() {
    for sub in [0x0000, 0x0006, 0x0008, 0x8001, 0xFFFF] {
        assert_eq!(
            HwRequest::decode(sub, &[]),
            Err(HwError::UnknownSubcommand(sub))
        );
        assert_eq!(
            HwReply::decode(sub, &[]),
            Err(HwError::UnknownSubcommand(sub))
        );
    }
    assert_eq!(HwError::UnknownSubcommand(6).return_code(), 0x0009);
    assert_eq!(HwError::JointOutOfRange(0).return_code(), 0x0002);
}

#[test]
fn joints_and_selectors_out_of_range() {
    assert_eq!(
        HwRequest::decode(1, &hex("08")),
        Err(HwError::SelectorOutOfRange(8))
    );
    assert_eq!(
        HwRequest::decode(1, &hex("FF")),
        Err(HwError::SelectorOutOfRange(255))
    );
    let bad = HwRequest::GetActuatorFeedback { selector: 8 };
    assert_eq!(bad.encode_payload(), Err(HwError::SelectorOutOfRange(8)));
    for joint in [0u8, 8, 0xFF] {
        let mut bytes = hex("02 00000001 42B40000 C0200000 00000000 00000000");
        bytes[0] = joint;
        assert_eq!(
            HwRequest::decode(2, &bytes),
            Err(HwError::JointOutOfRange(joint))
        );
        let request = HwRequest::SendActuatorCommand {
            joint,
            command: ActuatorCommand::jog(0.0, 1.0),
        };
        assert_eq!(
            request.encode_payload(),
            Err(HwError::JointOutOfRange(joint))
        );
        let mut block = hex(BLOCK_J2);
        block[0] = joint;
        assert_eq!(
            HwReply::decode(2, &block),
            Err(HwError::JointOutOfRange(joint))
        );
    }
}

#[test]
fn non_finite_values_are_rejected_with_their_field() {
    let cases = [
        (
            "02 00000001 7FC00000 00000000 00000000 00000000",
            "position_deg",
        ),
        (
            "02 00000001 00000000 7F800000 00000000 00000000",
            "velocity_deg_s",
        ),
        (
            "02 00000001 00000000 00000000 FF800000 00000000",
            "torque_nm",
        ),
        (
            "02 00000001 00000000 00000000 00000000 7FC00000",
            "current_a",
        ),
    ];
    for (bytes, field) in cases {
        assert_eq!(
            HwRequest::decode(2, &hex(bytes)),
            Err(HwError::NonFinite { field })
        );
    }
    let request = HwRequest::SendActuatorCommand {
        joint: 1,
        command: ActuatorCommand::jog(0.0, f32::NAN),
    };
    assert_eq!(
        request.encode_payload(),
        Err(HwError::NonFinite {
            field: "velocity_deg_s"
        })
    );
    // Ambient temperature is the 4th float of the arm state (offset 10 + 12 = 22).
    let mut arm = hex(ARM_STATE_HEX);
    arm[22..26].copy_from_slice(&hex("7F800000"));
    assert_eq!(
        HwReply::decode(3, &arm),
        Err(HwError::NonFinite {
            field: "ambient_temp_c"
        })
    );
    // Torque z is the last float.
    let mut arm = hex(ARM_STATE_HEX);
    arm[94..98].copy_from_slice(&hex("FFC00000"));
    assert_eq!(
        HwReply::decode(3, &arm),
        Err(HwError::NonFinite {
            field: "torque_nm.z"
        })
    );
    // Core temperature of a feedback block is at offset 33.
    let mut block = hex(BLOCK_J2);
    block[33..37].copy_from_slice(&hex("7FC00000"));
    assert_eq!(
        HwReply::decode(2, &block),
        Err(HwError::NonFinite {
            field: "core_temp_c"
        })
    );
    let mut state = arm_state();
    state.force_n[1] = f32::INFINITY;
    assert_eq!(
        HwReply::GetArmState { state }.validate(),
        Err(HwError::NonFinite { field: "force_n.y" })
    );
}

#[test]
fn undefined_command_bits_are_rejected() {
    let bytes = hex("01 00000401 00000000 00000000 00000000 00000000");
    assert_eq!(
        HwRequest::decode(2, &bytes),
        Err(HwError::UndefinedBits {
            field: "command_flags",
            bits: 0x400
        })
    );
    let request = HwRequest::SendActuatorCommand {
        joint: 1,
        command: ActuatorCommand {
            flags: CommandFlags(0x8000_0000),
            ..ActuatorCommand::jog(0.0, 0.0)
        },
    };
    assert_eq!(
        request.encode_payload(),
        Err(HwError::UndefinedBits {
            field: "command_flags",
            bits: 0x8000_0000
        })
    );
}

#[test]
fn feedback_list_count_and_order() {
    assert_eq!(HwReply::decode(1, &[]), Err(short(1, 1, 0)));
    assert_eq!(
        HwReply::decode(1, &hex("08")),
        Err(HwError::CountOutOfRange(8))
    );
    let two = hex(&format!("02 {BLOCK_J2}"));
    assert_eq!(HwReply::decode(1, &two), Err(mismatch(2, 107, 54)));
    let reversed = hex(&format!("02 {BLOCK_J7} {BLOCK_J2}"));
    assert_eq!(
        HwReply::decode(1, &reversed),
        Err(HwError::JointOrder {
            previous: 7,
            joint: 2
        })
    );
    let duplicate = hex(&format!("02 {BLOCK_J2} {BLOCK_J2}"));
    assert_eq!(
        HwReply::decode(1, &duplicate),
        Err(HwError::JointOrder {
            previous: 2,
            joint: 2
        })
    );
    let eight = HwReply::GetActuatorFeedback {
        actuators: vec![feedback_j2(); 8],
    };
    assert_eq!(eight.validate(), Err(HwError::CountOutOfRange(8)));
    let unordered = HwReply::GetActuatorFeedback {
        actuators: vec![feedback_j7(), feedback_j2()],
    };
    assert_eq!(
        unordered.validate(),
        Err(HwError::JointOrder {
            previous: 7,
            joint: 2
        })
    );
}

/// Every bit value of kinova-actuator-cyclic.txt, typed in by hand.
const COMMAND_BITS: [(u32, &str); 10] = [
    (0x1, "servo_enable"),
    (0x2, "brake_disable"),
    (0x4, "clear_major_fault"),
    (0x8, "clear_minor_fault"),
    (0x10, "protective_stop"),
    (0x20, "force_brake_release"),
    (0x40, "ignore"),
    (0x80, "low_gains"),
    (0x100, "led_0"),
    (0x200, "led_1"),
];
const STATUS_BITS: [(u32, &str); 24] = [
    (0x10, "stabilized"),
    (0x20, "motor_indexed"),
    (0x40, "motor_indexing"),
    (0x80, "reserved_7"),
    (0x100, "reserved_8"),
    (0x200, "reserved_9"),
    (0x400, "braking"),
    (0x800, "servoing"),
    (0x1000, "major_fault"),
    (0x2000, "minor_fault"),
    (0x4000, "calibrated_torque"),
    (0x8000, "calibrated_mag_sensor"),
    (0x10000, "calibrated_zero"),
    (0x20000, "reserved_17"),
    (0x40000, "reserved_18"),
    (0x80000, "reserved_19"),
    (0x100000, "reserved_20"),
    (0x200000, "reserved_21"),
    (0x400000, "reserved_22"),
    (0x800000, "reserved_23"),
    (0x1000000, "calibrated_current"),
    (0x2000000, "calibrated_motor"),
    (0x4000000, "sw0_active"),
    (0x8000000, "sw1_active"),
];

#[test]
fn every_command_flag_decodes_to_its_name() {
    for (value, name) in COMMAND_BITS {
        let flags = CommandFlags(value);
        assert_eq!(flags.names(), vec![name]);
        assert_eq!(flags.to_string(), name);
        assert_eq!(flags.undefined_bits(), 0);
    }
    let named: Vec<(u32, &str)> = CommandFlags::NAMED.iter().map(|(f, n)| (f.0, *n)).collect();
    assert_eq!(named, COMMAND_BITS);
    assert_eq!(CommandFlags::DEFINED, 0x3FF);
    assert_eq!(CommandFlags::SERVO_ENABLE.0, 0x1);
    assert_eq!(CommandFlags::CLEAR_MAJOR_FAULT.0, 0x4);
    assert_eq!(CommandFlags::CLEAR_MINOR_FAULT.0, 0x8);
    assert_eq!(CommandFlags::LED_1.0, 0x200);
}

#[test]
fn every_status_flag_decodes_to_its_name() {
    for (value, name) in STATUS_BITS {
        assert_eq!(StatusFlags(value).names(), vec![name]);
        assert_eq!(StatusFlags(value).to_string(), name);
    }
    let named: Vec<(u32, &str)> = StatusFlags::NAMED.iter().map(|(f, n)| (f.0, *n)).collect();
    assert_eq!(named, STATUS_BITS);
    assert_eq!(StatusFlags::DEFINED, 0x0FFF_FFF0);
    assert_eq!(StatusFlags::RESERVED_7.0, 0x80);
    assert_eq!(StatusFlags::MAJOR_FAULT.0, 0x1000);
    assert_eq!(StatusFlags::SW1_ACTIVE.0, 0x800_0000);
}

#[test]
fn flag_words_combine_and_show_unknown_bits() {
    assert_eq!(CommandFlags::NO_COMMAND.names(), Vec::<&str>::new());
    assert_eq!(CommandFlags::NO_COMMAND.to_string(), "no_command");
    assert_eq!(StatusFlags::UNKNOWN_STATUS.to_string(), "unknown_status");
    assert_eq!(ArmFlags(0).to_string(), "none");
    let clear = CommandFlags(0x0C);
    assert_eq!(
        clear,
        CommandFlags::CLEAR_MAJOR_FAULT | CommandFlags::CLEAR_MINOR_FAULT
    );
    assert_eq!(clear.to_string(), "clear_major_fault|clear_minor_fault");
    assert!(clear.contains(CommandFlags::CLEAR_MINOR_FAULT));
    assert!(!clear.contains(CommandFlags::SERVO_ENABLE | CommandFlags::CLEAR_MINOR_FAULT));
    assert_eq!(
        CommandFlags(0x1000_0401).names(),
        vec!["servo_enable", "bit_10", "bit_28"]
    );
    assert_eq!(CommandFlags(0x1000_0401).undefined_bits(), 0x1000_0400);
    let status = StatusFlags(0x8000_0831);
    assert_eq!(
        status.to_string(),
        "bit_0|stabilized|motor_indexed|servoing|bit_31"
    );
    assert!(status.contains(StatusFlags::SERVOING));
    assert_eq!(
        ArmFlags(0x0080_0401).names(),
        vec![
            "firmware_update_failure",
            "unable_to_reach_pose",
            "emergency_stop"
        ]
    );
    assert_eq!(
        ArmFlags(0x8000_0002).to_string(),
        "unknown_bit_1|unknown_bit_31"
    );
    assert_eq!(ArmFlags::from(Flag::IllegalPosition).0, 0x4000_0000);
}

#[test]
fn robot_states_are_named() {
    // The Modbus register map's names, so both links name a state alike.
    let names = [
        "unspecified",
        "base_initialization",
        "base_initialized",
        "arm_initialization",
        "in_fault",
        "in_maintenance",
        "low_level_servoing",
        "ready",
        "controlled_by_sequence",
        "controlled_manually",
    ];
    for (value, name) in (0u16..).zip(names) {
        assert_eq!(RobotState(value).to_string(), name);
    }
    assert_eq!(RobotState::IN_FAULT, RobotState(4));
    assert_eq!(RobotState::CONTROLLED_MANUALLY, RobotState(9));
    assert_eq!(RobotState(10).to_string(), "state_10");
    assert_eq!(RobotState(10).name(), None);
}

#[test]
fn structures_serialize_to_json_with_raw_flag_words() {
    let json = serde_json::to_value(feedback_j2()).unwrap();
    assert_eq!(json["joint"], 2);
    assert_eq!(json["status"], 0x830);
    assert_eq!(json["position_deg"], 90.0);
    let json = serde_json::to_value(arm_state()).unwrap();
    assert_eq!(json["robot_state"], 7);
    assert_eq!(json["faults"], 0x0080_0000);
    assert_eq!(json["force_n"], serde_json::json!([0.0, 0.0, -9.5]));
}

fn finite() -> impl Strategy<Value = f32> {
    prop_oneof![
        -1.0e6f32..1.0e6f32,
        Just(0.0),
        Just(-0.0),
        Just(f32::MAX),
        Just(f32::MIN)
    ]
}

fn feedback(joint: u8) -> impl Strategy<Value = ActuatorFeedback> {
    (any::<[u32; 6]>(), proptest::array::uniform7(finite())).prop_map(move |(w, f)| {
        ActuatorFeedback {
            joint,
            status: StatusFlags(w[0]),
            jitter_us: w[1],
            position_deg: f[0],
            velocity_deg_s: f[1],
            torque_nm: f[2],
            current_a: f[3],
            voltage_v: f[4],
            motor_temp_c: f[5],
            core_temp_c: f[6],
            fault_bank_a: w[2],
            fault_bank_b: w[3],
            warning_bank_a: w[4],
            warning_bank_b: w[5],
        }
    })
}

fn any_request() -> impl Strategy<Value = HwRequest> {
    let command =
        (0u32..=0x3FF, proptest::array::uniform4(finite())).prop_map(|(b, f)| ActuatorCommand {
            flags: CommandFlags(b),
            position_deg: f[0],
            velocity_deg_s: f[1],
            torque_nm: f[2],
            current_a: f[3],
        });
    prop_oneof![
        (0u8..=7).prop_map(|selector| HwRequest::GetActuatorFeedback { selector }),
        (1u8..=7, command)
            .prop_map(|(joint, command)| HwRequest::SendActuatorCommand { joint, command }),
        Just(HwRequest::GetArmState),
        Just(HwRequest::StopAllJoints),
        Just(HwRequest::ClearAllFaults),
    ]
}

fn any_reply() -> impl Strategy<Value = HwReply> {
    let list = proptest::sample::subsequence((1u8..=7).collect::<Vec<_>>(), 0..=7)
        .prop_flat_map(|joints| joints.into_iter().map(feedback).collect::<Vec<_>>());
    let state = (
        any::<(u16, u32, u32)>(),
        proptest::collection::vec(finite(), 22),
    )
        .prop_map(|((s, f, w), v)| {
            let xyz = |i: usize| [v[i], v[i + 1], v[i + 2]];
            ArmState {
                robot_state: RobotState(s),
                faults: ArmFlags(f),
                warnings: ArmFlags(w),
                current_a: v[0],
                voltage_v: v[1],
                cpu_temp_c: v[2],
                ambient_temp_c: v[3],
                tcp_position_m: xyz(4),
                tcp_orientation_deg: xyz(7),
                linear_velocity_m_s: xyz(10),
                angular_velocity_deg_s: xyz(13),
                force_n: xyz(16),
                torque_nm: xyz(19),
            }
        });
    prop_oneof![
        list.prop_map(|actuators| HwReply::GetActuatorFeedback { actuators }),
        (1u8..=7)
            .prop_flat_map(feedback)
            .prop_map(|feedback| HwReply::SendActuatorCommand { feedback }),
        state.prop_map(|state| HwReply::GetArmState { state }),
        Just(HwReply::StopAllJoints),
        Just(HwReply::ClearAllFaults),
    ]
}

proptest! {
    #[test]
    fn every_request_round_trips(request in any_request()) {
        let bytes = request.encode_payload().unwrap();
        prop_assert_eq!(HwRequest::decode(request.subcommand(), &bytes).unwrap(), request);
    }

    #[test]
    fn every_reply_round_trips(reply in any_reply()) {
        prop_assert!(reply.validate().is_ok());
        let bytes = reply.encode_payload();
        prop_assert_eq!(HwReply::decode(reply.subcommand(), &bytes).unwrap(), reply);
    }

    #[test]
    fn decoding_arbitrary_bytes_never_panics(
        sub in 0u16..=7,
        bytes in proptest::collection::vec(any::<u8>(), 0..400),
    ) {
        if let Ok(request) = HwRequest::decode(sub, &bytes) {
            prop_assert_eq!(request.encode_payload().unwrap(), bytes.clone());
        }
        if let Ok(reply) = HwReply::decode(sub, &bytes) {
            prop_assert!(reply.validate().is_ok());
            prop_assert_eq!(reply.encode_payload(), bytes);
        }
    }
}
