//! Frames split across reads, and the per-frame read deadline (`armjog::net::FrameReader`).
//!
//! Issue 9, items 2 and 6: a frame with a good checksum but an unknown command or a wrong length
//! must be decoded however TCP splits it; a header announcing more payload than comes must not
//! hold back the frames behind it for longer than the deadline. Timing runs on tokio's paused
//! clock over in-memory streams, so it is exact and does not depend on the machine's load.

use std::time::Duration;

use armjog::net::{DEFAULT_FRAME_DEADLINE, FrameReader};
use armjog::talos::frame::{Decoded, FrameHeader, HEADER_LEN, Rejection};
use armjog::talos::{Checksum, FrameCodec, RejectReason, Request, TalosFrame};
use bytes::BytesMut;
use tokio::io::{AsyncWriteExt, DuplexStream};
use tokio::time::Instant;
use tokio_util::codec::Decoder;

const DEADLINE: Duration = DEFAULT_FRAME_DEADLINE;

fn bytes_of(frame: &TalosFrame, checksum: Checksum) -> Vec<u8> {
    frame.to_bytes(checksum).expect("fits")
}

fn req(request: Request, id: u32) -> TalosFrame {
    request.to_frame(id).expect("valid request")
}

/// Command 0x0042 is not in the ICD.
fn unknown_command(id: u32) -> TalosFrame {
    TalosFrame::new(id, 0x0042, vec![1, 2, 3])
}

/// Set Speed carries one byte, not two.
fn wrong_length(id: u32) -> TalosFrame {
    TalosFrame::new(id, 0x000A, vec![1, 2])
}

fn save(id: u32) -> TalosFrame {
    req(
        Request::SavePosition {
            name: "pick".into(),
            anchor: true,
            parent: "home".into(),
        },
        id,
    )
}

/// Everything the codec yields for `pieces` fed one after the other, then at end of stream.
fn decode_pieces(checksum: Checksum, pieces: &[&[u8]]) -> Vec<Decoded> {
    let mut codec = FrameCodec::new(checksum);
    let mut buf = BytesMut::new();
    let mut out = Vec::new();
    for piece in pieces {
        buf.extend_from_slice(piece);
        while let Some(item) = codec.decode(&mut buf).expect("decode never errors") {
            out.push(item);
        }
    }
    while let Some(item) = codec.decode_eof(&mut buf).expect("decode_eof never errors") {
        out.push(item);
    }
    out
}

// ---- the codec: splits do not matter ----

#[test]
fn a_frame_split_at_every_offset_is_decoded_as_in_one_read() {
    for checksum in Checksum::ALL {
        let mut frames = vec![save(2), req(Request::PolarPanStop, 4)];
        // With no checksum, nothing vouches for a header the ICD does not allow: those are
        // refused whole (see talos_decoder.rs).
        if checksum != Checksum::None {
            frames.extend([unknown_command(6), wrong_length(8)]);
        }
        for frame in frames {
            let wire = bytes_of(&frame, checksum);
            let whole = decode_pieces(checksum, &[&wire]);
            assert_eq!(whole, [Decoded::TalosFrame(frame.clone())], "{checksum}");
            for at in 0..=wire.len() {
                let (a, b) = wire.split_at(at);
                assert_eq!(
                    decode_pieces(checksum, &[a, b]),
                    whole,
                    "{checksum}: {frame:?} split at {at}"
                );
            }
        }
    }
}

#[test]
fn several_split_odd_frames_in_a_row_all_come_out() {
    // The regression of issue 9 item 2: once one split odd frame was dropped, the codec lost
    // sync and dropped every such frame after it. Each frame here is split at a different place.
    for checksum in [Checksum::Crc16, Checksum::Xor8] {
        let frames: Vec<TalosFrame> = (0..8u32)
            .map(|i| {
                if i % 2 == 0 {
                    unknown_command(2 * i)
                } else {
                    wrong_length(2 * i)
                }
            })
            .collect();
        let wires: Vec<Vec<u8>> = frames.iter().map(|f| bytes_of(f, checksum)).collect();
        let mut pieces: Vec<&[u8]> = Vec::new();
        for (i, wire) in wires.iter().enumerate() {
            // After the header: the split the old decoder got wrong.
            let (a, b) = wire.split_at(HEADER_LEN + i % (wire.len() - HEADER_LEN));
            pieces.extend([a, b]);
        }
        let expected: Vec<Decoded> = frames.into_iter().map(Decoded::TalosFrame).collect();
        assert_eq!(decode_pieces(checksum, &pieces), expected, "{checksum}");
    }
}

#[test]
fn expire_gives_up_the_waiting_frame_and_finds_the_one_behind_it() {
    for checksum in Checksum::ALL {
        let header = stalled_header();
        let next = req(Request::PolarPanStop, 0x1234_5678);
        let mut buf = BytesMut::from(&[header.clone(), bytes_of(&next, checksum)].concat()[..]);
        let have = buf.len();
        let mut codec = FrameCodec::new(checksum);
        assert_eq!(codec.decode(&mut buf).unwrap(), None, "{checksum}: waits");
        // Nothing is waiting in an empty buffer, and nothing was dropped yet.
        assert_eq!(codec.expire(&mut BytesMut::new(), 1, DEADLINE), None);
        assert_eq!(
            codec.expire(&mut buf, have, DEADLINE),
            Some(Decoded::Rejected(Rejection {
                reason: RejectReason::Stalled {
                    have,
                    needed: HEADER_LEN + 500 + checksum.len(),
                    after: DEADLINE,
                },
                discarded: HEADER_LEN,
                header: Some(FrameHeader {
                    id: 2,
                    command: 0x0008,
                    length: 500
                }),
                fits: None,
            })),
            "{checksum}"
        );
        assert_eq!(
            codec.decode(&mut buf).unwrap(),
            Some(Decoded::TalosFrame(next)),
            "{checksum}"
        );
        assert!(buf.is_empty());
    }
}

// ---- the reader's deadline ----

/// A hardware operation header (a plausible command) announcing 500 payload bytes.
fn stalled_header() -> Vec<u8> {
    let mut header = vec![0, 0, 0, 2, 0, 0, 0x00, 0x08];
    header.extend(500u16.to_be_bytes());
    header
}

fn reader(checksum: Checksum) -> (FrameReader<DuplexStream>, DuplexStream) {
    let (ours, theirs) = tokio::io::duplex(64 * 1024);
    let reader = FrameReader::new(ours, FrameCodec::new(checksum), DEADLINE, "test peer");
    (reader, theirs)
}

async fn next_item(reader: &mut FrameReader<DuplexStream>) -> Decoded {
    reader
        .next()
        .await
        .expect("stream still open")
        .expect("no IO error")
}

fn assert_stalled(item: &Decoded, have: usize, needed: usize) {
    match item {
        Decoded::Rejected(Rejection {
            reason:
                RejectReason::Stalled {
                    have: h,
                    needed: n,
                    after,
                },
            ..
        }) => {
            assert_eq!((*h, *n, *after), (have, needed, DEADLINE), "{item:?}");
        }
        other => panic!("expected a stalled frame, got {other:?}"),
    }
}

#[tokio::test(start_paused = true)]
async fn split_odd_frames_with_pauses_all_come_out_of_the_reader() {
    let (mut reader, mut peer) = reader(Checksum::Crc16);
    let frames: Vec<TalosFrame> = (0..6u32)
        .map(|i| {
            if i % 2 == 0 {
                unknown_command(2 * i)
            } else {
                wrong_length(2 * i)
            }
        })
        .collect();
    let wires: Vec<Vec<u8>> = frames
        .iter()
        .map(|f| bytes_of(f, Checksum::Crc16))
        .collect();
    let writer = tokio::spawn(async move {
        for wire in wires {
            let (a, b) = wire.split_at(HEADER_LEN + 1);
            peer.write_all(a).await.unwrap();
            tokio::time::sleep(Duration::from_millis(300)).await;
            peer.write_all(b).await.unwrap();
        }
        peer
    });
    for frame in frames {
        assert_eq!(next_item(&mut reader).await, Decoded::TalosFrame(frame));
    }
    drop(writer.await.unwrap());
    assert!(reader.next().await.is_none(), "the stream has ended");
}

#[tokio::test(start_paused = true)]
async fn a_header_announcing_more_than_comes_releases_the_frame_behind_it_at_the_deadline() {
    for checksum in Checksum::ALL {
        let (mut reader, mut peer) = reader(checksum);
        let next = req(Request::PolarPanStop, 0x1234_5678);
        let wire = [stalled_header(), bytes_of(&next, checksum)].concat();
        let start = Instant::now();
        peer.write_all(&wire).await.unwrap();
        let item = next_item(&mut reader).await;
        let waited = start.elapsed();
        assert_stalled(&item, wire.len(), HEADER_LEN + 500 + checksum.len());
        assert!(
            waited >= DEADLINE && waited < DEADLINE + Duration::from_millis(50),
            "{checksum}: given up after {waited:?}"
        );
        // The frame behind it comes out at once, without another byte from the peer.
        assert_eq!(next_item(&mut reader).await, Decoded::TalosFrame(next));
        assert!(start.elapsed() < DEADLINE + Duration::from_millis(50));
    }
}

#[tokio::test(start_paused = true)]
async fn a_trickle_of_bytes_does_not_extend_the_deadline() {
    let (mut reader, mut peer) = reader(Checksum::Crc16);
    let start = Instant::now();
    peer.write_all(&stalled_header()).await.unwrap();
    let trickle = tokio::spawn(async move {
        for _ in 0..20 {
            tokio::time::sleep(Duration::from_millis(900)).await;
            if peer.write_all(&[0x5A]).await.is_err() {
                break;
            }
        }
        peer
    });
    let item = next_item(&mut reader).await;
    let waited = start.elapsed();
    // The header and the one byte that came at 900 ms.
    assert_stalled(&item, HEADER_LEN + 1, HEADER_LEN + 500 + 2);
    assert!(
        waited >= DEADLINE && waited < DEADLINE + Duration::from_millis(50),
        "given up after {waited:?}"
    );
    trickle.abort();
}

#[tokio::test(start_paused = true)]
async fn a_stalled_frame_with_nothing_behind_it_is_dropped_whole_and_the_reader_then_idles() {
    let (mut reader, mut peer) = reader(Checksum::Crc16);
    peer.write_all(&stalled_header()).await.unwrap();
    match next_item(&mut reader).await {
        Decoded::Rejected(rejection) => assert_eq!(rejection.discarded, HEADER_LEN),
        other => panic!("expected the stall, got {other:?}"),
    }
    // Nothing is left to time out: no further reports while the peer is silent.
    let idle = tokio::time::timeout(Duration::from_secs(30), reader.next()).await;
    assert!(idle.is_err(), "reported {idle:?} with nothing buffered");
    // And the connection still works.
    let frame = save(4);
    peer.write_all(&bytes_of(&frame, Checksum::Crc16))
        .await
        .unwrap();
    assert_eq!(next_item(&mut reader).await, Decoded::TalosFrame(frame));
}

#[tokio::test(start_paused = true)]
async fn a_stray_byte_before_a_stop_holds_it_no_longer_than_the_deadline() {
    // At a clean boundary, a stray byte makes a STOP's header read as a 1024-byte Handshake,
    // which the codec waits for; the deadline releases the STOP.
    let (mut reader, mut peer) = reader(Checksum::Crc16);
    let stop = req(Request::PolarPanStop, 2);
    let start = Instant::now();
    peer.write_all(&[[0x12].as_slice(), &bytes_of(&stop, Checksum::Crc16)].concat())
        .await
        .unwrap();
    assert!(matches!(
        next_item(&mut reader).await,
        Decoded::Rejected(Rejection {
            reason: RejectReason::Stalled { .. },
            discarded: 1,
            ..
        })
    ));
    assert_eq!(next_item(&mut reader).await, Decoded::TalosFrame(stop));
    assert!(start.elapsed() < DEADLINE + Duration::from_millis(50));
}

#[tokio::test(start_paused = true)]
async fn a_frame_completed_within_the_deadline_is_not_given_up() {
    let (mut reader, mut peer) = reader(Checksum::Crc16);
    let frame = save(6);
    let wire = bytes_of(&frame, Checksum::Crc16);
    let (a, b) = wire.split_at(3);
    let b = b.to_vec();
    peer.write_all(a).await.unwrap();
    let writer = tokio::spawn(async move {
        tokio::time::sleep(DEADLINE - Duration::from_millis(10)).await;
        peer.write_all(&b).await.unwrap();
        peer
    });
    assert_eq!(next_item(&mut reader).await, Decoded::TalosFrame(frame));
    drop(writer.await.unwrap());
}

#[tokio::test(start_paused = true)]
async fn bytes_that_came_while_the_caller_was_busy_are_not_expired() {
    // The server answers one frame before it reads the next: the rest of a frame that arrived
    // meanwhile is read before the deadline is checked.
    let (mut reader, mut peer) = reader(Checksum::Crc16);
    let first = save(2);
    let second = save(4);
    let second_wire = bytes_of(&second, Checksum::Crc16);
    let (a, b) = second_wire.split_at(5);
    peer.write_all(&[bytes_of(&first, Checksum::Crc16).as_slice(), a].concat())
        .await
        .unwrap();
    assert_eq!(next_item(&mut reader).await, Decoded::TalosFrame(first));
    tokio::time::sleep(Duration::from_millis(300)).await;
    peer.write_all(b).await.unwrap();
    // The caller is busy for three deadlines before it asks for the next frame.
    tokio::time::sleep(3 * DEADLINE).await;
    assert_eq!(next_item(&mut reader).await, Decoded::TalosFrame(second));
}

#[tokio::test(start_paused = true)]
async fn the_stream_ending_inside_a_frame_is_reported_truncated() {
    let (mut reader, mut peer) = reader(Checksum::Crc16);
    let frame = save(2);
    let wire = bytes_of(&frame, Checksum::Crc16);
    peer.write_all(&wire).await.unwrap();
    peer.write_all(&wire[..7]).await.unwrap();
    drop(peer);
    assert_eq!(next_item(&mut reader).await, Decoded::TalosFrame(frame));
    assert!(matches!(
        next_item(&mut reader).await,
        Decoded::Rejected(Rejection {
            reason: RejectReason::Truncated { have: 7, .. },
            discarded: 7,
            ..
        })
    ));
    assert!(reader.next().await.is_none());
}

// ---- expiry on arbitrary input ----

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(256))]

    /// Whatever the bytes, the split and the moments the deadline passes: no panic, an expiry
    /// while the codec waits always reports what it dropped, the codec never holds more than
    /// one frame's worth, and every byte is in a frame or reported discarded, exactly once.
    #[test]
    fn expiring_at_arbitrary_moments_accounts_for_every_byte(
        bytes in proptest::collection::vec(
            proptest::prop_oneof![3 => 0u8..=0x12, 1 => proptest::prelude::any::<u8>()],
            0..600,
        ),
        chunk in 1usize..40,
        expiries in proptest::collection::vec(proptest::prelude::any::<(bool, u8)>(), 64),
    ) {
        for checksum in Checksum::ALL {
            let mut codec = FrameCodec::with_max_payload(checksum, 64);
            let mut buf = BytesMut::new();
            let mut accounted = 0;
            let mut account = |item: &Decoded| match item {
                Decoded::TalosFrame(f) => accounted += f.encoded_len(checksum),
                Decoded::Rejected(r) => accounted += r.discarded,
            };
            for (i, piece) in bytes.chunks(chunk).enumerate() {
                buf.extend_from_slice(piece);
                while let Some(item) = codec.decode(&mut buf).unwrap() {
                    account(&item);
                }
                proptest::prop_assert!(buf.len() < codec.max_frame_len());
                let (expire, overdue) = expiries[i % expiries.len()];
                if expire && !buf.is_empty() {
                    let overdue = 1 + usize::from(overdue) % buf.len();
                    let item = codec.expire(&mut buf, overdue, DEADLINE);
                    match &item {
                        Some(Decoded::Rejected(r)) => {
                            proptest::prop_assert!(r.discarded >= 1);
                            let stalled = matches!(r.reason, RejectReason::Stalled { .. });
                            proptest::prop_assert!(stalled, "{:?}", r);
                        }
                        other => proptest::prop_assert!(false, "expiry gave {:?}", other),
                    }
                    for item in item.into_iter().chain(std::iter::from_fn(|| {
                        codec.decode(&mut buf).unwrap()
                    })) {
                        account(&item);
                    }
                }
            }
            while let Some(item) = codec.decode_eof(&mut buf).unwrap() {
                account(&item);
            }
            proptest::prop_assert!(buf.is_empty());
            proptest::prop_assert_eq!(accounted, bytes.len(), "{}", checksum);
        }
    }
}
