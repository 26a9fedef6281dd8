//! Which checksum a frame that fails ours fits: `talos::checksum_that_fits` and the decoder's
//! rejections that carry it.

use bytes::BytesMut;
use tokio_util::codec::Decoder;

use armjog::talos::frame::{DEFAULT_MAX_PAYLOAD, Decoded};
use armjog::talos::{Checksum, FrameCodec, Reply, ReturnCode, checksum_that_fits};

fn reply(checksum: Checksum) -> Vec<u8> {
    Reply::GetSpeed {
        return_code: ReturnCode::OK,
        speed: 42,
    }
    .to_frame(1)
    .expect("frame")
    .to_bytes(checksum)
    .expect("bytes")
}

#[test]
fn every_dialect_is_recognised_under_each_other() {
    for speaks in Checksum::ALL {
        let bytes = reply(speaks);
        for used in Checksum::ALL.into_iter().filter(|c| *c != speaks) {
            let fit = checksum_that_fits(&bytes, used, DEFAULT_MAX_PAYLOAD);
            assert_eq!(
                fit.map(|f| (f.used, f.fits)),
                Some((used, speaks)),
                "{speaks} bytes under {used}"
            );
        }
    }
}

#[test]
fn noise_and_a_corrupt_frame_fit_nothing() {
    assert_eq!(
        checksum_that_fits(&[0xFF; 16], Checksum::Crc16, DEFAULT_MAX_PAYLOAD),
        None
    );
    let mut corrupt = reply(Checksum::Crc16);
    corrupt[11] ^= 0x40;
    let last = corrupt.len() - 1;
    corrupt[last] ^= 0x01;
    assert_eq!(
        checksum_that_fits(&corrupt, Checksum::Xor8, DEFAULT_MAX_PAYLOAD),
        None
    );
}

#[test]
fn a_bad_checksum_rejection_names_the_fitting_checksum() {
    let mut codec = FrameCodec::new(Checksum::Xor8);
    let mut buf = BytesMut::from(&reply(Checksum::Crc16)[..]);
    let Some(Decoded::Rejected(rejection)) = codec.decode(&mut buf).expect("decode") else {
        panic!("a crc16 frame under xor8 is rejected");
    };
    let fit = rejection.fits.expect("fits crc16");
    assert_eq!((fit.used, fit.fits), (Checksum::Xor8, Checksum::Crc16));
    assert!(
        rejection
            .to_string()
            .contains("checksum fails xor8 but fits crc16"),
        "{rejection}"
    );
}

#[test]
fn a_stalled_frame_names_the_fitting_checksum() {
    let mut codec = FrameCodec::new(Checksum::Crc16);
    let bytes = reply(Checksum::Xor8);
    let mut buf = BytesMut::from(&bytes[..]);
    assert_eq!(
        codec.decode(&mut buf).expect("decode"),
        None,
        "a byte short: waits"
    );
    let Some(Decoded::Rejected(rejection)) =
        codec.expire(&mut buf, bytes.len(), std::time::Duration::from_secs(1))
    else {
        panic!("given up at its deadline");
    };
    let fit = rejection.fits.expect("fits xor8");
    assert_eq!((fit.used, fit.fits), (Checksum::Crc16, Checksum::Xor8));
}
