//! The deployed operator's reply dialect: every frame, valid or not, is answered by the four
//! bytes `41 43 4B 00` ("ACK\0") before it is even validated. An ACK carries no id, so a link
//! pairs ACKs with its outstanding requests in order.

use bytes::{Buf, BytesMut};
use tokio_util::codec::{Decoder, Encoder};

/// The four bytes of one acknowledgement.
pub const ACK: [u8; 4] = *b"ACK\0";

/// What an ack-dialect stream yields.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AckItem {
    Ack,
    /// Bytes that were not part of an ACK and were dropped.
    Garbage(usize),
}

/// Decodes a stream of ACKs (and encodes them, for test operators).
#[derive(Debug, Clone, Copy, Default)]
pub struct AckCodec;

impl Decoder for AckCodec {
    type Item = AckItem;
    type Error = std::io::Error;

    fn decode(&mut self, src: &mut BytesMut) -> Result<Option<AckItem>, Self::Error> {
        if src.starts_with(&ACK) {
            src.advance(ACK.len());
            return Ok(Some(AckItem::Ack));
        }
        // Drop bytes up to the next position that could still begin an ACK.
        let keep_from = (0..src.len())
            .find(|&i| {
                let tail = &src[i..];
                let n = tail.len().min(ACK.len());
                tail[..n] == ACK[..n]
            })
            .unwrap_or(src.len());
        if keep_from > 0 {
            src.advance(keep_from);
            return Ok(Some(AckItem::Garbage(keep_from)));
        }
        Ok(None)
    }

    fn decode_eof(&mut self, src: &mut BytesMut) -> Result<Option<AckItem>, Self::Error> {
        if let Some(item) = self.decode(src)? {
            return Ok(Some(item));
        }
        let left = src.len();
        src.clear();
        Ok((left > 0).then_some(AckItem::Garbage(left)))
    }
}

impl Encoder<AckItem> for AckCodec {
    type Error = std::io::Error;

    fn encode(&mut self, _item: AckItem, dst: &mut BytesMut) -> Result<(), Self::Error> {
        dst.extend_from_slice(&ACK);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn drain(bytes: &[u8]) -> Vec<AckItem> {
        let mut buf = BytesMut::from(bytes);
        let mut codec = AckCodec;
        let mut out = Vec::new();
        while let Some(item) = codec.decode(&mut buf).expect("decode") {
            out.push(item);
        }
        out
    }

    #[test]
    fn reads_consecutive_acks() {
        assert_eq!(
            drain(&[0x41, 0x43, 0x4B, 0x00, 0x41, 0x43, 0x4B, 0x00]),
            [AckItem::Ack, AckItem::Ack]
        );
    }

    #[test]
    fn waits_for_a_split_ack_and_reports_garbage() {
        let mut buf = BytesMut::from(&b"xyACK"[..]);
        let mut codec = AckCodec;
        assert_eq!(codec.decode(&mut buf).unwrap(), Some(AckItem::Garbage(2)));
        assert_eq!(codec.decode(&mut buf).unwrap(), None);
        buf.extend_from_slice(&[0x00]);
        assert_eq!(codec.decode(&mut buf).unwrap(), Some(AckItem::Ack));
    }

    #[test]
    fn a_false_start_is_dropped() {
        assert_eq!(drain(b"ACKXACK\0"), [AckItem::Garbage(4), AckItem::Ack]);
    }
}
