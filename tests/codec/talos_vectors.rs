//! Known-answer vectors for every ICD request and reply.
//!
//! Every byte string here was written by hand from `shared/icd/talos-api-icd.md`, field by field
//! (`|` separates the wrapper from the payload, spaces separate fields); none was produced by the
//! code under test. Each vector is checked in both directions: encoding the value gives the
//! bytes, and decoding the bytes (through `FrameCodec`) gives the value back.
//!
//! Wrapper: Command ID u32 | RESERVED u16 | Command Value u16 | Length u16 | Payload | Checksum.
//! Most vectors use the `none` checksum (trailing `0000`); a few use `xor8` (one byte, the XOR
//! of every header and payload byte, worked out in a comment) and `crc16` (CRC-16/CCITT-FALSE,
//! checked against an independent bit-by-bit implementation in `tests/common`).

use crate::common;
use common::{crc16_ccitt_false, hex};

use armjog::talos::frame::{Decoded, FrameHeader, HEADER_LEN};
use armjog::talos::message::{DecodeError, EncodeError};
use armjog::talos::name::NameError;
use armjog::talos::{Checksum, CommandValue, FrameCodec, Reply, Request, ReturnCode, TalosFrame};
use bytes::BytesMut;
use std::collections::BTreeSet;
use tokio_util::codec::Decoder;

/// Decodes exactly one frame from `bytes`, asserting nothing is left over.
fn decode_one(bytes: &[u8], checksum: Checksum) -> TalosFrame {
    let mut codec = FrameCodec::new(checksum);
    let mut buf = BytesMut::from(bytes);
    let item = codec.decode(&mut buf).expect("decode never errors");
    let frame = match item {
        Some(Decoded::TalosFrame(frame)) => frame,
        other => panic!("expected one frame from {bytes:02X?}, got {other:?}"),
    };
    assert!(buf.is_empty(), "bytes left after the frame: {buf:02X?}");
    assert_eq!(codec.decode_eof(&mut buf).expect("eof"), None);
    frame
}

/// Splits a `none` frame into its fields without the stream decoder, which (rightly) refuses
/// to treat a header with a payload length the ICD does not allow as a frame when there is no
/// checksum to vouch for it. Used for payloads that the message layer must refuse.
fn raw_frame(bytes: &[u8]) -> TalosFrame {
    let be16 = |i: usize| u16::from_be_bytes([bytes[i], bytes[i + 1]]);
    let length = usize::from(be16(8));
    assert_eq!(
        bytes.len(),
        HEADER_LEN + length + 2,
        "length field of {bytes:02X?}"
    );
    TalosFrame {
        id: u32::from_be_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]),
        reserved: be16(4),
        command: be16(6),
        payload: bytes[HEADER_LEN..HEADER_LEN + length].to_vec(),
    }
}

fn name(s: &str) -> String {
    s.to_owned()
}

/// (request, command id, frame with the `none` checksum)
fn request_vectors() -> Vec<(Request, u32, &'static str)> {
    vec![
        (
            Request::Handshake { oid: Some(0x1234) },
            0x0000_0010,
            "00000010 0000 0000 0002 | 1234 | 0000",
        ),
        (
            // What deployed clients (talos-rit/commander) send: a handshake with no payload.
            Request::Handshake { oid: None },
            0x0000_0000,
            "00000000 0000 0000 0000 | 0000",
        ),
        (
            // delta_azimuth -10 = 0xFFFFFFF6; time 1000 ms = 0x3E8.
            Request::PolarPan {
                delta_azimuth: -10,
                delta_altitude: 5,
                delay_ms: 0,
                time_ms: 1000,
            },
            0x0000_0002,
            "00000002 0000 0001 0010 | FFFFFFF6 00000005 00000000 000003E8 | 0000",
        ),
        (
            Request::Home { delay_ms: 250 },
            0x0000_0004,
            "00000004 0000 0002 0004 | 000000FA | 0000",
        ),
        (
            // moving_altitude -1 is the INT8 0xFF.
            Request::PolarPanStart {
                moving_azimuth: 1,
                moving_altitude: -1,
            },
            0x0000_0006,
            "00000006 0000 0003 0002 | 01 FF | 0000",
        ),
        (
            Request::PolarPanStop,
            0x0000_0008,
            "00000008 0000 0004 0000 | 0000",
        ),
        (
            // -1500 = !0x5DC + 1 = 0xFFFFFA24; 250 = 0xFA; 100 = 0x64; 2000 = 0x7D0.
            Request::CartesianMove {
                delta_x: -1500,
                delta_y: 0,
                delta_z: 250,
                delay_ms: 100,
                time_ms: 2000,
            },
            0x0000_000A,
            "0000000A 0000 0005 0014 | FFFFFA24 00000000 000000FA 00000064 000007D0 | 0000",
        ),
        (
            Request::CartesianMoveStart {
                moving_x: 0,
                moving_y: 1,
                moving_z: -1,
            },
            0x0000_000C,
            "0000000C 0000 0006 0003 | 00 01 FF | 0000",
        ),
        (
            Request::CartesianMoveStop,
            0x0000_000E,
            "0000000E 0000 0007 0000 | 0000",
        ),
        (
            // subcommand 0x0102, reserved u32 0, then 4 hardware bytes: length 2 + 4 + 4 = 10.
            Request::HardwareOperation {
                subcommand: 0x0102,
                reserved: 0,
                payload: vec![0xDE, 0xAD, 0xBE, 0xEF],
            },
            0x0000_0010,
            "00000010 0000 0008 000A | 0102 00000000 DEADBEEF | 0000",
        ),
        (
            Request::GetSpeed,
            0x0000_0012,
            "00000012 0000 0009 0000 | 0000",
        ),
        (
            Request::SetSpeed { speed: 50 },
            0x0000_0014,
            "00000014 0000 000A 0001 | 32 | 0000",
        ),
        (
            // "pick" = 70 69 63 6B, anchor 01, "home" = 68 6F 6D 65: length 1+4+1+1+4 = 11.
            Request::SavePosition {
                name: name("pick"),
                anchor: true,
                parent: name("home"),
            },
            0x0000_0016,
            "00000016 0000 000B 000B | 04 7069636B 01 04 686F6D65 | 0000",
        ),
        (
            // "old" = 6F 6C 64.
            Request::DeletePosition { name: name("old") },
            0x0000_0018,
            "00000018 0000 000C 0004 | 03 6F6C64 | 0000",
        ),
        (
            Request::GoToPosition { name: name("home") },
            0x0000_001A,
            "0000001A 0000 000D 0005 | 04 686F6D65 | 0000",
        ),
        (
            // "p1" = 70 31; -900 = !0x384 + 1 = 0xFFFFFC7C; 450 = 0x1C2; 1200 = 0x4B0.
            Request::SetPolarPosition {
                name: name("p1"),
                delta: -900,
                azimuth: 450,
                radius: 1200,
            },
            0x0000_001C,
            "0000001C 0000 000E 000F | 02 7031 FFFFFC7C 000001C2 000004B0 | 0000",
        ),
        (
            Request::GetPolarPosition { name: name("p1") },
            0x0000_001E,
            "0000001E 0000 000F 0003 | 02 7031 | 0000",
        ),
        (
            // "c 2" = 63 20 32 (an inner space is allowed); i32::MIN = 0x80000000.
            Request::SetCartesianPosition {
                name: name("c 2"),
                x: 1,
                y: -1,
                z: i32::MIN,
            },
            0x0000_0020,
            "00000020 0000 0010 0010 | 03 632032 00000001 FFFFFFFF 80000000 | 0000",
        ),
        (
            Request::GetCartesianPosition { name: name("c 2") },
            0xFFFF_FFFE,
            "FFFFFFFE 0000 0011 0004 | 03 632032 | 0000",
        ),
    ]
}

/// (reply, id of the request it answers, frame with the `none` checksum). Reply ids are id | 1.
fn reply_vectors() -> Vec<(Reply, u32, &'static str)> {
    vec![
        (
            Reply::Handshake {
                return_code: ReturnCode::OK,
                major_version: 1,
                minor_version: 2,
            },
            0x0000_0010,
            "00000011 0000 8000 0004 | 0000 01 02 | 0000",
        ),
        (
            Reply::PolarPan {
                return_code: ReturnCode::OK,
            },
            0x0000_0002,
            "00000003 0000 8001 0002 | 0000 | 0000",
        ),
        (
            Reply::Home {
                return_code: ReturnCode::BUSY,
            },
            0x0000_0004,
            "00000005 0000 8002 0002 | 0007 | 0000",
        ),
        (
            Reply::PolarPanStart {
                return_code: ReturnCode::OK,
            },
            0x0000_0006,
            "00000007 0000 8003 0002 | 0000 | 0000",
        ),
        (
            Reply::PolarPanStop {
                return_code: ReturnCode::OK,
            },
            0x0000_0008,
            "00000009 0000 8004 0002 | 0000 | 0000",
        ),
        (
            Reply::CartesianMove {
                return_code: ReturnCode::UNREACHABLE,
            },
            0x0000_000A,
            "0000000B 0000 8005 0002 | 0005 | 0000",
        ),
        (
            Reply::CartesianMoveStart {
                return_code: ReturnCode::ARM_FAULT,
            },
            0x0000_000C,
            "0000000D 0000 8006 0002 | 0006 | 0000",
        ),
        (
            Reply::CartesianMoveStop {
                return_code: ReturnCode::OK,
            },
            0x0000_000E,
            "0000000F 0000 8007 0002 | 0000 | 0000",
        ),
        (
            // return code, subcommand 0x0102, then 3 hardware bytes: length 2 + 2 + 3 = 7.
            Reply::HardwareOperation {
                return_code: ReturnCode::OK,
                subcommand: 0x0102,
                payload: vec![0x01, 0x02, 0x03],
            },
            0x0000_0010,
            "00000011 0000 8008 0007 | 0000 0102 010203 | 0000",
        ),
        (
            // speed 75 = 0x4B.
            Reply::GetSpeed {
                return_code: ReturnCode::OK,
                speed: 75,
            },
            0x0000_0012,
            "00000013 0000 8009 0003 | 0000 4B | 0000",
        ),
        (
            Reply::SetSpeed {
                return_code: ReturnCode::OUT_OF_RANGE,
            },
            0x0000_0014,
            "00000015 0000 800A 0002 | 0008 | 0000",
        ),
        (
            Reply::SavePosition {
                return_code: ReturnCode::INVALID_PARENT,
            },
            0x0000_0016,
            "00000017 0000 800B 0002 | 000A | 0000",
        ),
        (
            Reply::DeletePosition {
                return_code: ReturnCode::UNKNOWN_POSITION,
            },
            0x0000_0018,
            "00000019 0000 800C 0002 | 0004 | 0000",
        ),
        (
            Reply::GoToPosition {
                return_code: ReturnCode::OK,
            },
            0x0000_001A,
            "0000001B 0000 800D 0002 | 0000 | 0000",
        ),
        (
            Reply::SetPolarPosition {
                return_code: ReturnCode::OK,
            },
            0x0000_001C,
            "0000001D 0000 800E 0002 | 0000 | 0000",
        ),
        (
            // -900 = 0xFFFFFC7C; 450 = 0x1C2; 1200 = 0x4B0: length 2 + 12 = 14.
            Reply::GetPolarPosition {
                return_code: ReturnCode::OK,
                delta: -900,
                azimuth: 450,
                radius: 1200,
            },
            0x0000_001E,
            "0000001F 0000 800F 000E | 0000 FFFFFC7C 000001C2 000004B0 | 0000",
        ),
        (
            Reply::SetCartesianPosition {
                return_code: ReturnCode(0x1234),
            },
            0x0000_0020,
            "00000021 0000 8010 0002 | 1234 | 0000",
        ),
        (
            // The request id's low bit is already set here: the reply keeps it (id | 1).
            Reply::GetCartesianPosition {
                return_code: ReturnCode::OK,
                x: -1,
                y: 0,
                z: i32::MAX,
            },
            0xFFFF_FFFF,
            "FFFFFFFF 0000 8011 000E | 0000 FFFFFFFF 00000000 7FFFFFFF | 0000",
        ),
    ]
}

#[test]
fn the_vectors_cover_every_icd_command() {
    let all: BTreeSet<CommandValue> = CommandValue::ALL.into_iter().collect();
    let requests: BTreeSet<CommandValue> = request_vectors()
        .iter()
        .map(|(r, _, _)| r.command())
        .collect();
    let replies: BTreeSet<CommandValue> = reply_vectors()
        .iter()
        .map(|(r, _, _)| r.command())
        .collect();
    assert_eq!(all.len(), 18);
    assert_eq!(requests, all);
    assert_eq!(replies, all);
    // Handshake twice: with the ICD's OID and empty, as deployed clients send it.
    assert_eq!(request_vectors().len(), 19);
    assert_eq!(reply_vectors().len(), 18);
}

#[test]
fn every_request_encodes_to_its_vector() {
    for (request, id, text) in request_vectors() {
        let bytes = hex(text);
        let frame = request.to_frame(id).expect("valid request");
        assert_eq!(frame.id, id, "{request:?}");
        assert_eq!(frame.reserved, 0, "{request:?}");
        assert!(!frame.is_reply(), "{request:?}");
        assert_eq!(
            frame.to_bytes(Checksum::None).expect("fits"),
            bytes,
            "{request:?} => {text}"
        );
        assert_eq!(frame.encoded_len(Checksum::None), bytes.len());
    }
}

#[test]
fn every_request_vector_decodes_to_its_value() {
    for (request, id, text) in request_vectors() {
        let bytes = hex(text);
        let frame = decode_one(&bytes, Checksum::None);
        assert_eq!(frame.id, id, "{text}");
        assert_eq!(frame.command, request.command().request_value(), "{text}");
        assert_eq!(frame.payload, bytes[HEADER_LEN..bytes.len() - 2], "{text}");
        assert_eq!(frame.command_value(), Some(request.command()));
        assert_eq!(Request::from_frame(&frame), Ok(request.clone()), "{text}");
        // A request frame is not a reply.
        assert_eq!(
            Reply::from_frame(&frame),
            Err(DecodeError::UnknownCommand(frame.command)),
            "{text}"
        );
    }
}

#[test]
fn every_reply_encodes_to_its_vector() {
    for (reply, request_id, text) in reply_vectors() {
        let bytes = hex(text);
        let frame = reply.to_frame(request_id).expect("valid reply");
        assert_eq!(frame.id, request_id | 1, "{reply:?}");
        assert!(frame.is_reply(), "{reply:?}");
        assert_eq!(
            frame.to_bytes(Checksum::None).expect("fits"),
            bytes,
            "{reply:?} => {text}"
        );
    }
}

#[test]
fn every_reply_vector_decodes_to_its_value() {
    for (reply, request_id, text) in reply_vectors() {
        let bytes = hex(text);
        let frame = decode_one(&bytes, Checksum::None);
        assert_eq!(frame.id, request_id | 1, "{text}");
        assert_eq!(frame.id & 1, 1, "{text}");
        assert_eq!(frame.command, 0x8000 | reply.command().request_value());
        assert_eq!(frame.command_value(), Some(reply.command()));
        assert_eq!(Reply::from_frame(&frame), Ok(reply.clone()), "{text}");
        assert_eq!(
            Request::from_frame(&frame),
            Err(DecodeError::UnknownCommand(frame.command)),
            "{text}"
        );
    }
}

#[test]
fn return_codes_read_from_the_vectors() {
    let codes: Vec<u16> = reply_vectors()
        .iter()
        .map(|(r, _, _)| r.return_code().0)
        .collect();
    assert_eq!(
        codes,
        [0, 0, 7, 0, 0, 5, 6, 0, 0, 0, 8, 0x0A, 4, 0, 0, 0, 0x1234, 0]
    );
}

#[test]
fn a_handshake_takes_an_oid_or_nothing_but_not_one_byte() {
    // talos-rit/commander's handshake with its 1-byte XOR checksum (every byte is 0, so is the
    // XOR).
    let commander = hex("00000000 0000 0000 0000 | 00");
    let frame = decode_one(&commander, Checksum::Xor8);
    assert_eq!(
        Request::from_frame(&frame),
        Ok(Request::Handshake { oid: None })
    );
    // The client side keeps the ICD's 2-byte OID.
    assert_eq!(
        Request::Handshake { oid: Some(7) }
            .to_frame(0)
            .unwrap()
            .to_bytes(Checksum::Xor8)
            .unwrap(),
        hex("00000000 0000 0000 0002 | 0007 | 05") // 02 ^ 07 = 05
    );
    let one_byte = raw_frame(&hex("00000004 0000 0000 0001 | 07 | 0000"));
    assert!(matches!(
        Request::from_frame(&one_byte),
        Err(DecodeError::Truncated { .. })
    ));
}

#[test]
fn save_position_with_an_empty_parent_has_a_zero_length_byte() {
    // name "pick", anchor 00, parent length 00 and no parent bytes: length 1+4+1+1 = 7.
    let request = Request::SavePosition {
        name: name("pick"),
        anchor: false,
        parent: String::new(),
    };
    let bytes = hex("00000040 0000 000B 0007 | 04 7069636B 00 00 | 0000");
    assert_eq!(
        request
            .to_frame(0x40)
            .unwrap()
            .to_bytes(Checksum::None)
            .unwrap(),
        bytes
    );
    assert_eq!(
        Request::from_frame(&decode_one(&bytes, Checksum::None)),
        Ok(request)
    );
}

#[test]
fn save_position_with_anchor_and_an_empty_parent_still_round_trips() {
    // The ICD says the operator ignores the anchor when the parent is empty; the wire keeps it.
    let request = Request::SavePosition {
        name: name("a"),
        anchor: true,
        parent: String::new(),
    };
    let bytes = hex("00000042 0000 000B 0004 | 01 61 01 00 | 0000");
    assert_eq!(
        request
            .to_frame(0x42)
            .unwrap()
            .to_bytes(Checksum::None)
            .unwrap(),
        bytes
    );
    assert_eq!(
        Request::from_frame(&decode_one(&bytes, Checksum::None)),
        Ok(request)
    );
}

#[test]
fn a_255_byte_name_is_the_longest_and_its_length_byte_is_ff() {
    let long = "n".repeat(255);
    let request = Request::GoToPosition { name: long.clone() };
    let mut expected = hex("00000044 0000 000D 0100 | FF");
    expected.extend(std::iter::repeat_n(0x6E, 255));
    expected.extend([0x00, 0x00]);
    assert_eq!(
        request
            .to_frame(0x44)
            .unwrap()
            .to_bytes(Checksum::None)
            .unwrap(),
        expected
    );
    assert_eq!(
        Request::from_frame(&decode_one(&expected, Checksum::None)),
        Ok(Request::GoToPosition { name: long })
    );
}

#[test]
fn hardware_operation_keeps_its_reserved_word_and_an_empty_payload() {
    let request = Request::HardwareOperation {
        subcommand: 0xFFFF,
        reserved: 0xA5A5_5A5A,
        payload: vec![],
    };
    let bytes = hex("00000046 0000 0008 0006 | FFFF A5A55A5A | 0000");
    assert_eq!(
        request
            .to_frame(0x46)
            .unwrap()
            .to_bytes(Checksum::None)
            .unwrap(),
        bytes
    );
    assert_eq!(
        Request::from_frame(&decode_one(&bytes, Checksum::None)),
        Ok(request)
    );
}

#[test]
fn the_wrapper_reserved_field_is_kept_by_the_frame_and_ignored_by_the_message() {
    let bytes = hex("00000048 ABCD 0009 0000 | 0000");
    let frame = decode_one(&bytes, Checksum::None);
    assert_eq!(
        frame,
        TalosFrame {
            id: 0x48,
            reserved: 0xABCD,
            command: 0x0009,
            payload: vec![],
        }
    );
    assert_eq!(Request::from_frame(&frame), Ok(Request::GetSpeed));
    assert_eq!(frame.to_bytes(Checksum::None).unwrap(), bytes);
}

#[test]
fn the_none_checksum_field_is_never_checked() {
    // armjog writes 00 00, but early clients' field is not verified: anything is accepted.
    let bytes = hex("00000012 0000 0009 0000 | BEEF");
    assert_eq!(
        Request::from_frame(&decode_one(&bytes, Checksum::None)),
        Ok(Request::GetSpeed)
    );
}

// ---- error replies ----

#[test]
fn an_error_reply_is_sent_with_its_full_layout_zeroed() {
    let reply = Reply::error(
        CommandValue::GetCartesianPosition,
        ReturnCode::UNKNOWN_POSITION,
    );
    assert_eq!(
        reply,
        Reply::GetCartesianPosition {
            return_code: ReturnCode::UNKNOWN_POSITION,
            x: 0,
            y: 0,
            z: 0,
        }
    );
    let bytes = hex("00000051 0000 8011 000E | 0004 00000000 00000000 00000000 | 0000");
    assert_eq!(
        reply
            .to_frame(0x50)
            .unwrap()
            .to_bytes(Checksum::None)
            .unwrap(),
        bytes
    );
    assert_eq!(
        Reply::from_frame(&decode_one(&bytes, Checksum::None)),
        Ok(reply)
    );

    let handshake = Reply::error(CommandValue::Handshake, ReturnCode::INTERNAL_ERROR);
    assert_eq!(
        handshake
            .to_frame(0x52)
            .unwrap()
            .to_bytes(Checksum::None)
            .unwrap(),
        hex("00000053 0000 8000 0004 | 00FF 00 00 | 0000")
    );
    let hw = Reply::error(
        CommandValue::ExecuteHardwareOperation,
        ReturnCode::UNSUPPORTED_SUBCOMMAND,
    );
    assert_eq!(
        hw.to_frame(0x54).unwrap().to_bytes(Checksum::None).unwrap(),
        hex("00000055 0000 8008 0004 | 0009 0000 | 0000")
    );
}

#[test]
fn a_bare_return_code_decodes_as_an_error_reply_with_zero_fields() {
    let cases = [
        (
            "00000061 0000 8000 0002 | 0001 | 0000",
            Reply::Handshake {
                return_code: ReturnCode::UNKNOWN_COMMAND,
                major_version: 0,
                minor_version: 0,
            },
        ),
        (
            "00000063 0000 8008 0002 | 0009 | 0000",
            Reply::HardwareOperation {
                return_code: ReturnCode::UNSUPPORTED_SUBCOMMAND,
                subcommand: 0,
                payload: vec![],
            },
        ),
        (
            "00000065 0000 8009 0002 | 0006 | 0000",
            Reply::GetSpeed {
                return_code: ReturnCode::ARM_FAULT,
                speed: 0,
            },
        ),
        (
            "00000067 0000 800F 0002 | 0004 | 0000",
            Reply::GetPolarPosition {
                return_code: ReturnCode::UNKNOWN_POSITION,
                delta: 0,
                azimuth: 0,
                radius: 0,
            },
        ),
        (
            "00000069 0000 8011 0002 | 0004 | 0000",
            Reply::GetCartesianPosition {
                return_code: ReturnCode::UNKNOWN_POSITION,
                x: 0,
                y: 0,
                z: 0,
            },
        ),
    ];
    for (text, expected) in cases {
        let frame = decode_one(&hex(text), Checksum::None);
        assert_eq!(Reply::from_frame(&frame), Ok(expected.clone()), "{text}");
        assert_eq!(
            Reply::error(expected.command(), expected.return_code()),
            expected
        );
    }
}

#[test]
fn a_bare_success_code_is_not_a_complete_reply() {
    let cases = [
        (
            "00000071 0000 8000 0002 | 0000 | 0000",
            CommandValue::Handshake,
            "major_version",
        ),
        (
            "00000073 0000 8009 0002 | 0000 | 0000",
            CommandValue::GetSpeed,
            "speed",
        ),
        (
            "00000075 0000 800F 0002 | 0000 | 0000",
            CommandValue::GetPolarPosition,
            "delta",
        ),
        (
            "00000077 0000 8011 0002 | 0000 | 0000",
            CommandValue::GetCartesianPosition,
            "x",
        ),
        (
            "00000079 0000 8008 0002 | 0000 | 0000",
            CommandValue::ExecuteHardwareOperation,
            "subcommand",
        ),
    ];
    for (text, command, field) in cases {
        let frame = decode_one(&hex(text), Checksum::None);
        assert_eq!(
            Reply::from_frame(&frame),
            Err(DecodeError::Truncated { command, field }),
            "{text}"
        );
    }
}

#[test]
fn a_partial_error_reply_is_truncated_not_zero_filled() {
    // Return code 4 and only the first of three INT32s.
    let frame = raw_frame(&hex("00000081 0000 800F 0006 | 0004 00000001 | 0000"));
    assert_eq!(
        Reply::from_frame(&frame),
        Err(DecodeError::Truncated {
            command: CommandValue::GetPolarPosition,
            field: "azimuth",
        })
    );
}

#[test]
fn an_empty_reply_payload_lacks_its_return_code() {
    let frame = raw_frame(&hex("00000083 0000 8001 0000 | 0000"));
    assert_eq!(
        Reply::from_frame(&frame),
        Err(DecodeError::Truncated {
            command: CommandValue::PolarPanDiscrete,
            field: "return_code",
        })
    );
}

// ---- xor8: one checksum byte ----

/// (frame, the request it holds, or the reply it holds and the request id it answers)
type XorCase = (&'static str, Option<Request>, Option<(Reply, u32)>);

#[test]
fn xor8_vectors() {
    let cases: [XorCase; 4] = [
        (
            // 00^00^00^06 ^ 00^00 ^ 00^03 ^ 00^02 ^ 01^FF
            //   = 06 ^ 03 ^ 02 ^ 01 ^ FF = 05 ^ 02 = 07 ^ 01 = 06 ^ FF = F9
            "00000006 0000 0003 0002 | 01 FF | F9",
            Some(Request::PolarPanStart {
                moving_azimuth: 1,
                moving_altitude: -1,
            }),
            None,
        ),
        (
            // 12 ^ 09 = 1B (every other byte is zero)
            "00000012 0000 0009 0000 | 1B",
            Some(Request::GetSpeed),
            None,
        ),
        (
            // header: 16 ^ 0B ^ 0B = 16
            // payload: 04^70=74, ^69=1D, ^63=7E, ^6B=15, ^01=14, ^04=10, ^68=78, ^6F=17,
            //          ^6D=7A, ^65=1F
            // total: 16 ^ 1F = 09
            "00000016 0000 000B 000B | 04 7069636B 01 04 686F6D65 | 09",
            Some(Request::SavePosition {
                name: name("pick"),
                anchor: true,
                parent: name("home"),
            }),
            None,
        ),
        (
            // 11 ^ 80 ^ 04 ^ 01 ^ 02 = 91 ^ 04 = 95 ^ 01 = 94 ^ 02 = 96
            "00000011 0000 8000 0004 | 0000 01 02 | 96",
            None,
            Some((
                Reply::Handshake {
                    return_code: ReturnCode::OK,
                    major_version: 1,
                    minor_version: 2,
                },
                0x10,
            )),
        ),
    ];
    for (text, request, reply) in cases {
        let bytes = hex(text);
        let frame = decode_one(&bytes, Checksum::Xor8);
        if let Some(request) = request {
            let id = frame.id;
            assert_eq!(
                request
                    .to_frame(id)
                    .unwrap()
                    .to_bytes(Checksum::Xor8)
                    .unwrap(),
                bytes,
                "{text}"
            );
            assert_eq!(Request::from_frame(&frame), Ok(request), "{text}");
        }
        if let Some((reply, request_id)) = reply {
            assert_eq!(
                reply
                    .to_frame(request_id)
                    .unwrap()
                    .to_bytes(Checksum::Xor8)
                    .unwrap(),
                bytes,
                "{text}"
            );
            assert_eq!(Reply::from_frame(&frame), Ok(reply), "{text}");
        }
        // The same frame with its checksum byte changed is refused.
        let mut bad = bytes.clone();
        *bad.last_mut().unwrap() ^= 0x01;
        let mut codec = FrameCodec::new(Checksum::Xor8);
        let mut buf = BytesMut::from(&bad[..]);
        assert!(
            matches!(codec.decode(&mut buf).unwrap(), Some(Decoded::Rejected(_))),
            "{text}"
        );
    }
}

// ---- crc16: CRC-16/CCITT-FALSE ----

#[test]
fn the_reference_crc_is_ccitt_false() {
    assert_eq!(crc16_ccitt_false(b"123456789"), 0x29B1);
    assert_eq!(crc16_ccitt_false(b""), 0xFFFF);
    // The library agrees on the check value too.
    assert_eq!(Checksum::Crc16.compute(b"123456789"), 0x29B1);
}

#[test]
fn crc16_vectors() {
    // The trailing CRC of each vector was computed outside this crate and is re-checked below
    // with the bit-by-bit reference.
    let requests = [
        (
            "0000000C 0000 0006 0003 | 00 01 FF | F48E",
            Request::CartesianMoveStart {
                moving_x: 0,
                moving_y: 1,
                moving_z: -1,
            },
        ),
        (
            "00000010 0000 0000 0002 | 1234 | AAA1",
            Request::Handshake { oid: Some(0x1234) },
        ),
        ("00000012 0000 0009 0000 | 2830", Request::GetSpeed),
    ];
    for (text, request) in requests {
        let bytes = hex(text);
        let (covered, field) = bytes.split_at(bytes.len() - 2);
        assert_eq!(
            crc16_ccitt_false(covered).to_be_bytes(),
            field,
            "reference CRC of {text}"
        );
        let frame = decode_one(&bytes, Checksum::Crc16);
        assert_eq!(
            request
                .to_frame(frame.id)
                .unwrap()
                .to_bytes(Checksum::Crc16)
                .unwrap(),
            bytes,
            "{text}"
        );
        assert_eq!(Request::from_frame(&frame), Ok(request), "{text}");
    }

    let replies = [
        (
            "00000013 0000 8011 000E | 0000 FFFFFFFF 00000000 7FFFFFFF | 3699",
            0x12,
            Reply::GetCartesianPosition {
                return_code: ReturnCode::OK,
                x: -1,
                y: 0,
                z: i32::MAX,
            },
        ),
        (
            "00000019 0000 800C 0002 | 0004 | 6434",
            0x18,
            Reply::DeletePosition {
                return_code: ReturnCode::UNKNOWN_POSITION,
            },
        ),
    ];
    for (text, request_id, reply) in replies {
        let bytes = hex(text);
        let (covered, field) = bytes.split_at(bytes.len() - 2);
        assert_eq!(crc16_ccitt_false(covered).to_be_bytes(), field, "{text}");
        let frame = decode_one(&bytes, Checksum::Crc16);
        assert_eq!(
            reply
                .to_frame(request_id)
                .unwrap()
                .to_bytes(Checksum::Crc16)
                .unwrap(),
            bytes,
            "{text}"
        );
        assert_eq!(Reply::from_frame(&frame), Ok(reply), "{text}");
    }
}

#[test]
fn crc16_of_every_request_and_reply_vector_matches_the_reference() {
    // The `none` vectors re-sealed with the reference CRC must be exactly what crc16 encodes.
    for (request, id, text) in request_vectors() {
        let mut bytes = hex(text);
        bytes.truncate(bytes.len() - 2);
        let crc = crc16_ccitt_false(&bytes);
        bytes.extend(crc.to_be_bytes());
        let frame = request.to_frame(id).unwrap();
        assert_eq!(frame.to_bytes(Checksum::Crc16).unwrap(), bytes, "{text}");
        assert_eq!(
            Request::from_frame(&decode_one(&bytes, Checksum::Crc16)),
            Ok(request)
        );
    }
    for (reply, request_id, text) in reply_vectors() {
        let mut bytes = hex(text);
        bytes.truncate(bytes.len() - 2);
        let crc = crc16_ccitt_false(&bytes);
        bytes.extend(crc.to_be_bytes());
        let frame = reply.to_frame(request_id).unwrap();
        assert_eq!(frame.to_bytes(Checksum::Crc16).unwrap(), bytes, "{text}");
        assert_eq!(
            Reply::from_frame(&decode_one(&bytes, Checksum::Crc16)),
            Ok(reply)
        );
    }
}

#[test]
fn a_crc16_frame_with_a_flipped_bit_is_rejected_with_its_header() {
    let mut bytes = hex("0000000C 0000 0006 0003 | 00 01 FF | F48E");
    bytes[11] ^= 0x04; // moving_y 01 -> 05
    let mut codec = FrameCodec::new(Checksum::Crc16);
    let mut buf = BytesMut::from(&bytes[..]);
    let Some(Decoded::Rejected(rejection)) = codec.decode(&mut buf).unwrap() else {
        panic!("a corrupt frame must be rejected");
    };
    let expected = crc16_ccitt_false(&bytes[..bytes.len() - 2]);
    assert_eq!(
        rejection.reason,
        armjog::talos::RejectReason::BadChecksum {
            expected,
            found: 0xF48E,
        }
    );
    assert_eq!(
        rejection.header,
        Some(FrameHeader {
            id: 0x0C,
            command: 0x0006,
            length: 3,
        })
    );
}

// ---- encode errors name the field ----

#[test]
fn a_direction_outside_minus_one_to_one_is_refused_with_its_field() {
    let err = Request::CartesianMoveStart {
        moving_x: 0,
        moving_y: 2,
        moving_z: 0,
    }
    .to_frame(2)
    .unwrap_err();
    assert_eq!(
        err,
        EncodeError::Direction {
            field: "moving_y",
            value: 2,
        }
    );
    assert!(err.to_string().contains("moving_y"), "{err}");

    let err = Request::PolarPanStart {
        moving_azimuth: 1,
        moving_altitude: i8::MIN,
    }
    .to_frame(2)
    .unwrap_err();
    assert_eq!(
        err,
        EncodeError::Direction {
            field: "moving_altitude",
            value: -128,
        }
    );
    assert!(matches!(
        Request::CartesianMoveStart {
            moving_x: -2,
            moving_y: 0,
            moving_z: 0
        }
        .to_frame(2),
        Err(EncodeError::Direction {
            field: "moving_x",
            value: -2
        })
    ));
    assert!(matches!(
        Request::CartesianMoveStart {
            moving_x: 0,
            moving_y: 0,
            moving_z: 3
        }
        .to_frame(2),
        Err(EncodeError::Direction {
            field: "moving_z",
            value: 3
        })
    ));
}

#[test]
fn bad_names_are_refused_with_their_field() {
    let cases = [
        (
            Request::GoToPosition {
                name: String::new(),
            },
            "name",
            NameError::Empty,
        ),
        (
            Request::DeletePosition {
                name: "x".repeat(256),
            },
            "name",
            NameError::TooLong(256),
        ),
        (
            Request::GetPolarPosition { name: name("a\nb") },
            "name",
            NameError::BadByte {
                byte: 0x0A,
                offset: 1,
            },
        ),
        (
            Request::SetCartesianPosition {
                name: name("tab\there"),
                x: 0,
                y: 0,
                z: 0,
            },
            "name",
            NameError::BadByte {
                byte: 0x09,
                offset: 3,
            },
        ),
        (
            Request::SavePosition {
                name: String::new(),
                anchor: false,
                parent: String::new(),
            },
            "name",
            NameError::Empty,
        ),
        (
            Request::SavePosition {
                name: name("child"),
                anchor: true,
                parent: name(" parent"),
            },
            "parent",
            NameError::OuterSpace,
        ),
        (
            Request::SavePosition {
                name: name("child"),
                anchor: true,
                parent: "p".repeat(256),
            },
            "parent",
            NameError::TooLong(256),
        ),
        (
            Request::SavePosition {
                name: name("child"),
                anchor: false,
                parent: name("par\u{7f}"),
            },
            "parent",
            NameError::BadByte {
                byte: 0x7F,
                offset: 3,
            },
        ),
    ];
    for (request, field, reason) in cases {
        let err = request.to_frame(4).unwrap_err();
        assert_eq!(
            err,
            EncodeError::Name {
                field,
                reason: reason.clone()
            },
            "{request:?}"
        );
        assert!(err.to_string().starts_with(field), "{err}");
    }
}

// ---- decode errors ----

#[test]
fn decoding_refuses_payloads_that_break_the_icd() {
    use CommandValue as C;
    let cases = [
        (
            "00000002 0000 0003 0002 | 02 00 | 0000",
            DecodeError::Direction {
                command: C::PolarPanStart,
                field: "moving_azimuth",
                value: 2,
            },
        ),
        (
            "00000002 0000 0006 0003 | 00 00 FE | 0000",
            DecodeError::Direction {
                command: C::CartesianMoveStart,
                field: "moving_z",
                value: -2,
            },
        ),
        (
            "00000002 0000 000B 0004 | 01 61 02 00 | 0000",
            DecodeError::Boolean {
                command: C::SavePosition,
                field: "anchor",
                value: 2,
            },
        ),
        (
            "00000002 0000 000D 0001 | 00 | 0000",
            DecodeError::Name {
                command: C::GoToPosition,
                field: "name",
                reason: NameError::Empty,
            },
        ),
        (
            "00000002 0000 000D 0003 | 05 6162 | 0000",
            DecodeError::Truncated {
                command: C::GoToPosition,
                field: "name",
            },
        ),
        (
            "00000002 0000 000B 0005 | 01 61 00 01 20 | 0000",
            DecodeError::Name {
                command: C::SavePosition,
                field: "parent",
                reason: NameError::OuterSpace,
            },
        ),
        (
            "00000002 0000 0004 0001 | 00 | 0000",
            DecodeError::TrailingBytes {
                command: C::PolarPanStop,
                count: 1,
            },
        ),
        (
            "00000002 0000 0002 0003 | 000000 | 0000",
            DecodeError::Truncated {
                command: C::Home,
                field: "delay_ms",
            },
        ),
        (
            "00000002 0000 0008 0005 | 0001 000000 | 0000",
            DecodeError::Truncated {
                command: C::ExecuteHardwareOperation,
                field: "reserved",
            },
        ),
    ];
    for (text, expected) in cases {
        let frame = raw_frame(&hex(text));
        assert_eq!(Request::from_frame(&frame), Err(expected), "{text}");
    }
    // An unknown command value reaches from_frame only from a synced crc16/xor8 stream.
    let frame = decode_one(&hex("00000002 0000 0012 0000 | ACD9"), Checksum::Crc16);
    assert_eq!(
        Request::from_frame(&frame),
        Err(DecodeError::UnknownCommand(0x0012))
    );
}

#[test]
fn a_reply_frame_always_gets_an_odd_id() {
    let reply = Reply::GoToPosition {
        return_code: ReturnCode::OK,
    };
    assert_eq!(reply.to_frame(0).unwrap().id, 1);
    assert_eq!(reply.to_frame(54).unwrap().id, 55);
    assert_eq!(reply.to_frame(0xFFFF_FFFE).unwrap().id, 0xFFFF_FFFF);
}
