//! The stop set written ahead (`StopAhead`): armed by the link once it owes one, written whole
//! by someone else between the link's writes, and then the link's own: its replies pair with it,
//! an ack-dialect STOP without its ACK is sent again, and the link owes no stop after it.

use std::time::Duration;

use armjog::link::talos::{AheadOutcome, StopAhead};
use armjog::link::{Answer, Dialect, TalosConfig, TalosEvent, TalosLink};
use armjog::talos::{Checksum, Request};

use crate::common::{self, Action, TestOperator, answering, stop_set, wire};

const POLAR_START: Request = Request::PolarPanStart {
    moving_azimuth: 1,
    moving_altitude: 0,
};

fn config(addr: &str, dialect: Dialect, ahead: &StopAhead) -> TalosConfig {
    let mut c = TalosConfig::new(addr);
    c.dialect = dialect;
    c.checksum = match dialect {
        Dialect::Icd => Checksum::Crc16,
        Dialect::Ack => Checksum::Xor8,
    };
    c.request_timeout = Duration::from_millis(300);
    c.stop_ahead = Some(ahead.clone());
    c
}

/// An operator that ACKs every frame but the `n`th (from 0).
fn acking_except(skip: usize) -> common::Script {
    let seen = std::sync::Arc::new(std::sync::atomic::AtomicUsize::new(0));
    std::sync::Arc::new(move |_: &armjog::talos::TalosFrame| {
        let n = seen.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
        match n == skip {
            true => Vec::new(),
            false => vec![Action::Write(b"ACK\0".to_vec())],
        }
    })
}

#[tokio::test]
async fn icd_the_set_is_armed_by_a_start_written_once_and_its_replies_are_the_links() {
    let ahead = StopAhead::new();
    let mut op = TestOperator::start(Checksum::Crc16, answering(Checksum::Crc16)).await;
    let (link, mut events) = TalosLink::connect(config(&op.addr, Dialect::Icd, &ahead))
        .await
        .expect("connect");
    assert_eq!(
        ahead.write_now(),
        AheadOutcome::NothingOwed,
        "nothing moved"
    );
    let start = link.request(POLAR_START).await.expect("start");
    assert_eq!(op.next_frame().await.id, start.id);

    assert_eq!(ahead.write_now(), AheadOutcome::Written);
    let written = [
        op.next_frame().await,
        op.next_frame().await,
        op.next_frame().await,
    ];
    assert_eq!(wire(&written), stop_set(Dialect::Icd));
    let mut ids: Vec<u32> = written.iter().map(|f| f.id).collect();
    assert!(
        ids.iter().all(|id| id % 2 == 0 && *id != start.id),
        "{ids:?}"
    );
    ids.dedup();
    assert_eq!(ids.len(), 3, "an id each");
    assert_eq!(ahead.write_now(), AheadOutcome::NothingOwed, "written once");

    // The link goes on; the replies to the set came before this one's and paired with it.
    let speed = link.request(Request::GetSpeed).await.expect("get speed");
    assert!(matches!(speed.answer, Answer::Reply(_)));
    assert!(ids.iter().all(|id| *id != speed.id), "ids never reused");
    assert_eq!(op.next_frame().await.id, speed.id);
    assert!(
        events.try_recv().is_err(),
        "no unpaired or late reply: the set was the link's"
    );
    // Stopped by the set: a link dropped now owes the arm nothing.
    drop(link);
    let after = op.frames_until_quiet(Duration::from_millis(300)).await;
    assert!(after.is_empty(), "{:?}", wire(&after));
    assert_eq!(ahead.write_now(), AheadOutcome::NoLink, "the link ended");
}

#[tokio::test]
async fn ack_dialect_the_set_written_ahead_takes_its_place_in_the_ack_order() {
    let ahead = StopAhead::new();
    let mut op = TestOperator::start(Checksum::Xor8, acking_except(usize::MAX)).await;
    let (link, mut events) = TalosLink::connect(config(&op.addr, Dialect::Ack, &ahead))
        .await
        .expect("connect");
    link.request(POLAR_START).await.expect("start");
    op.next_frame().await;
    assert_eq!(ahead.write_now(), AheadOutcome::Written);
    assert_eq!(wire(&[op.next_frame().await]), stop_set(Dialect::Ack));
    // The next request's ACK is its own: the STOP's came first and was the STOP's.
    let start = link.request(POLAR_START).await.expect("start again");
    assert_eq!(start.answer, Answer::Ack);
    tokio::time::sleep(Duration::from_millis(50)).await;
    let unexpected: Vec<TalosEvent> = std::iter::from_fn(|| events.try_recv().ok()).collect();
    assert!(unexpected.is_empty(), "{unexpected:?}");
    // Moving again: armed again.
    assert_eq!(ahead.write_now(), AheadOutcome::Written);
}

#[tokio::test]
async fn ack_dialect_a_stop_written_ahead_without_its_ack_is_sent_again() {
    let ahead = StopAhead::new();
    // Frame 0 is the START, frame 1 the STOP written ahead: its ACK is lost.
    let mut op = TestOperator::start(Checksum::Xor8, acking_except(1)).await;
    let (link, _events) = TalosLink::connect(config(&op.addr, Dialect::Ack, &ahead))
        .await
        .expect("connect");
    link.request(POLAR_START).await.expect("start");
    op.next_frame().await;
    assert_eq!(ahead.write_now(), AheadOutcome::Written);
    let first = op.next_frame().await;
    let again = op.next_frame().await;
    assert_eq!(wire(std::slice::from_ref(&first)), stop_set(Dialect::Ack));
    assert_eq!(
        wire(std::slice::from_ref(&again)),
        stop_set(Dialect::Ack),
        "sent again"
    );
    assert_ne!(first.id, again.id);
    drop(link);
}

#[tokio::test]
async fn a_link_over_any_transport_but_tcp_writes_nothing_ahead() {
    let ahead = StopAhead::new();
    let (console, _operator) = tokio::io::duplex(4096);
    let (link, _events) = TalosLink::over(console, config("memory", Dialect::Icd, &ahead));
    let _ = link.submit(POLAR_START);
    tokio::time::sleep(Duration::from_millis(20)).await;
    assert_eq!(ahead.write_now(), AheadOutcome::NoLink);
}

/// The frames the operator (on a runtime of its own) has read within `wait`, taken without
/// yielding: the caller's thread stays blocked meanwhile, so its link task cannot run.
fn received_blocking(op: &mut TestOperator, wait: Duration) -> Vec<armjog::talos::TalosFrame> {
    let until = std::time::Instant::now() + wait;
    let mut frames = Vec::new();
    while std::time::Instant::now() < until {
        while let Ok(item) = op.received.try_recv() {
            if let armjog::talos::frame::Decoded::TalosFrame(frame) = item {
                frames.push(frame);
            }
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    frames
}

/// An operator served from a runtime of its own, and a current-thread runtime for the link:
/// blocking the latter's thread keeps the link task from running, not the operator.
/// An ICD link to `op` with a stop-ahead slot attached, as the console has it.
async fn ahead_link(
    op: &TestOperator,
) -> (
    StopAhead,
    TalosLink,
    tokio::sync::mpsc::UnboundedReceiver<TalosEvent>,
) {
    let ahead = StopAhead::new();
    let (link, events) = TalosLink::connect(config(&op.addr, Dialect::Icd, &ahead))
        .await
        .expect("connect");
    (ahead, link, events)
}

fn apart(
    checksum: Checksum,
) -> (
    tokio::runtime::Runtime,
    TestOperator,
    tokio::runtime::Runtime,
) {
    let operator_side = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(1)
        .enable_all()
        .build()
        .expect("operator runtime");
    let op = operator_side.block_on(TestOperator::start(checksum, answering(checksum)));
    let console_side = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .expect("console runtime");
    (operator_side, op, console_side)
}

#[test]
fn a_start_on_a_quiet_link_is_written_in_the_callers_turn_and_answered_to_it() {
    let (_operator_side, mut op, console_side) = apart(Checksum::Crc16);
    console_side.block_on(async {
        let (ahead, link, mut events) = ahead_link(&op).await;
        let start = link.submit(POLAR_START).expect("submitted");
        let id = start.id();
        let read = received_blocking(&mut op, Duration::from_millis(300));
        assert_eq!(
            wire(&read),
            wire(&[frame_of(POLAR_START, id)]),
            "on the wire before the link task ran"
        );
        let exchange = start.wait().await.expect("answered");
        assert_eq!(exchange.id, id);
        assert!(matches!(exchange.answer, Answer::Reply(_)));
        // The link owes the stop set now, as after any START.
        assert_eq!(ahead.write_now(), AheadOutcome::Written);
        tokio::time::sleep(Duration::from_millis(50)).await;
        assert!(events.try_recv().is_err(), "no late or unpaired reply");
    });
}

#[test]
fn a_start_behind_a_queued_request_keeps_its_place() {
    let (_operator_side, mut op, console_side) = apart(Checksum::Crc16);
    console_side.block_on(async {
        let (_ahead, link, _events) = ahead_link(&op).await;
        let speed = link.submit(Request::GetSpeed).expect("submitted");
        let start = link.submit(POLAR_START).expect("submitted");
        assert!(
            received_blocking(&mut op, Duration::from_millis(150)).is_empty(),
            "the START did not overtake the queued request"
        );
        speed.wait().await.expect("speed answered");
        start.wait().await.expect("start answered");
        let read = [op.next_frame().await, op.next_frame().await];
        assert_eq!(
            read.iter()
                .map(|f| Request::from_frame(f).expect("request"))
                .collect::<Vec<_>>(),
            [Request::GetSpeed, POLAR_START]
        );
    });
}

/// `request`'s frame as the link writes it, with `id`.
fn frame_of(request: Request, id: u32) -> armjog::talos::TalosFrame {
    request.to_frame(id).expect("frame")
}

#[test]
fn a_start_written_through_and_then_dropped_with_the_link_is_stopped() {
    let (_operator_side, mut op, console_side) = apart(Checksum::Crc16);
    console_side.block_on(async {
        let (_ahead, link, _events) = ahead_link(&op).await;
        let start = link.submit(POLAR_START).expect("submitted");
        // Every caller gone before the link task saw the START: it still owes the stop set.
        drop(start);
        drop(link);
        let read = op.frames_until_quiet(Duration::from_millis(300)).await;
        let mut expected = wire(&[frame_of(POLAR_START, 0)]);
        expected.extend(stop_set(Dialect::Icd));
        assert_eq!(wire(&read), expected);
    });
}
