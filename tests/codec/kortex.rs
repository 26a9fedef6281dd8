//! Known-answer vectors for the Kortex register map, written by hand from the ICD: CDAB floats
//! and UINT32s, flag bitmasks and inputs, the snapshot's JSON shape, every command's writes,
//! and polar pan twists.

use armjog::kortex::commands::{self, CommandError, StoredMotion, Write};
use armjog::kortex::image::ReadBlock;
use armjog::kortex::two_registers::{f32_from_words, f32_to_words, u32_from_words, u32_to_words};
use armjog::kortex::{
    ActionStatus, Coded, ControlCoil, Flag, FlagSet, MoveType, PolarPanError, PolarPanSettings,
    Pose, ReferenceFrame, RegisterImage, RobotState, Table, Telemetry, Twist, polar_twist,
};
use serde_json::{Value, json};

#[test]
fn floats_and_u32s_are_low_word_first() {
    // (value, IEEE-754 bits by hand / Python's struct module, registers N and N + 1)
    let vectors: [(f32, [u16; 2]); 6] = [
        (1.0, [0x0000, 0x3F80]),
        (-0.5, [0x0000, 0xBF00]),
        (0.4566, [0xC77A, 0x3EE9]), // 0x3EE9C77A
        (0.001, [0x126F, 0x3A83]),  // 0x3A83126F
        (90.0, [0x0000, 0x42B4]),
        (100.0, [0x0000, 0x42C8]),
    ];
    for (value, words) in vectors {
        assert_eq!(f32_to_words(value), words, "{value}");
        assert_eq!(f32_from_words(words), value);
    }
    assert_eq!(u32_to_words(0x0080_0011), [0x0011, 0x0080]);
    assert_eq!(u32_from_words([0x0004, 0x4000]), 0x4000_0004);
    assert!(f32_from_words([0x0000, 0x7FC0]).is_nan());
}

/// An image with every field at a distinct, hand-encoded value.
fn known_image() -> RegisterImage {
    let mut image = RegisterImage::default();
    let ir = &mut image.input_registers;
    ir[0] = 4; // in fault
    ir[2..4].copy_from_slice(&[0x0011, 0x0080]); // faults: bits 0, 4, 23
    ir[4..6].copy_from_slice(&[0x0002, 0x4000]); // warnings: bit 1 (unnamed), bit 30
    ir[6..8].copy_from_slice(&[0x0000, 0x3FC0]); // current 1.5 A
    ir[8..10].copy_from_slice(&[0x0000, 0x41C0]); // voltage 24 V
    ir[10..12].copy_from_slice(&[0x0000, 0x4234]); // cpu 45 C
    ir[12..14].copy_from_slice(&[0x0000, 0x41F0]); // ambient 30 C
    // Joint 1 and joint 7 of each block; the rest stay zero.
    ir[34..36].copy_from_slice(&[0x0000, 0x4334]); // j1 position 180
    ir[46..48].copy_from_slice(&[0x0000, 0x42B4]); // j7 position 90
    ir[48..50].copy_from_slice(&[0x0000, 0xBF00]); // j1 velocity -0.5
    ir[60..62].copy_from_slice(&[0x0000, 0x3F80]); // j7 velocity 1
    ir[62..64].copy_from_slice(&[0x0000, 0x421C]); // j1 torque 39
    ir[74..76].copy_from_slice(&[0x0000, 0x4110]); // j7 torque 9
    ir[76..78].copy_from_slice(&[0x0000, 0x3E80]); // j1 current 0.25
    ir[88..90].copy_from_slice(&[0x0000, 0x4000]); // j7 current 2
    ir[90..92].copy_from_slice(&[0x0000, 0x4220]); // j1 temperature 40
    ir[102..104].copy_from_slice(&[0x0000, 0x4248]); // j7 temperature 50
    ir[104..106].copy_from_slice(&[0xC77A, 0x3EE9]); // x 0.4566
    ir[106..108].copy_from_slice(&[0x126F, 0x3A83]); // y 0.001
    ir[108..110].copy_from_slice(&[0x1B09, 0x3EDE]); // z 0.4338
    ir[110..112].copy_from_slice(&[0x0000, 0x42B4]); // theta x 90
    ir[114..116].copy_from_slice(&[0x0000, 0x42B4]); // theta z 90
    ir[116..118].copy_from_slice(&[0x0000, 0x3E80]); // twist x 0.25
    ir[126..128].copy_from_slice(&[0x0000, 0xC120]); // twist theta z -10
    ir[128..130].copy_from_slice(&[0x0000, 0x4120]); // force x 10
    ir[138..140].copy_from_slice(&[0x0000, 0xBF80]); // torque z -1
    let hr = &mut image.holding_registers;
    hr[0] = 2; // fault reset
    hr[100] = 3; // aborted
    hr[101] = 1234;
    hr[102] = 2; // cartesian trajectory
    hr[104..106].copy_from_slice(&[0x0000, 0x3E80]); // linear limit 0.25
    hr[106..108].copy_from_slice(&[0x0000, 0x4248]); // angular limit 50
    image.discrete_inputs[4] = true; // in fault
    image.discrete_inputs[32 + 25] = true; // fault input: inrush current limiter
    image.discrete_inputs[64 + 2] = true; // warning input: max ambient temperature
    image
}

#[test]
fn a_known_image_decodes_to_every_field() {
    let t = Telemetry::decode(&known_image());
    assert_eq!(t.robot_state, Coded::Known(RobotState::InFault));
    assert_eq!(t.state_from_inputs, Some(RobotState::InFault));
    assert_eq!(
        t.faults.flags(),
        vec![
            Flag::FirmwareUpdateFailure,
            Flag::JointFault,
            Flag::EmergencyStop,
            Flag::InrushCurrentLimiterFault
        ]
    );
    assert_eq!(
        t.warnings.names(),
        vec![
            "unknown_bit_1",
            "maximum_ambient_temperature",
            "illegal_position"
        ]
    );
    assert_eq!(
        (
            t.arm.current,
            t.arm.voltage,
            t.arm.cpu_temperature,
            t.arm.ambient_temperature
        ),
        (1.5, 24.0, 45.0, 30.0)
    );
    let j1 = t.joints[0];
    let j7 = t.joints[6];
    assert_eq!(
        [
            j1.position,
            j1.velocity,
            j1.torque,
            j1.current,
            j1.temperature
        ],
        [180.0, -0.5, 39.0, 0.25, 40.0]
    );
    assert_eq!(
        [
            j7.position,
            j7.velocity,
            j7.torque,
            j7.current,
            j7.temperature
        ],
        [90.0, 1.0, 9.0, 2.0, 50.0]
    );
    assert_eq!(t.joints[3].position, 0.0);
    let pose = t.tcp.pose;
    assert_eq!(
        [
            pose.x,
            pose.y,
            pose.z,
            pose.theta_x,
            pose.theta_y,
            pose.theta_z
        ],
        [0.4566, 0.001, 0.4338, 90.0, 0.0, 90.0]
    );
    assert_eq!((t.tcp.twist.x, t.tcp.twist.theta_z), (0.25, -10.0));
    assert_eq!((t.tcp.wrench.force_x, t.tcp.wrench.torque_z), (10.0, -1.0));
    assert_eq!(t.action.status, Coded::Known(ActionStatus::Aborted));
    assert_eq!(t.action.id, 1234);
    assert_eq!(
        t.action.move_type,
        Coded::Known(MoveType::CartesianTrajectory)
    );
    assert_eq!(
        (t.speed_limits.linear, t.speed_limits.angular),
        (0.25, 50.0)
    );
    assert_eq!(t.control, Coded::Known(ControlCoil::FaultReset));
}

#[test]
fn robot_state_falls_back_to_the_inputs_only_for_unlisted_numbers() {
    let mut image = RegisterImage::default();
    image.input_registers[0] = 42;
    assert_eq!(Telemetry::decode(&image).robot_state, Coded::Unknown(42));
    image.discrete_inputs[9] = true;
    let t = Telemetry::decode(&image);
    assert_eq!(t.robot_state, Coded::Known(RobotState::ControlledManually));
    image.input_registers[0] = 7;
    let t = Telemetry::decode(&image);
    assert_eq!(t.robot_state.key(), "ready");
    assert_eq!(t.state_from_inputs, Some(RobotState::ControlledManually));
}

#[test]
fn every_named_flag_sits_where_the_icd_puts_it() {
    // (flag, fault input, warning input) from the ICD's discrete input tables.
    let table = [
        (Flag::FirmwareUpdateFailure, 32, 64),
        (Flag::MaximumAmbientTemperature, 34, 66),
        (Flag::MaximumCoreTemperature, 35, 67),
        (Flag::JointFault, 36, 68),
        (Flag::AboveMaximumDof, 40, 72),
        (Flag::UnableToReachPose, 42, 74),
        (Flag::JointDetectionError, 43, 75),
        (Flag::NetworkInitialisationError, 44, 76),
        (Flag::MaximumCurrent, 45, 77),
        (Flag::MaximumVoltage, 46, 78),
        (Flag::MinimumVoltage, 47, 79),
        (Flag::EmergencyStop, 55, 87),
        (Flag::EmergencyLine, 56, 88),
        (Flag::InrushCurrentLimiterFault, 57, 89),
        (Flag::NvramCorrupted, 58, 90),
        (Flag::IncompatibleFirmwareVersion, 59, 91),
        (Flag::PowerOnSelfTestFailure, 60, 92),
        (Flag::DiscreteInputStuckActive, 61, 93),
        (Flag::IllegalPosition, 62, 94),
    ];
    assert_eq!(<Flag as armjog::kortex::CodeName>::ALL.len(), table.len());
    for (flag, fault, warning) in table {
        assert_eq!((flag.fault_input(), flag.warning_input()), (fault, warning));
        let mut image = RegisterImage::default();
        image.discrete_inputs[usize::from(warning)] = true;
        let t = Telemetry::decode(&image);
        assert!(t.faults.is_empty());
        assert_eq!(t.warnings.flags(), vec![flag]);
    }
    // Bit 30 of the fault bitmask: registers 2-3 = [0x0000, 0x4000].
    assert_eq!(
        FlagSet::from_bits(u32_from_words([0x0000, 0x4000])).flags(),
        vec![Flag::IllegalPosition]
    );
}

#[test]
fn the_json_object_has_exactly_the_documented_shape() {
    let value = serde_json::to_value(Telemetry::decode(&known_image())).unwrap();
    let keys = |v: &Value| -> Vec<String> {
        let mut k: Vec<String> = v.as_object().unwrap().keys().cloned().collect();
        k.sort();
        k
    };
    let sorted = |k: &[&str]| {
        let mut k: Vec<String> = k.iter().map(|s| s.to_string()).collect();
        k.sort();
        k
    };
    assert_eq!(
        keys(&value),
        sorted(&[
            "robot_state",
            "faults",
            "warnings",
            "arm",
            "joints",
            "tcp",
            "action",
            "speed_limits"
        ])
    );
    assert_eq!(value["robot_state"], json!("in_fault"));
    assert_eq!(
        value["faults"],
        json!([
            "firmware_update_failure",
            "joint_fault",
            "emergency_stop",
            "inrush_current_limiter_fault"
        ])
    );
    assert_eq!(
        keys(&value["arm"]),
        sorted(&[
            "current",
            "voltage",
            "cpu_temperature",
            "ambient_temperature"
        ])
    );
    let joints = value["joints"].as_array().unwrap();
    assert_eq!(joints.len(), 7);
    assert_eq!(
        keys(&joints[0]),
        sorted(&["position", "velocity", "torque", "current", "temperature"])
    );
    assert_eq!(joints[0]["position"], json!(180.0));
    assert_eq!(keys(&value["tcp"]), sorted(&["pose", "twist", "wrench"]));
    let cartesian = sorted(&["x", "y", "z", "theta_x", "theta_y", "theta_z"]);
    assert_eq!(keys(&value["tcp"]["pose"]), cartesian);
    assert_eq!(keys(&value["tcp"]["twist"]), cartesian);
    assert_eq!(
        keys(&value["tcp"]["wrench"]),
        sorted(&[
            "force_x", "force_y", "force_z", "torque_x", "torque_y", "torque_z"
        ])
    );
    // Serialised straight from f32, a value prints as the ICD float it is.
    let text = serde_json::to_string(&Telemetry::decode(&known_image())).unwrap();
    assert!(
        text.contains(r#""pose":{"x":0.4566,"y":0.001,"z":0.4338,"#),
        "{text}"
    );
    assert_eq!(
        value["action"],
        json!({"status": "aborted", "id": 1234, "move_type": "cartesian_trajectory"})
    );
    assert_eq!(
        value["speed_limits"],
        json!({"linear": 0.25, "angular": 50.0})
    );
}

#[test]
fn twist_and_stop_writes() {
    let twist = Twist {
        y: 0.5,
        theta_x: -0.5,
        ..Twist::ZERO
    };
    assert_eq!(
        commands::twist(ReferenceFrame::Mixed, twist).unwrap(),
        vec![
            Write::Registers {
                addr: 200,
                values: vec![0]
            },
            Write::Registers {
                addr: 202,
                values: vec![3, 1, 0, 0, 0x0000, 0x3F00, 0, 0, 0x0000, 0xBF00, 0, 0, 0, 0]
            },
            Write::Registers {
                addr: 200,
                values: vec![1]
            },
        ]
    );
    assert_eq!(
        commands::stop(),
        vec![Write::Registers {
            addr: 200,
            values: vec![2]
        }]
    );
    assert_eq!(
        commands::stop()[0].to_string(),
        "write holding registers 200-200 = [0x0002] (FC16)"
    );
}

#[test]
fn values_over_the_limits_are_refused() {
    let at_limit = Twist {
        x: 0.3,
        y: 0.4,
        theta_y: 100.0,
        ..Twist::ZERO
    };
    assert!(commands::twist(ReferenceFrame::Base, at_limit).is_ok());
    let too_fast = Twist {
        x: 0.3,
        y: 0.41,
        ..Twist::ZERO
    };
    assert!(matches!(
        commands::twist(ReferenceFrame::Base, too_fast),
        Err(CommandError::LinearTooFast { .. })
    ));
    let spinning = Twist {
        theta_x: -60.0,
        theta_y: 81.0,
        ..Twist::ZERO
    };
    assert!(matches!(
        commands::twist(ReferenceFrame::Base, spinning),
        Err(CommandError::AngularTooFast { .. })
    ));
    let nan = Twist {
        theta_z: f32::NAN,
        ..Twist::ZERO
    };
    assert!(matches!(
        commands::twist(ReferenceFrame::Base, nan),
        Err(CommandError::NotFinite {
            what: "theta_z",
            ..
        })
    ));
    assert_eq!(commands::reference_frame(3), Ok(ReferenceFrame::Base));
    for bad in [0, 4, 0xFFFF] {
        assert_eq!(
            commands::reference_frame(bad),
            Err(CommandError::UnknownReferenceFrame(bad))
        );
    }
    assert!(commands::speed_limits(0.5, 100.0).is_ok());
    assert!(commands::speed_limits(0.51, 100.0).is_err());
    assert!(commands::speed_limits(0.1, -1.0).is_err());
    assert!(commands::speed_limits(0.1, f32::INFINITY).is_err());
    let in_mm = Pose {
        z: 433.8,
        ..Pose::default()
    };
    assert!(matches!(
        commands::go_to_pose(ReferenceFrame::Base, in_mm),
        Err(CommandError::OutOfReach { what: "z", .. })
    ));
    let spun = Pose {
        theta_y: 720.0,
        ..Pose::default()
    };
    assert!(commands::go_to_pose(ReferenceFrame::Base, spun).is_err());
}

#[test]
fn a_stored_id_is_1_to_65535_and_0_is_never_written() {
    assert_eq!(commands::STORED_IDS, 1..=65535);
    assert_eq!(commands::stored_id(1).unwrap(), 1);
    assert_eq!(commands::stored_id(65535).unwrap(), 65535);
    for refused in [0, -1, 65536] {
        let err = commands::stored_id(refused).expect_err("outside");
        assert_eq!(err.to_string(), format!("{refused} is outside 1 to 65535"));
    }
    for motion in [StoredMotion::Action, StoredMotion::Sequence] {
        assert!(commands::start_stored(0, motion).is_err(), "{motion:?} 0");
    }
}

#[test]
fn stored_motion_speed_limit_and_coil_writes() {
    assert_eq!(
        commands::start_stored(2, StoredMotion::Action).unwrap(),
        vec![
            Write::Registers {
                addr: 200,
                values: vec![0]
            },
            Write::Registers {
                addr: 201,
                values: vec![2, 0]
            },
            Write::Registers {
                addr: 200,
                values: vec![1]
            },
        ]
    );
    assert_eq!(
        commands::speed_limits(0.5, 90.0).unwrap(),
        vec![Write::Registers {
            addr: 216,
            values: vec![0x0000, 0x3F00, 0x0000, 0x42B4]
        }]
    );
    assert_eq!(
        commands::pulse(ControlCoil::FaultReset),
        vec![
            Write::Coil {
                addr: 2,
                value: true
            },
            Write::Coil {
                addr: 2,
                value: false
            }
        ]
    );
}

fn close(a: f32, b: f32) -> bool {
    (a - b).abs() < 1e-5
}

#[test]
fn polar_pan_twists_by_hand() {
    let settings = PolarPanSettings {
        angular_speed: 10.0,
        max_linear_speed: 0.25,
    };
    let w = 10f32.to_radians(); // 0.174533 rad/s
    let pose = Pose {
        x: 0.5,
        z: 0.3,
        ..Pose::default()
    };
    // Azimuth +1: rotation about base Z, v = w z x p = (0, 0.5 w, 0).
    let t = polar_twist(pose, 1.0, 0.0, settings).unwrap();
    assert!(
        close(t.y, 0.5 * w) && close(t.x, 0.0) && close(t.z, 0.0),
        "{t:?}"
    );
    assert_eq!((t.theta_x, t.theta_y, t.theta_z), (0.0, 0.0, 10.0));
    // Altitude +1 at bearing 0: axis (0, -1, 0), v = w (-z, 0, r) = w (-0.3, 0, 0.5).
    let t = polar_twist(pose, 0.0, 1.0, settings).unwrap();
    assert!(
        close(t.x, -0.3 * w) && close(t.y, 0.0) && close(t.z, 0.5 * w),
        "{t:?}"
    );
    assert!(close(t.theta_y, -10.0) && close(t.theta_x, 0.0) && t.theta_z == 0.0);
    // Bearing 90 deg (tool on +Y), altitude -1: axis (1, 0, 0), v = -w (0, -z, r).
    let side = Pose {
        y: 0.4,
        z: 0.3,
        ..Pose::default()
    };
    let t = polar_twist(side, 0.0, -1.0, settings).unwrap();
    assert!(close(t.y, 0.3 * w) && close(t.z, -0.4 * w), "{t:?}");
    assert!(close(t.theta_x, -10.0));
    // Far out, the linear speed is capped: 2 m x 0.1745 rad/s = 0.349 m/s -> 0.25 m/s.
    let far = Pose {
        x: 2.0,
        ..Pose::default()
    };
    let t = polar_twist(far, -1.0, 0.0, settings).unwrap();
    assert!(close(t.linear_speed(), 0.25), "{t:?}");
    assert!(close(t.theta_z, -10.0 * 0.25 / (2.0 * w)));
    // On the base axis there is no altitude axis.
    let up = Pose {
        z: 0.9,
        ..Pose::default()
    };
    assert!(matches!(
        polar_twist(up, 0.0, 1.0, settings),
        Err(PolarPanError::OnBaseAxis { .. })
    ));
    assert!(polar_twist(up, 1.0, 0.0, settings).is_ok());
    assert!(polar_twist(pose, 0.0, -1.01, settings).is_err());
}

#[test]
fn a_reply_longer_than_asked_is_refused() {
    let mut image = RegisterImage::default();
    let block = ReadBlock::new(Table::HoldingRegisters, 100, 108);
    assert!(image.store_words(block, &[0; 9]).is_err());
    assert!(image.store_words(block, &[7; 8]).is_ok());
    assert_eq!(image.holding_registers[107], 7);
}
