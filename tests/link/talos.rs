//! The operator link against a scripted operator on loopback. Its exact timing (timeouts,
//! STOP re-sends, late replies) is tested on the paused clock in `talos_paused.rs`.

use crate::common;

use std::sync::Arc;
use std::time::Duration;

use armjog::link::talos::TalosEvent;
use armjog::link::{Answer, Dialect, TalosConfig, TalosError, TalosLink};
use armjog::talos::{Checksum, CommandValue, Reply, Request, ReturnCode, TalosFrame};
use common::{Action, TestOperator, answering, ok_reply, reply_bytes, stop_set, wire};

fn config(addr: &str, checksum: Checksum) -> TalosConfig {
    let mut c = TalosConfig::new(addr);
    c.checksum = checksum;
    c.request_timeout = Duration::from_millis(300);
    c
}

#[tokio::test]
async fn handshake_reports_the_operators_version_for_every_checksum() {
    for checksum in Checksum::ALL {
        let mut op = TestOperator::start(checksum, answering(checksum)).await;
        let (link, _events) = TalosLink::connect(config(&op.addr, checksum))
            .await
            .unwrap();
        assert_eq!(link.handshake(7).await.unwrap(), Some((1, 2)));
        let sent = op.next_frame().await;
        assert_eq!(sent.command, 0x0000);
        assert_eq!(sent.payload, [0x00, 0x07]);
    }
}

#[tokio::test]
async fn ids_are_even_and_increasing_and_replies_pair_out_of_order() {
    // The operator holds the first reply back and answers the second first.
    let held = Arc::new(std::sync::Mutex::new(Vec::<TalosFrame>::new()));
    let held2 = held.clone();
    let script: common::Script = Arc::new(move |f: &TalosFrame| {
        let mut held = held2.lock().unwrap();
        held.push(f.clone());
        if held.len() == 2 {
            held.iter()
                .rev()
                .map(|f| Action::Write(reply_bytes(&ok_reply(f), f.id, Checksum::Crc16)))
                .collect()
        } else {
            Vec::new()
        }
    });
    let op = TestOperator::start(Checksum::Crc16, script).await;
    let (link, _events) = TalosLink::connect(config(&op.addr, Checksum::Crc16))
        .await
        .unwrap();
    let (a, b) = tokio::join!(link.request(Request::GetSpeed), async {
        tokio::time::sleep(Duration::from_millis(20)).await;
        link.request(Request::Handshake { oid: Some(0) }).await
    });
    let (a, b) = (a.unwrap(), b.unwrap());
    assert_eq!(a.id, 0);
    assert_eq!(b.id, 2);
    assert!(matches!(
        a.answer,
        Answer::Reply(Reply::GetSpeed { speed: 42, .. })
    ));
    assert!(matches!(
        b.answer,
        Answer::Reply(Reply::Handshake {
            major_version: 1,
            ..
        })
    ));
    assert_eq!(
        held.lock()
            .unwrap()
            .iter()
            .map(|f| f.id)
            .collect::<Vec<_>>(),
        [0, 2]
    );
}

#[tokio::test]
async fn an_error_return_code_is_a_typed_error_carrying_the_reply() {
    let script: common::Script = Arc::new(|f: &TalosFrame| {
        let reply = Reply::error(CommandValue::GoToPosition, ReturnCode::UNKNOWN_POSITION);
        vec![Action::Write(reply_bytes(&reply, f.id, Checksum::Crc16))]
    });
    let op = TestOperator::start(Checksum::Crc16, script).await;
    let (link, _events) = TalosLink::connect(config(&op.addr, Checksum::Crc16))
        .await
        .unwrap();
    let err = link
        .request(Request::GoToPosition {
            name: "nowhere".into(),
        })
        .await
        .unwrap_err();
    let TalosError::ReturnCode { exchange } = &err else {
        panic!("expected ReturnCode, got {err:?}");
    };
    assert_eq!(exchange.return_code(), ReturnCode::UNKNOWN_POSITION);
    assert!(err.to_string().contains("UNKNOWN_POSITION"), "{err}");
}

#[tokio::test]
async fn a_corrupt_reply_fails_its_request_as_a_checksum_error() {
    let script: common::Script = Arc::new(|f: &TalosFrame| {
        let mut bytes = reply_bytes(&ok_reply(f), f.id, Checksum::Crc16);
        let last = bytes.len() - 1;
        bytes[last] ^= 0xFF;
        vec![Action::Write(bytes)]
    });
    let op = TestOperator::start(Checksum::Crc16, script).await;
    let (link, _events) = TalosLink::connect(config(&op.addr, Checksum::Crc16))
        .await
        .unwrap();
    let err = link.request(Request::GetSpeed).await.unwrap_err();
    assert!(matches!(err, TalosError::Checksum { id: 0, .. }), "{err:?}");
}

#[tokio::test]
async fn a_reply_to_an_unknown_id_is_reported_not_dropped() {
    let script: common::Script = Arc::new(|f: &TalosFrame| {
        let stray = Reply::error(CommandValue::GetSpeed, ReturnCode::OK);
        vec![
            Action::Write(reply_bytes(&stray, 1000, Checksum::Crc16)),
            Action::Write(reply_bytes(&ok_reply(f), f.id, Checksum::Crc16)),
        ]
    });
    let op = TestOperator::start(Checksum::Crc16, script).await;
    let (link, mut events) = TalosLink::connect(config(&op.addr, Checksum::Crc16))
        .await
        .unwrap();
    link.request(Request::GetSpeed).await.unwrap();
    let event = tokio::time::timeout(Duration::from_secs(1), events.recv())
        .await
        .unwrap();
    assert_eq!(
        event,
        Some(TalosEvent::UnpairedReply {
            id: 1001,
            command: 0x8009
        })
    );
}

#[tokio::test]
async fn a_dropped_connection_fails_the_pending_request_and_is_reported() {
    let op = TestOperator::start(
        Checksum::Crc16,
        Arc::new(|_: &TalosFrame| vec![Action::Close]),
    )
    .await;
    let (link, mut events) = TalosLink::connect(config(&op.addr, Checksum::Crc16))
        .await
        .unwrap();
    let err = link
        .request(Request::Home { delay_ms: 0 })
        .await
        .unwrap_err();
    assert!(matches!(err, TalosError::Disconnected { .. }), "{err:?}");
    let event = tokio::time::timeout(Duration::from_secs(1), events.recv())
        .await
        .unwrap();
    assert!(
        matches!(event, Some(TalosEvent::Disconnected { .. })),
        "{event:?}"
    );
    // Later requests fail at once.
    let err = link.request(Request::GetSpeed).await.unwrap_err();
    assert!(matches!(err, TalosError::Disconnected { .. }), "{err:?}");
}

#[tokio::test]
async fn connecting_to_a_closed_port_is_refused() {
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap().to_string();
    drop(listener);
    let err = TalosLink::connect(config(&addr, Checksum::Crc16))
        .await
        .unwrap_err();
    assert!(
        matches!(
            err,
            TalosError::Connect(armjog::net::ConnectError::Refused { .. })
        ),
        "{err:?}"
    );
}

#[tokio::test]
async fn ack_dialect_pairs_acks_in_order_and_refuses_typed_commands_locally() {
    let script: common::Script = Arc::new(|_: &TalosFrame| vec![Action::Write(b"ACK\0".to_vec())]);
    let mut op = TestOperator::start(Checksum::Xor8, script).await;
    let mut c = config(&op.addr, Checksum::Xor8);
    c.dialect = Dialect::Ack;
    let (link, _events) = TalosLink::connect(c).await.unwrap();
    let first = link.request(Request::PolarPanStart {
        moving_azimuth: 1,
        moving_altitude: 0,
    });
    let exchange = first.await.unwrap();
    assert_eq!(exchange.answer, Answer::Ack);
    assert_eq!(exchange.reply_bytes, b"ACK\0");
    assert_eq!(link.handshake(0).await.unwrap(), None);
    let err = link.request(Request::GetSpeed).await.unwrap_err();
    assert!(matches!(
        err,
        TalosError::NotInDialect {
            command: CommandValue::GetSpeed
        }
    ));
    assert!(err.to_string().contains("ack dialect"), "{err}");
    // Only the two supported commands reached the operator.
    assert_eq!(op.next_frame().await.command, 0x0003);
    assert_eq!(op.next_frame().await.command, 0x0000);
    assert!(
        tokio::time::timeout(Duration::from_millis(100), op.received.recv())
            .await
            .is_err(),
        "get_speed must not be sent"
    );
}

#[tokio::test]
async fn dropping_the_link_mid_motion_sends_the_whole_stop_set() {
    let mut op = TestOperator::start(Checksum::Crc16, answering(Checksum::Crc16)).await;
    let (link, _events) = TalosLink::connect(config(&op.addr, Checksum::Crc16))
        .await
        .unwrap();
    link.request(Request::CartesianMoveStart {
        moving_x: 1,
        moving_y: 0,
        moving_z: -1,
    })
    .await
    .unwrap();
    assert_eq!(op.next_frame().await.command, 0x0006);
    drop(link);
    let stops = op.frames_until_quiet(Duration::from_millis(300)).await;
    assert_eq!(
        wire(&stops),
        stop_set(Dialect::Icd),
        "the stop set follows the drop"
    );
    assert!(stops.iter().all(|f| f.id % 2 == 0));
}

#[tokio::test]
async fn dropping_the_link_after_a_partial_stop_sends_the_whole_set() {
    // A discrete step and a polar STOP: the polar STOP alone stops nothing the step started.
    let mut op = TestOperator::start(Checksum::Crc16, answering(Checksum::Crc16)).await;
    let (link, _events) = TalosLink::connect(config(&op.addr, Checksum::Crc16))
        .await
        .unwrap();
    for request in [
        Request::CartesianMove {
            delta_x: 10,
            delta_y: 0,
            delta_z: 0,
            delay_ms: 0,
            time_ms: 0,
        },
        Request::PolarPanStop,
    ] {
        link.request(request).await.unwrap();
    }
    assert_eq!(op.next_frame().await.command, 0x0005);
    assert_eq!(op.next_frame().await.command, 0x0004);
    drop(link);
    let stops = op.frames_until_quiet(Duration::from_millis(300)).await;
    assert_eq!(wire(&stops), stop_set(Dialect::Icd));
}

#[tokio::test]
async fn dropping_a_link_stopped_in_full_sends_nothing() {
    let mut op = TestOperator::start(Checksum::Crc16, answering(Checksum::Crc16)).await;
    let (link, _events) = TalosLink::connect(config(&op.addr, Checksum::Crc16))
        .await
        .unwrap();
    link.request(Request::PolarPanStart {
        moving_azimuth: 1,
        moving_altitude: 0,
    })
    .await
    .unwrap();
    let stop_all_joints = Request::HardwareOperation {
        subcommand: 0x0004,
        reserved: 0,
        payload: Vec::new(),
    };
    for stop in [
        Request::CartesianMoveStop,
        Request::PolarPanStop,
        stop_all_joints,
    ] {
        link.request(stop).await.unwrap();
    }
    let sent = op.frames_until_quiet(Duration::from_millis(200)).await;
    assert_eq!(sent.len(), 4);
    drop(link);
    assert_nothing_more(&mut op).await;
}

#[tokio::test]
async fn dropping_an_idle_link_sends_nothing() {
    let mut op = TestOperator::start(Checksum::Crc16, answering(Checksum::Crc16)).await;
    let (link, _events) = TalosLink::connect(config(&op.addr, Checksum::Crc16))
        .await
        .unwrap();
    link.request(Request::GetSpeed).await.unwrap();
    assert_eq!(op.next_frame().await.command, 0x0009);
    drop(link);
    assert_nothing_more(&mut op).await;
}

#[tokio::test]
async fn a_start_submitted_behind_a_request_keeps_its_place_and_a_drop_before_its_write_stops_it() {
    let mut op = TestOperator::start(Checksum::Crc16, answering(Checksum::Crc16)).await;
    let (link, _events) = TalosLink::connect(config(&op.addr, Checksum::Crc16))
        .await
        .unwrap();
    let start = Request::PolarPanStart {
        moving_azimuth: 1,
        moving_altitude: 0,
    };
    // Both submitted before the link's task has run; every caller gone before it writes them.
    let speed = link.submit(Request::GetSpeed).unwrap();
    let moving = link.submit(start.clone()).unwrap();
    drop((speed, moving, link));
    let sent = op.frames_until_quiet(Duration::from_millis(300)).await;
    let mut expected = wire(&[
        Request::GetSpeed.to_frame(0).unwrap(),
        start.to_frame(2).unwrap(),
    ]);
    expected.extend(stop_set(Dialect::Icd));
    assert_eq!(
        wire(&sent),
        expected,
        "in the order submitted, then the stop set"
    );
    assert_eq!(sent[0].id, 0);
    assert_eq!(sent[1].id, 2);
}

#[tokio::test]
async fn an_invalid_request_is_refused_before_sending_with_the_field_named() {
    let mut op = TestOperator::start(Checksum::Crc16, answering(Checksum::Crc16)).await;
    let (link, _events) = TalosLink::connect(config(&op.addr, Checksum::Crc16))
        .await
        .unwrap();
    let err = link
        .request(Request::CartesianMoveStart {
            moving_x: 0,
            moving_y: 2,
            moving_z: 0,
        })
        .await
        .unwrap_err();
    assert!(err.to_string().contains("moving_y"), "{err}");
    assert!(
        tokio::time::timeout(Duration::from_millis(100), op.received.recv())
            .await
            .is_err()
    );
}

/// An ack-dialect operator that answers every frame with "ACK\0" except those `drop` picks
/// (by the frame's position in the connection, from 0, and the frame).
fn acking_except(
    drop: impl Fn(usize, &TalosFrame) -> bool + Send + Sync + 'static,
) -> common::Script {
    let seen = Arc::new(std::sync::atomic::AtomicUsize::new(0));
    Arc::new(move |f: &TalosFrame| {
        let n = seen.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
        if drop(n, f) {
            Vec::new()
        } else {
            vec![Action::Write(b"ACK\0".to_vec())]
        }
    })
}

fn ack_config(addr: &str) -> TalosConfig {
    let mut c = config(addr, Checksum::Xor8);
    c.dialect = Dialect::Ack;
    c
}

const POLAR_START: Request = Request::PolarPanStart {
    moving_azimuth: 1,
    moving_altitude: 0,
};

/// Every frame the operator received so far, waiting `settle` for stragglers.
#[tokio::test]
async fn ack_dialect_one_lost_ack_during_refreshes_does_not_fail_the_final_stop() {
    // The second START's ACK is lost while STARTs are refreshed every 100 ms: every later ACK
    // pairs one request early, so the STOP's own ACK is taken by the last START.
    let mut op = TestOperator::start(Checksum::Xor8, acking_except(|n, _| n == 1)).await;
    let (link, _events) = TalosLink::connect(ack_config(&op.addr)).await.unwrap();
    let mut starts = Vec::new();
    for _ in 0..5 {
        starts.push(link.submit(POLAR_START).unwrap());
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
    let stop = link.request(Request::PolarPanStop).await;
    assert!(stop.is_ok(), "the operator acknowledged the STOP: {stop:?}");
    let frames = op.frames_until_quiet(Duration::from_millis(300)).await;
    let stops = frames.iter().filter(|f| f.command == 0x0004).count();
    assert!(
        (1..=2).contains(&stops),
        "at most one re-send: {stops} STOP frames"
    );
    drop(starts);
}

#[tokio::test]
async fn ack_dialect_an_expired_request_leaves_the_queue_so_the_next_stop_pairs_first_time() {
    let mut op = TestOperator::start(Checksum::Xor8, acking_except(|n, _| n == 0)).await;
    let (link, mut events) = TalosLink::connect(ack_config(&op.addr)).await.unwrap();
    let start = link.submit(POLAR_START).unwrap();
    let err = start.wait().await.unwrap_err();
    assert!(
        matches!(
            err,
            TalosError::Timeout {
                command: CommandValue::PolarPanStart,
                id: 0,
                ..
            }
        ),
        "{err:?}"
    );
    let stop = link.request(Request::PolarPanStop).await.unwrap();
    assert_eq!(stop.id, 2, "the STOP's own ACK answered it");
    assert!(
        stop.latency < Duration::from_millis(150),
        "{:?}",
        stop.latency
    );
    let frames = op.frames_until_quiet(Duration::from_millis(300)).await;
    assert_eq!(
        frames.iter().map(|f| f.command).collect::<Vec<_>>(),
        [0x0003, 0x0004],
        "no re-send was needed"
    );
    let event = tokio::time::timeout(Duration::from_secs(1), events.recv()).await;
    assert!(
        matches!(
            event,
            Ok(Some(TalosEvent::AckExpired {
                id: 0,
                resent_as: None,
                ..
            }))
        ),
        "{event:?}"
    );
}

/// Nothing more reaches the operator within 150 ms (the link closes, or stays quiet).
async fn assert_nothing_more(op: &mut TestOperator) {
    assert!(
        tokio::time::timeout(Duration::from_millis(150), op.received.recv())
            .await
            .map(|item| item.is_none())
            .unwrap_or(true),
        "a frame after the link was dropped"
    );
}
