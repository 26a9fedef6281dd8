//! The first exchange with an operator that speaks another checksum or dialect: the error names
//! the checksum its reply fits, or the options to try, in the link's words and on the console's
//! link line (the driver's Down reason).

use crate::common;

use std::sync::Arc;
use std::time::Duration;

use tokio::io::AsyncWriteExt;
use tokio::sync::mpsc;

use armjog::link::driver::{Driver, DriverConfig};
use armjog::link::interface::{ArmEvent, LinkStatus};
use armjog::link::talos::{first_exchange_error, wait_for_checksum_fit};
use armjog::link::{TalosConfig, TalosError, TalosLink};
use armjog::talos::{Checksum, Reply, ReturnCode, TalosFrame};
use common::{Action, TestOperator, reply_bytes};

fn handshake_reply() -> Reply {
    Reply::Handshake {
        return_code: ReturnCode::OK,
        major_version: 1,
        minor_version: 0,
    }
}

#[tokio::test(start_paused = true)]
async fn a_reply_given_up_after_the_timeout_still_names_its_checksum() {
    let (ours, mut theirs) = tokio::io::duplex(4096);
    let config = TalosConfig::new("duplex");
    assert!(
        config.frame_deadline > config.request_timeout,
        "the case this covers: the reply is given up only after the request timed out"
    );
    let (link, mut events) = TalosLink::over(ours, config.clone());
    let pending = link
        .submit(armjog::talos::Request::Handshake { oid: Some(0) })
        .expect("submitted");
    // An xor8 reply is a byte short under crc16: it never completes.
    let reply = reply_bytes(&handshake_reply(), pending.id(), Checksum::Xor8);
    theirs.write_all(&reply).await.expect("reply");
    let err = pending.wait().await.expect_err("never completes");
    assert!(matches!(err, TalosError::Timeout { .. }), "{err:?}");
    let fit = wait_for_checksum_fit(&mut events, config.frame_deadline)
        .await
        .expect("the given-up reply fits xor8");
    assert_eq!((fit.used, fit.fits), (Checksum::Crc16, Checksum::Xor8));
    let words = first_exchange_error(&err, &config, Some(fit));
    assert!(words.contains("no reply from duplex"), "{words}");
    assert!(
        words.contains("checksum fails crc16 but fits xor8: try --checksum xor8"),
        "{words}"
    );
    drop(theirs);
}

#[tokio::test(start_paused = true)]
async fn nothing_decodable_gives_no_checksum_and_the_hint_lists_the_options() {
    let (ours, theirs) = tokio::io::duplex(4096);
    let config = TalosConfig::new("duplex");
    let (link, mut events) = TalosLink::over(ours, config.clone());
    let err = link.handshake(0).await.expect_err("silent operator");
    assert_eq!(
        wait_for_checksum_fit(&mut events, config.frame_deadline).await,
        None
    );
    let words = first_exchange_error(&err, &config, None);
    for part in [
        "no reply from duplex within 500ms",
        "(now --dialect icd --checksum crc16)",
        "try --dialect ack or --checksum xor8|none",
    ] {
        assert!(words.contains(part), "lacks {part:?}: {words}");
    }
    drop(theirs);
}

/// The reason of the first Down status the driver reports.
async fn down_reason(events: &mut mpsc::UnboundedReceiver<ArmEvent>) -> String {
    // Generous: the handshake's timeout and the frame deadline on a loaded machine.
    let within = Duration::from_secs(20);
    let until = tokio::time::Instant::now() + within;
    loop {
        match tokio::time::timeout_at(until, events.recv()).await {
            Ok(Some(ArmEvent::Status(LinkStatus::Down { reason }))) => return reason,
            Ok(Some(_)) => {}
            Ok(None) => panic!("the driver ended"),
            Err(_) => panic!("no Down status within {within:?}"),
        }
    }
}

#[tokio::test]
async fn the_console_link_line_names_the_checksum_the_operator_speaks() {
    let script: common::Script = Arc::new(|f: &TalosFrame| {
        vec![Action::Write(reply_bytes(
            &handshake_reply(),
            f.id,
            Checksum::Xor8,
        ))]
    });
    let op = TestOperator::start(Checksum::Crc16, script).await;
    let (_driver, mut events) =
        Driver::spawn(DriverConfig::new(Some(TalosConfig::new(&op.addr)), None));
    let reason = down_reason(&mut events).await;
    assert!(reason.starts_with("talos handshake: "), "{reason}");
    assert!(reason.contains(&op.addr), "{reason}");
    assert!(reason.contains("try --checksum xor8"), "{reason}");
}

#[tokio::test]
async fn the_console_link_line_hints_at_the_options_for_a_silent_operator() {
    let op = TestOperator::start(Checksum::Crc16, Arc::new(|_: &TalosFrame| Vec::new())).await;
    let (_driver, mut events) =
        Driver::spawn(DriverConfig::new(Some(TalosConfig::new(&op.addr)), None));
    let reason = down_reason(&mut events).await;
    assert!(
        reason.contains("try --dialect ack or --checksum"),
        "{reason}"
    );
}
