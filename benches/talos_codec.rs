//! Encode and decode cost of typical Talos frames.
//!
//! - encode: `Request::to_frame` / `Reply::to_frame` + `TalosFrame::encode_into` into a reused `Vec`;
//! - decode: `FrameCodec::decode` from a reused `BytesMut` + `Request::from_frame` /
//!   `Reply::from_frame`;
//! - round_trip: both, one after the other (the figure to compare with the 200 ns target).
//!
//! Run: `cargo bench --bench talos_codec -- --warm-up-time 1 --measurement-time 3`

use std::hint::black_box;

use armjog::talos::frame::{DEFAULT_MAX_PAYLOAD, Decoded, HEADER_LEN, parse_frame};
use armjog::talos::{Checksum, FrameCodec, Reply, Request, ReturnCode, TalosFrame};
use bytes::BytesMut;
use criterion::{Criterion, criterion_group, criterion_main};
use tokio_util::codec::Decoder;

/// A message of either direction, so one benchmark body serves both.
#[derive(Clone)]
enum Message {
    Request(Request),
    Reply(Reply),
}

impl Message {
    fn to_frame(&self, id: u32) -> TalosFrame {
        match self {
            Message::Request(r) => r.to_frame(id).expect("valid request"),
            Message::Reply(r) => r.to_frame(id).expect("valid reply"),
        }
    }

    /// Decodes the frame back into a message of the same direction.
    fn read(&self, frame: &TalosFrame) -> Message {
        match self {
            Message::Request(_) => Message::Request(Request::from_frame(frame).expect("request")),
            Message::Reply(_) => Message::Reply(Reply::from_frame(frame).expect("reply")),
        }
    }
}

fn typical() -> [(&'static str, Message); 3] {
    [
        (
            "cart_start",
            Message::Request(Request::CartesianMoveStart {
                moving_x: 1,
                moving_y: 0,
                moving_z: -1,
            }),
        ),
        (
            "get_cart_reply",
            Message::Reply(Reply::GetCartesianPosition {
                return_code: ReturnCode::OK,
                x: 4_566,
                y: 10,
                z: 4_338,
            }),
        ),
        (
            "save",
            Message::Request(Request::SavePosition {
                name: "pick 1".into(),
                anchor: true,
                parent: "home".into(),
            }),
        ),
    ]
}

fn decode_one(codec: &mut FrameCodec, buf: &mut BytesMut) -> TalosFrame {
    match codec.decode(buf).expect("decode") {
        Some(Decoded::TalosFrame(frame)) => frame,
        other => panic!("expected a frame, got {other:?}"),
    }
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("talos_codec");
    for checksum in [Checksum::Crc16, Checksum::Xor8] {
        for (name, message) in typical() {
            let wire = message.to_frame(0x0000_1234).to_bytes(checksum).unwrap();

            let mut out = Vec::with_capacity(64);
            group.bench_function(format!("{name}/{checksum}/encode"), |b| {
                b.iter(|| {
                    let frame = black_box(&message).to_frame(black_box(0x0000_1234));
                    out.clear();
                    frame.encode_into(checksum, &mut out).unwrap();
                    black_box(&out);
                })
            });

            let mut codec = FrameCodec::new(checksum);
            let mut buf = BytesMut::with_capacity(256);
            group.bench_function(format!("{name}/{checksum}/decode"), |b| {
                b.iter(|| {
                    buf.extend_from_slice(black_box(&wire));
                    let frame = decode_one(&mut codec, &mut buf);
                    black_box(message.read(&frame))
                })
            });

            group.bench_function(format!("{name}/{checksum}/round_trip"), |b| {
                b.iter(|| {
                    let frame = black_box(&message).to_frame(black_box(0x0000_1234));
                    out.clear();
                    frame.encode_into(checksum, &mut out).unwrap();
                    buf.extend_from_slice(&out);
                    let frame = decode_one(&mut codec, &mut buf);
                    black_box(message.read(&frame))
                })
            });
        }
    }
    group.finish();
}

/// The pieces of a round trip, to see where the time goes.
fn parts(c: &mut Criterion) {
    let mut group = c.benchmark_group("talos_parts");
    let get_cart = typical()[1].1.to_frame(0x1234);
    let covered = &get_cart.to_bytes(Checksum::Xor8).unwrap()[..HEADER_LEN + 14];
    for checksum in [Checksum::Crc16, Checksum::Xor8] {
        group.bench_function(format!("checksum_24_bytes/{checksum}"), |b| {
            b.iter(|| black_box(checksum.compute(black_box(covered))))
        });
    }
    let (_, save) = &typical()[2];
    let Message::Request(save) = save else {
        unreachable!()
    };
    let frame = save.to_frame(0x1234).unwrap();
    let wire = frame.to_bytes(Checksum::Xor8).unwrap();
    group.bench_function("save/to_frame", |b| {
        b.iter(|| black_box(black_box(save).to_frame(0x1234)))
    });
    let mut out = Vec::with_capacity(64);
    group.bench_function("save/encode_into/xor8", |b| {
        b.iter(|| {
            out.clear();
            black_box(&frame)
                .encode_into(Checksum::Xor8, &mut out)
                .unwrap();
            black_box(&out);
        })
    });
    group.bench_function("save/parse_frame/xor8", |b| {
        b.iter(|| {
            black_box(parse_frame(
                black_box(&wire),
                Checksum::Xor8,
                DEFAULT_MAX_PAYLOAD,
                false,
            ))
        })
    });
    group.bench_function("save/from_frame", |b| {
        b.iter(|| black_box(Request::from_frame(black_box(&frame))))
    });
    group.finish();
}

criterion_group!(benches, bench, parts);
criterion_main!(benches);
