//! What each Talos request does to the arm (`Request::class`) and the stop set
//! (`stop_requests`), against the ICDs' own words.
//!
//! Every frame here was written by hand from `shared/icd/talos-api-icd.md` and
//! `docs/hardware-icd.md`, field by field (`|` separates the wrapper from the payload), none
//! produced by the code under test. The ICDs' stops are Polar Pan STOP (0x0004), Cartesian
//! Move STOP (0x0007) and Execute Hardware Operation (0x0008) with subcommand STOP_ALL_JOINTS
//! (0x0004), whose RESERVED field is "ignored on receipt".
//!
//! Wrapper: Command ID u32 | RESERVED u16 | Command Value u16 | Length u16 | Payload | Checksum
//! (the `none` checksum, two zero bytes, unless said otherwise).

use crate::common::hex;

use armjog::talos::frame::Decoded;
use armjog::talos::{Checksum, Dialect, FrameCodec, Request, RequestClass, stop_requests};
use bytes::BytesMut;
use tokio_util::codec::Decoder;

const STOP: RequestClass = RequestClass::Stop;
const STILL: RequestClass = RequestClass::Still;
/// A move the operator carries to its end: discrete pan and move, home, go-to.
const TO_END: RequestClass = RequestClass::Motion { runs_to_end: true };
/// Moves until stopped or no longer refreshed: continuous starts, joint commands.
const UNTIL_STOPPED: RequestClass = RequestClass::Motion { runs_to_end: false };

/// The request in one whole frame, through the stream decoder as a link reads it.
fn request(text: &str, checksum: Checksum) -> Request {
    let mut codec = FrameCodec::new(checksum);
    let mut buf = BytesMut::from(hex(text).as_slice());
    let frame = match codec.decode(&mut buf).expect("decode never errors") {
        Some(Decoded::TalosFrame(frame)) => frame,
        other => panic!("expected one frame from {text}, got {other:?}"),
    };
    assert!(buf.is_empty(), "bytes left after {text}");
    Request::from_frame(&frame).unwrap_or_else(|e| panic!("{text}: {e:?}"))
}

/// (frame, what the ICD says it does), one or more per ICD request.
fn classified() -> Vec<(&'static str, RequestClass)> {
    vec![
        // Handshake, OID 0x1234.
        ("00000010 0000 0000 0002 | 1234 | 0000", STILL),
        // Polar Pan (Discrete): azimuth -10, altitude 5, delay 0, time 1000 ms.
        (
            "00000012 0000 0001 0010 | FFFFFFF6 00000005 00000000 000003E8 | 0000",
            TO_END,
        ),
        // Home, delay 0.
        ("00000014 0000 0002 0004 | 00000000 | 0000", TO_END),
        // Polar Pan (Continuous START): azimuth 1, altitude 0.
        ("00000016 0000 0003 0002 | 01 00 | 0000", UNTIL_STOPPED),
        // ... and all-zero: still a start, the operator may be told to move.
        ("00000018 0000 0003 0002 | 00 00 | 0000", UNTIL_STOPPED),
        // Polar Pan (Continuous STOP): no body.
        ("0000001A 0000 0004 0000 | 0000", STOP),
        // Cartesian Move (Discrete): x 100, y 0, z -1, delay 0, time 500 ms.
        (
            "0000001C 0000 0005 0014 | 00000064 00000000 FFFFFFFF 00000000 000001F4 | 0000",
            TO_END,
        ),
        // Cartesian Move (Continuous START): x 0, y 0, z -1.
        ("0000001E 0000 0006 0003 | 00 00 FF | 0000", UNTIL_STOPPED),
        // Cartesian Move (Continuous STOP): no body.
        ("00000020 0000 0007 0000 | 0000", STOP),
        // Execute Hardware Operation: subcommand u16, RESERVED u32, hardware payload.
        // GET_ACTUATOR_FEEDBACK, joint selector 0 (all).
        ("00000022 0000 0008 0007 | 0001 00000000 00 | 0000", STILL),
        // GET_ARM_STATE, no body.
        ("00000024 0000 0008 0006 | 0003 00000000 | 0000", STILL),
        // STOP_ALL_JOINTS, no body.
        ("00000026 0000 0008 0006 | 0004 00000000 | 0000", STOP),
        // STOP_ALL_JOINTS with RESERVED set: "ignored on receipt", still a stop.
        ("00000028 0000 0008 0006 | 0004 A5A55A5A | 0000", STOP),
        // CLEAR_ALL_FAULTS, no body: "Moves nothing".
        ("0000002A 0000 0008 0006 | 0005 00000000 | 0000", STILL),
        // A subcommand this build does not know (0x0009): not known to be still.
        (
            "0000002C 0000 0008 0006 | 0009 00000000 | 0000",
            UNTIL_STOPPED,
        ),
        // Get Speed, no body.
        ("0000002E 0000 0009 0000 | 0000", STILL),
        // Set Speed 50.
        ("00000030 0000 000A 0001 | 32 | 0000", STILL),
        // Save Position "a", anchor false, no parent.
        ("00000032 0000 000B 0004 | 01 61 00 00 | 0000", STILL),
        // Delete Position "a".
        ("00000034 0000 000C 0002 | 01 61 | 0000", STILL),
        // Go to Position "a".
        ("00000036 0000 000D 0002 | 01 61 | 0000", TO_END),
        // Set Polar Position "a": delta 1, azimuth 2, radius 3.
        (
            "00000038 0000 000E 000E | 01 61 00000001 00000002 00000003 | 0000",
            STILL,
        ),
        // Get Polar Position "a".
        ("0000003A 0000 000F 0002 | 01 61 | 0000", STILL),
        // Set Cartesian Position "a": x 1, y 2, z 3.
        (
            "0000003C 0000 0010 000E | 01 61 00000001 00000002 00000003 | 0000",
            STILL,
        ),
        // Get Cartesian Position "a".
        ("0000003E 0000 0011 0002 | 01 61 | 0000", STILL),
    ]
}

#[test]
fn every_request_does_to_the_arm_what_the_icd_says() {
    for (text, class) in classified() {
        assert_eq!(request(text, Checksum::None).class(), class, "{text}");
    }
}

/// The hardware ICD's worked example: jog joint 2 at -2.5 deg/s (SEND_ACTUATOR_COMMAND), id
/// 42, CRC-16 0x0D73, copied from `docs/hardware-icd.md`.
#[test]
fn the_hardware_icds_joint_jog_moves_until_stopped() {
    let jog = "00 00 00 2A 00 00 00 08 00 1B 00 02 00 00 00 00 02 00 00 00 01 42 B4 00 00 \
               C0 20 00 00 00 00 00 00 00 00 00 00 0D 73";
    assert_eq!(request(jog, Checksum::Crc16).class(), UNTIL_STOPPED);
}

/// The stop set, as it goes out with ids 0x40, 0x42, 0x44: the three ICD stops, and each is
/// what the classification calls a stop; the ack dialect (commands 0x0000-0x0004) carries the
/// polar STOP only.
#[test]
fn the_stop_set_is_the_icds_three_stops_and_nothing_else() {
    let written = |dialect| -> Vec<Vec<u8>> {
        stop_requests(dialect)
            .iter()
            .zip([0x40, 0x42, 0x44])
            .map(|(request, id)| {
                assert_eq!(request.class(), STOP, "{request:?}");
                request
                    .to_frame(id)
                    .expect("frame")
                    .to_bytes(Checksum::None)
                    .expect("bytes")
            })
            .collect()
    };
    assert_eq!(
        written(Dialect::Icd),
        vec![
            hex("00000040 0000 0007 0000 | 0000"),
            hex("00000042 0000 0004 0000 | 0000"),
            hex("00000044 0000 0008 0006 | 0004 00000000 | 0000"),
        ]
    );
    assert_eq!(
        written(Dialect::Ack),
        vec![hex("00000040 0000 0004 0000 | 0000")]
    );
    // Every request the ICD calls a stop is in the set (RESERVED, ignored, aside).
    let icd_set = stop_requests(Dialect::Icd);
    for (text, class) in classified() {
        let request = request(text, Checksum::None);
        let reserved_set =
            matches!(&request, Request::HardwareOperation { reserved, .. } if *reserved != 0);
        if class == STOP && !reserved_set {
            assert!(
                icd_set.contains(&request),
                "{text} is a stop missing from the set"
            );
        }
    }
}
