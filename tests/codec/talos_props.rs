//! Round trips of every request and reply through the whole codec, for every checksum:
//! value -> to_frame -> to_bytes -> FrameCodec::decode -> from_frame -> the same value.

use armjog::talos::frame::{DEFAULT_MAX_PAYLOAD, Decoded, HEADER_LEN};
use armjog::talos::{Checksum, FrameCodec, Reply, Request, ReturnCode, TalosFrame};
use bytes::BytesMut;
use proptest::collection::vec;
use proptest::prelude::*;
use tokio_util::codec::Decoder;

const CASES: u32 = 256;

/// A valid position name: printable ASCII, 1..=255 bytes, no leading or trailing space.
fn position_name() -> impl Strategy<Value = String> {
    prop_oneof![
        3 => "[!-~]([ -~]{0,14}[!-~])?",
        1 => "[!-~]([ -~]{0,253}[!-~])?",
    ]
}

/// A parent: empty (the operator's default) or a valid name.
fn parent_name() -> impl Strategy<Value = String> {
    prop_oneof![Just(String::new()), position_name()]
}

fn direction() -> impl Strategy<Value = i8> {
    -1i8..=1
}

/// Largest hardware payload that still fits the decoder's default bound (6 bytes precede it).
const MAX_HW_REQUEST_BYTES: usize = DEFAULT_MAX_PAYLOAD - 6;
/// Return code and subcommand precede a reply's hardware bytes.
const MAX_HW_REPLY_BYTES: usize = DEFAULT_MAX_PAYLOAD - 4;

fn hw_bytes(max: usize) -> impl Strategy<Value = Vec<u8>> {
    prop_oneof![
        4 => vec(any::<u8>(), 0..=32),
        1 => vec(any::<u8>(), 0..=max),
    ]
}

fn request() -> impl Strategy<Value = Request> {
    prop_oneof![
        proptest::option::of(any::<u16>()).prop_map(|oid| Request::Handshake { oid }),
        (any::<i32>(), any::<i32>(), any::<u32>(), any::<u32>()).prop_map(
            |(delta_azimuth, delta_altitude, delay_ms, time_ms)| Request::PolarPan {
                delta_azimuth,
                delta_altitude,
                delay_ms,
                time_ms,
            }
        ),
        any::<u32>().prop_map(|delay_ms| Request::Home { delay_ms }),
        (direction(), direction()).prop_map(|(moving_azimuth, moving_altitude)| {
            Request::PolarPanStart {
                moving_azimuth,
                moving_altitude,
            }
        }),
        Just(Request::PolarPanStop),
        (
            any::<i32>(),
            any::<i32>(),
            any::<i32>(),
            any::<u32>(),
            any::<u32>()
        )
            .prop_map(|(delta_x, delta_y, delta_z, delay_ms, time_ms)| {
                Request::CartesianMove {
                    delta_x,
                    delta_y,
                    delta_z,
                    delay_ms,
                    time_ms,
                }
            }),
        (direction(), direction(), direction()).prop_map(|(moving_x, moving_y, moving_z)| {
            Request::CartesianMoveStart {
                moving_x,
                moving_y,
                moving_z,
            }
        }),
        Just(Request::CartesianMoveStop),
        (any::<u16>(), any::<u32>(), hw_bytes(MAX_HW_REQUEST_BYTES)).prop_map(
            |(subcommand, reserved, payload)| Request::HardwareOperation {
                subcommand,
                reserved,
                payload,
            }
        ),
        Just(Request::GetSpeed),
        any::<u8>().prop_map(|speed| Request::SetSpeed { speed }),
        (position_name(), any::<bool>(), parent_name()).prop_map(|(name, anchor, parent)| {
            Request::SavePosition {
                name,
                anchor,
                parent,
            }
        }),
        position_name().prop_map(|name| Request::DeletePosition { name }),
        position_name().prop_map(|name| Request::GoToPosition { name }),
        (position_name(), any::<i32>(), any::<i32>(), any::<i32>()).prop_map(
            |(name, delta, azimuth, radius)| Request::SetPolarPosition {
                name,
                delta,
                azimuth,
                radius,
            }
        ),
        position_name().prop_map(|name| Request::GetPolarPosition { name }),
        (position_name(), any::<i32>(), any::<i32>(), any::<i32>())
            .prop_map(|(name, x, y, z)| Request::SetCartesianPosition { name, x, y, z }),
        position_name().prop_map(|name| Request::GetCartesianPosition { name }),
    ]
}

fn return_code() -> impl Strategy<Value = ReturnCode> {
    prop_oneof![
        2 => Just(ReturnCode::OK),
        1 => proptest::sample::select(ReturnCode::DEFINED),
        1 => any::<u16>().prop_map(ReturnCode),
    ]
}

fn reply() -> impl Strategy<Value = Reply> {
    let rc = return_code;
    prop_oneof![
        (rc(), any::<u8>(), any::<u8>()).prop_map(|(return_code, major_version, minor_version)| {
            Reply::Handshake {
                return_code,
                major_version,
                minor_version,
            }
        }),
        rc().prop_map(|return_code| Reply::PolarPan { return_code }),
        rc().prop_map(|return_code| Reply::Home { return_code }),
        rc().prop_map(|return_code| Reply::PolarPanStart { return_code }),
        rc().prop_map(|return_code| Reply::PolarPanStop { return_code }),
        rc().prop_map(|return_code| Reply::CartesianMove { return_code }),
        rc().prop_map(|return_code| Reply::CartesianMoveStart { return_code }),
        rc().prop_map(|return_code| Reply::CartesianMoveStop { return_code }),
        (rc(), any::<u16>(), hw_bytes(MAX_HW_REPLY_BYTES)).prop_map(
            |(return_code, subcommand, payload)| Reply::HardwareOperation {
                return_code,
                subcommand,
                payload,
            }
        ),
        (rc(), any::<u8>()).prop_map(|(return_code, speed)| Reply::GetSpeed { return_code, speed }),
        rc().prop_map(|return_code| Reply::SetSpeed { return_code }),
        rc().prop_map(|return_code| Reply::SavePosition { return_code }),
        rc().prop_map(|return_code| Reply::DeletePosition { return_code }),
        rc().prop_map(|return_code| Reply::GoToPosition { return_code }),
        rc().prop_map(|return_code| Reply::SetPolarPosition { return_code }),
        (rc(), any::<i32>(), any::<i32>(), any::<i32>()).prop_map(
            |(return_code, delta, azimuth, radius)| Reply::GetPolarPosition {
                return_code,
                delta,
                azimuth,
                radius,
            }
        ),
        rc().prop_map(|return_code| Reply::SetCartesianPosition { return_code }),
        (rc(), any::<i32>(), any::<i32>(), any::<i32>()).prop_map(|(return_code, x, y, z)| {
            Reply::GetCartesianPosition {
                return_code,
                x,
                y,
                z,
            }
        }),
    ]
}

/// Encodes `frame`, decodes it back through a fresh codec and checks the codec consumed exactly
/// the frame's bytes.
fn through_codec(frame: &TalosFrame, checksum: Checksum) -> Result<TalosFrame, TestCaseError> {
    let bytes = frame.to_bytes(checksum).expect("fits the length field");
    prop_assert_eq!(
        bytes.len(),
        HEADER_LEN + frame.payload.len() + checksum.len()
    );
    prop_assert_eq!(
        &bytes[8..10],
        &(frame.payload.len() as u16).to_be_bytes()[..]
    );
    let mut codec = FrameCodec::new(checksum);
    let mut buf = BytesMut::from(&bytes[..]);
    let decoded = codec.decode(&mut buf).expect("decode never errors");
    prop_assert!(buf.is_empty(), "{} bytes left", buf.len());
    prop_assert_eq!(codec.decode_eof(&mut buf).expect("eof"), None);
    match decoded {
        Some(Decoded::TalosFrame(got)) => Ok(got),
        other => Err(TestCaseError::fail(format!(
            "{checksum}: expected a frame, got {other:?}"
        ))),
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(CASES))]

    #[test]
    fn every_request_round_trips(request in request(), id in any::<u32>()) {
        for checksum in Checksum::ALL {
            let frame = request.to_frame(id).expect("a generated request is valid");
            prop_assert_eq!(frame.id, id);
            prop_assert_eq!(frame.command, request.command().request_value());
            let got = through_codec(&frame, checksum)?;
            prop_assert_eq!(&got, &frame);
            prop_assert_eq!(Request::from_frame(&got), Ok(request.clone()), "{}", checksum);
        }
    }

    #[test]
    fn every_reply_round_trips(reply in reply(), request_id in any::<u32>()) {
        for checksum in Checksum::ALL {
            let frame = reply.to_frame(request_id).expect("a generated reply is valid");
            prop_assert_eq!(frame.id, request_id | 1);
            prop_assert_eq!(frame.command, reply.command().reply_value());
            let got = through_codec(&frame, checksum)?;
            prop_assert_eq!(&got, &frame);
            prop_assert_eq!(Reply::from_frame(&got), Ok(reply.clone()), "{}", checksum);
        }
    }

    /// A stream of several messages, fed in arbitrary chunks, yields every one in order.
    #[test]
    fn a_stream_of_messages_round_trips_in_any_chunking(
        requests in vec(request(), 1..8),
        replies in vec(reply(), 1..8),
        chunk in 1usize..64,
    ) {
        for checksum in Checksum::ALL {
            let mut wire = Vec::new();
            let mut frames = Vec::new();
            for (i, r) in requests.iter().enumerate() {
                let frame = r.to_frame(2 * i as u32).unwrap();
                frame.encode_into(checksum, &mut wire).unwrap();
                frames.push(frame);
            }
            for (i, r) in replies.iter().enumerate() {
                let frame = r.to_frame(2 * i as u32).unwrap();
                frame.encode_into(checksum, &mut wire).unwrap();
                frames.push(frame);
            }
            let mut codec = FrameCodec::new(checksum);
            let mut buf = BytesMut::new();
            let mut got = Vec::new();
            for piece in wire.chunks(chunk) {
                buf.extend_from_slice(piece);
                while let Some(item) = codec.decode(&mut buf).unwrap() {
                    match item {
                        Decoded::TalosFrame(f) => got.push(f),
                        Decoded::Rejected(r) => {
                            return Err(TestCaseError::fail(format!("{checksum}: rejected {r:?}")))
                        }
                    }
                }
            }
            prop_assert_eq!(codec.decode_eof(&mut buf).unwrap(), None);
            prop_assert_eq!(&got, &frames);
            for (f, r) in got.iter().zip(&requests) {
                prop_assert_eq!(&Request::from_frame(f).unwrap(), r);
            }
            for (f, r) in got[requests.len()..].iter().zip(&replies) {
                prop_assert_eq!(&Reply::from_frame(f).unwrap(), r);
            }
        }
    }

    /// A bare return code that is not OK always decodes, for every reply, to `Reply::error`.
    #[test]
    fn a_bare_error_code_decodes_for_every_reply(
        index in 0usize..18,
        code in 1u16..,
    ) {
        let command = armjog::talos::CommandValue::ALL[index];
        let frame = TalosFrame::new(1, command.reply_value(), code.to_be_bytes().to_vec());
        let got = through_codec(&frame, Checksum::Crc16)?;
        let reply = Reply::from_frame(&got).expect("bare error reply");
        prop_assert_eq!(reply.return_code(), ReturnCode(code));
        prop_assert_eq!(reply.command(), command);
        prop_assert_eq!(&reply, &Reply::error(command, ReturnCode(code)));
    }
}
