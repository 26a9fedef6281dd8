//! Errors in words, with a hint: the binary against a closed port and against scripted
//! operators that are silent or speak another checksum.

use crate::common;

use std::sync::Arc;

use crate::armjog_run::armjog;
use armjog::talos::{Checksum, Reply, ReturnCode, TalosFrame};
use common::{Action, TestOperator, reply_bytes};

/// A loopback address nothing listens on.
fn closed_port() -> String {
    let listener = std::net::TcpListener::bind("127.0.0.1:0").expect("bind");
    let addr = listener.local_addr().expect("addr").to_string();
    drop(listener);
    addr
}

#[tokio::test(flavor = "multi_thread")]
async fn a_closed_port_reads_connection_refused_with_its_address() {
    let addr = closed_port();
    for args in [
        vec!["send", "get-speed", "--talos", &addr],
        vec!["modbus", "quick-stop", "--modbus", &addr],
        vec!["status", "--modbus", &addr],
    ] {
        let run = armjog(&args).await;
        assert_eq!(run.code, 3, "{args:?}: {}", run.stderr);
        assert!(
            run.stderr.contains("connection refused"),
            "{args:?}: {}",
            run.stderr
        );
        assert!(run.stderr.contains(&addr), "{args:?}: {}", run.stderr);
        assert!(!run.stderr.contains("os error"), "{args:?}: {}", run.stderr);
    }
}

/// An operator decoding `listens` and answering Get Speed in `replies`.
async fn operator(listens: Checksum, replies: Checksum) -> TestOperator {
    let script: common::Script = Arc::new(move |f: &TalosFrame| {
        let reply = Reply::GetSpeed {
            return_code: ReturnCode::OK,
            speed: 42,
        };
        vec![Action::Write(reply_bytes(&reply, f.id, replies))]
    });
    TestOperator::start(listens, script).await
}

#[tokio::test(flavor = "multi_thread")]
async fn a_silent_operator_hints_at_the_dialect_and_checksum() {
    let op = TestOperator::start(Checksum::Crc16, Arc::new(|_: &TalosFrame| Vec::new())).await;
    let run = armjog(&["send", "get-speed", "--talos", &op.addr, "--timeout", "300"]).await;
    assert_eq!(run.code, 3, "{}", run.stderr);
    for words in [
        "no reply from",
        op.addr.as_str(),
        "--dialect ack",
        "--checksum xor8|none",
    ] {
        assert!(
            run.stderr.contains(words),
            "lacks {words:?}: {}",
            run.stderr
        );
    }
}

#[tokio::test(flavor = "multi_thread")]
async fn an_xor8_reply_to_a_crc16_request_names_xor8() {
    // The reply is a byte short under crc16: it never completes and is given up.
    let op = operator(Checksum::Crc16, Checksum::Xor8).await;
    let run = armjog(&[
        "send",
        "get-speed",
        "--talos",
        &op.addr,
        "--timeout",
        "1000",
    ])
    .await;
    assert_eq!(run.code, 3, "{}", run.stderr);
    assert!(
        run.stderr
            .contains("checksum fails crc16 but fits xor8: try --checksum xor8"),
        "{}",
        run.stderr
    );
}

#[tokio::test(flavor = "multi_thread")]
async fn a_crc16_reply_to_an_xor8_request_names_crc16() {
    // The reply is a byte long under xor8: its checksum fails.
    let op = operator(Checksum::Xor8, Checksum::Crc16).await;
    let run = armjog(&[
        "send",
        "get-speed",
        "--talos",
        &op.addr,
        "--checksum",
        "xor8",
    ])
    .await;
    assert_eq!(run.code, 3, "{}", run.stderr);
    assert!(
        run.stderr
            .contains("checksum fails xor8 but fits crc16: try --checksum crc16"),
        "{}",
        run.stderr
    );
}
