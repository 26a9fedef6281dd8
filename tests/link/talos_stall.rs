//! A link whose operator stops reading, or stops talking, over an in-memory stream on tokio's
//! paused clock: a write that cannot complete within 500 ms ends the link, a full queue ends it
//! at once, and a link whose read side fails still writes the stop set.

use crate::common::{stop_set, wire};

use std::time::Duration;

use futures::StreamExt;
use tokio::io::{AsyncWriteExt, DuplexStream};
use tokio::sync::mpsc::UnboundedReceiver;
use tokio::time::Instant;
use tokio_util::codec::FramedRead;

use armjog::link::talos::{QUEUE_DEPTH, TalosEvent, WRITE_STALL};
use armjog::link::{Dialect, TalosConfig, TalosError, TalosLink};
use armjog::talos::frame::Decoded;
use armjog::talos::{Checksum, FrameCodec, Request, TalosFrame};

fn config(dialect: Dialect) -> TalosConfig {
    let mut config = TalosConfig::new("duplex");
    config.dialect = dialect;
    config.checksum = match dialect {
        Dialect::Icd => Checksum::Crc16,
        Dialect::Ack => Checksum::Xor8,
    };
    // Longer than the stall: a caller sees the link end, not its own timeout.
    config.request_timeout = Duration::from_secs(5);
    config
}

/// A link over a 64-byte stream whose far end is kept open and never read.
fn unread_link() -> (TalosLink, UnboundedReceiver<TalosEvent>, DuplexStream) {
    let (ours, theirs) = tokio::io::duplex(64);
    let (link, events) = TalosLink::over(ours, config(Dialect::Icd));
    (link, events, theirs)
}

/// A request bigger than the stream's buffer: its write cannot complete unread.
fn long_save(i: usize) -> Request {
    Request::SavePosition {
        name: format!("{i:03}{}", "p".repeat(200)),
        anchor: false,
        parent: String::new(),
    }
}

async fn disconnect_reason(events: &mut UnboundedReceiver<TalosEvent>) -> String {
    loop {
        match events.recv().await {
            Some(TalosEvent::Disconnected { reason }) => return reason,
            Some(_) => {}
            None => panic!("the link's events ended without a Disconnected"),
        }
    }
}

#[tokio::test(start_paused = true)]
async fn a_write_the_operator_never_reads_ends_the_link_after_500_ms() {
    let (link, mut events, _unread) = unread_link();
    let started = Instant::now();
    let pending = link.submit(long_save(0)).expect("queued at once");
    let reason = disconnect_reason(&mut events).await;
    assert_eq!(started.elapsed(), WRITE_STALL, "ended at the stall bound");
    assert_eq!(WRITE_STALL, Duration::from_millis(500));
    assert!(
        reason.contains("has not read for 500 ms (write stalled)"),
        "{reason}"
    );
    let err = pending
        .wait()
        .await
        .expect_err("the request fails with the link");
    assert!(
        matches!(&err, TalosError::Disconnected { reason } if reason.contains("write stalled")),
        "{err:?}"
    );
    assert_eq!(
        started.elapsed(),
        WRITE_STALL,
        "failed at once, not timed out"
    );
    let later = link.submit(Request::PolarPanStop);
    assert!(
        matches!(later, Err(TalosError::Disconnected { .. })),
        "{later:?}"
    );
}

#[tokio::test(start_paused = true)]
async fn a_full_queue_fails_at_once_and_ends_the_link() {
    let (link, mut events, _unread) = unread_link();
    let started = Instant::now();
    let mut queued = Vec::new();
    let refused = loop {
        match link.submit(long_save(queued.len())) {
            Ok(pending) => queued.push(pending),
            Err(e) => break e,
        }
        assert!(queued.len() <= QUEUE_DEPTH + 1, "the queue never filled");
    };
    assert!(queued.len() >= QUEUE_DEPTH, "{} queued", queued.len());
    assert!(
        matches!(&refused, TalosError::Disconnected { reason } if reason.contains("queued unsent")),
        "{refused:?}"
    );
    let reason = disconnect_reason(&mut events).await;
    assert!(reason.contains("queued unsent"), "{reason}");
    assert_eq!(
        started.elapsed(),
        Duration::ZERO,
        "no wait for the stall bound"
    );
    for pending in queued {
        let err = pending
            .wait()
            .await
            .expect_err("every queued request fails");
        assert!(matches!(err, TalosError::Disconnected { .. }), "{err:?}");
    }
    assert!(started.elapsed() < WRITE_STALL);
}

/// The operator's end: it reads every frame, and closes its own sending side on demand.
struct HalfClosingOperator {
    frames: FramedRead<tokio::io::ReadHalf<DuplexStream>, FrameCodec>,
    writes: tokio::io::WriteHalf<DuplexStream>,
}

impl HalfClosingOperator {
    async fn next_frame(&mut self) -> Option<TalosFrame> {
        match self.frames.next().await {
            Some(Ok(Decoded::TalosFrame(frame))) => Some(frame),
            None => None,
            other => panic!("expected a request frame, got {other:?}"),
        }
    }
}

fn half_closing_link(
    dialect: Dialect,
) -> (
    TalosLink,
    UnboundedReceiver<TalosEvent>,
    HalfClosingOperator,
) {
    let config = config(dialect);
    let checksum = config.checksum;
    let (ours, theirs) = tokio::io::duplex(4096);
    let (link, events) = TalosLink::over(ours, config);
    let (read, writes) = tokio::io::split(theirs);
    let operator = HalfClosingOperator {
        frames: FramedRead::new(read, FrameCodec::new(checksum)),
        writes,
    };
    (link, events, operator)
}

async fn failed_read_side_sends_the_stop_set(dialect: Dialect, motion: Request) {
    let (link, mut events, mut operator) = half_closing_link(dialect);
    let pending = link.submit(motion.clone()).expect("queued");
    let frame = operator.next_frame().await.expect("the motion");
    assert_eq!(frame.command, motion.command().request_value());
    // The operator stops talking but still listens: the link's reads end.
    operator.writes.shutdown().await.expect("half-close");
    let reason = disconnect_reason(&mut events).await;
    assert!(reason.contains("closed the connection"), "{reason}");
    assert!(pending.wait().await.is_err());
    let mut after = Vec::new();
    while let Some(frame) = operator.next_frame().await {
        after.push(frame);
    }
    assert_eq!(wire(&after), stop_set(dialect), "{dialect}");
    // The link, still held, takes nothing more.
    assert!(link.submit(Request::PolarPanStop).is_err());
}

#[tokio::test(start_paused = true)]
async fn a_link_whose_operator_stopped_answering_still_sends_the_icd_stop_set() {
    failed_read_side_sends_the_stop_set(Dialect::Icd, Request::Home { delay_ms: 0 }).await;
}

#[tokio::test(start_paused = true)]
async fn a_link_whose_operator_stopped_answering_still_sends_the_ack_stop_set() {
    let start = Request::PolarPanStart {
        moving_azimuth: 1,
        moving_altitude: 0,
    };
    failed_read_side_sends_the_stop_set(Dialect::Ack, start).await;
}

#[tokio::test(start_paused = true)]
async fn a_link_that_moved_nothing_sends_no_stop_when_its_read_side_fails() {
    let (link, mut events, mut operator) = half_closing_link(Dialect::Icd);
    let _pending = link.submit(Request::GetSpeed).expect("queued");
    assert!(operator.next_frame().await.is_some());
    operator.writes.shutdown().await.expect("half-close");
    disconnect_reason(&mut events).await;
    assert!(operator.next_frame().await.is_none(), "nothing after");
}
