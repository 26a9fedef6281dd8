//! The operator link reading replies split across reads, and a reply that never completes
//! (issue 9, items 2 and 6).

use crate::common;

use std::sync::Arc;
use std::time::{Duration, Instant};

use armjog::link::{TalosConfig, TalosError, TalosLink};
use armjog::talos::frame::HEADER_LEN;
use armjog::talos::{Checksum, RejectReason, Reply, Request, ReturnCode, TalosFrame};
use common::{Action, TestOperator, reply_bytes};

fn config(addr: &str) -> TalosConfig {
    let mut c = TalosConfig::new(addr);
    // Generous, so that only the behaviour under test can fail a request.
    c.request_timeout = Duration::from_secs(8);
    c
}

/// Answers Get Speed normally and a Handshake with `handshake_reply(frame)` written in two
/// parts, 100 ms apart, split after the header (the second part is empty if there is no more).
fn operator(handshake_reply: fn(&TalosFrame) -> Vec<u8>) -> common::Script {
    Arc::new(move |f: &TalosFrame| match Request::from_frame(f) {
        Ok(Request::Handshake { .. }) => {
            let wire = handshake_reply(f);
            let (a, b) = wire.split_at(wire.len().min(HEADER_LEN + 1));
            vec![
                Action::Write(a.to_vec()),
                Action::Sleep(Duration::from_millis(100)),
                Action::Write(b.to_vec()),
            ]
        }
        _ => {
            let reply = Reply::GetSpeed {
                return_code: ReturnCode::OK,
                speed: 42,
            };
            vec![Action::Write(reply_bytes(&reply, f.id, Checksum::Crc16))]
        }
    })
}

#[tokio::test]
async fn a_split_wrong_length_handshake_reply_is_a_malformed_reply() {
    // A Handshake reply carries a return code and two version bytes: three bytes here.
    let op = TestOperator::start(
        Checksum::Crc16,
        operator(|f| {
            TalosFrame::new(f.id | 1, 0x8000, vec![0, 0, 1])
                .to_bytes(Checksum::Crc16)
                .unwrap()
        }),
    )
    .await;
    let (link, _events) = TalosLink::connect(config(&op.addr)).await.unwrap();
    let err = link.handshake(7).await.unwrap_err();
    assert!(
        matches!(err, TalosError::MalformedReply { id: 0, .. }),
        "expected a malformed reply, got: {err}"
    );
    assert!(err.to_string().contains("malformed reply"), "{err}");
    // The link is still in step.
    assert!(link.request(Request::GetSpeed).await.is_ok());
}

#[tokio::test]
async fn a_reply_that_never_completes_fails_its_request_at_the_frame_deadline() {
    // The operator answers the Handshake with a header announcing 200 payload bytes, and no more.
    let op = TestOperator::start(
        Checksum::Crc16,
        operator(|f| {
            let mut header = (f.id | 1).to_be_bytes().to_vec();
            header.extend([0, 0, 0x80, 0x00]);
            header.extend(200u16.to_be_bytes());
            header
        }),
    )
    .await;
    let mut config = config(&op.addr);
    config.frame_deadline = Duration::from_secs(1);
    let (link, _events) = TalosLink::connect(config).await.unwrap();
    let start = Instant::now();
    let err = link.handshake(7).await.unwrap_err();
    let waited = start.elapsed();
    match &err {
        TalosError::Checksum { rejection, .. } => assert!(
            matches!(rejection.reason, RejectReason::Stalled { .. }),
            "{err}"
        ),
        other => panic!("expected the stalled reply, got: {other}"),
    }
    assert!(
        waited >= Duration::from_secs(1) && waited < Duration::from_secs(6),
        "failed after {waited:?}"
    );
    assert!(link.request(Request::GetSpeed).await.is_ok());
}
