//! Feeds arbitrary bytes to `FrameCodec` and every decoded frame to the message layer.
//!
//! The first byte picks the checksum dialect (low 2 bits), whether the payload bound is the
//! default or a small one (bit 2), and the read size (high 5 bits, 0 = everything at once), so
//! the fuzzer explores split reads too. Checked on every input: no panic, the decoder never
//! waits holding a full frame's worth of bytes, every input byte is either in a frame or
//! reported discarded, and every accepted frame re-encodes to the bytes it came from.
#![no_main]

use armjog::talos::frame::{DEFAULT_MAX_PAYLOAD, Decoded};
use armjog::talos::{Checksum, FrameCodec, Reply, Request};
use bytes::BytesMut;
use libfuzzer_sys::fuzz_target;
use tokio_util::codec::Decoder;

fuzz_target!(|data: &[u8]| {
    let Some((&control, input)) = data.split_first() else {
        return;
    };
    let checksum = Checksum::ALL[usize::from(control & 0b11) % Checksum::ALL.len()];
    let max_payload = if control & 0b100 == 0 {
        DEFAULT_MAX_PAYLOAD
    } else {
        16
    };
    let chunk = match usize::from(control >> 3) {
        0 => input.len().max(1),
        n => n,
    };

    let mut codec = FrameCodec::with_max_payload(checksum, max_payload);
    let mut buf = BytesMut::new();
    // Items come out in stream order, so this is also where the next item's bytes begin.
    let mut accounted = 0;
    let mut check = |item: Decoded| match item {
        Decoded::Frame(frame) => {
            let bytes = frame
                .to_bytes(checksum)
                .expect("a decoded frame re-encodes");
            let original = &input[accounted..accounted + bytes.len()];
            // The `none` field is never checked, so it may hold anything.
            let compared = bytes.len() - if checksum == Checksum::None { 2 } else { 0 };
            assert_eq!(&bytes[..compared], &original[..compared]);
            assert!(frame.payload.len() <= max_payload);
            accounted += bytes.len();
            let _ = Request::from_frame(&frame);
            let _ = Reply::from_frame(&frame);
        }
        Decoded::Rejected(rejection) => {
            assert!(rejection.discarded > 0, "empty rejection {rejection:?}");
            accounted += rejection.discarded;
        }
    };
    for piece in input.chunks(chunk) {
        buf.extend_from_slice(piece);
        while let Some(item) = codec.decode(&mut buf).expect("decode never errors") {
            check(item);
        }
        assert!(
            buf.len() < codec.max_frame_len(),
            "waits holding {} bytes",
            buf.len()
        );
    }
    while let Some(item) = codec.decode_eof(&mut buf).expect("decode_eof never errors") {
        check(item);
    }
    assert!(buf.is_empty(), "{} bytes left after EOF", buf.len());
    assert_eq!(accounted, input.len(), "bytes lost or counted twice");
});
