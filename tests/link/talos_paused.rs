//! The operator link's timing over an in-memory stream on tokio's paused clock: timeouts,
//! the ack dialect's STOP re-sends and late replies, measured exactly with no real sleeps.

use std::time::Duration;

use futures::StreamExt;
use tokio::io::{AsyncWriteExt, DuplexStream, ReadHalf, WriteHalf};
use tokio::time::Instant;
use tokio_util::codec::FramedRead;

use armjog::link::talos::{STOP_ACK_INTERVAL, STOP_ACK_TRIES, TalosEvent};
use armjog::link::{Answer, Dialect, TalosConfig, TalosError, TalosLink};
use armjog::talos::frame::Decoded;
use armjog::talos::{Checksum, CommandValue, FrameCodec, Reply, Request, ReturnCode, TalosFrame};

const TIMEOUT: Duration = Duration::from_millis(300);

/// The operator's end of the stream: frames the link wrote, and a writer for replies.
struct Operator {
    frames: FramedRead<ReadHalf<DuplexStream>, FrameCodec>,
    replies: WriteHalf<DuplexStream>,
    checksum: Checksum,
}

impl Operator {
    /// The next frame the link wrote, and when it arrived on the paused clock.
    async fn next_frame(&mut self) -> (Instant, TalosFrame) {
        match self.frames.next().await {
            Some(Ok(Decoded::TalosFrame(frame))) => (Instant::now(), frame),
            other => panic!("expected a request frame, got {other:?}"),
        }
    }

    async fn reply(&mut self, reply: &Reply, request_id: u32) {
        let bytes = reply
            .to_frame(request_id)
            .unwrap()
            .to_bytes(self.checksum)
            .unwrap();
        self.replies.write_all(&bytes).await.unwrap();
    }

    async fn ack(&mut self) {
        self.replies.write_all(b"ACK\0").await.unwrap();
    }
}

fn link(
    dialect: Dialect,
) -> (
    TalosLink,
    tokio::sync::mpsc::UnboundedReceiver<TalosEvent>,
    Operator,
) {
    let checksum = match dialect {
        Dialect::Icd => Checksum::Crc16,
        Dialect::Ack => Checksum::Xor8,
    };
    let mut config = TalosConfig::new("duplex");
    config.dialect = dialect;
    config.checksum = checksum;
    config.request_timeout = TIMEOUT;
    let (ours, theirs) = tokio::io::duplex(4096);
    let (link, events) = TalosLink::over(ours, config);
    let (read, write) = tokio::io::split(theirs);
    let operator = Operator {
        frames: FramedRead::new(read, FrameCodec::new(checksum)),
        replies: write,
        checksum,
    };
    (link, events, operator)
}

fn speed_reply(speed: u8) -> Reply {
    Reply::GetSpeed {
        return_code: ReturnCode::OK,
        speed,
    }
}

#[tokio::test(start_paused = true)]
async fn a_request_with_no_reply_times_out_at_exactly_its_timeout() {
    let (link, _events, mut operator) = link(Dialect::Icd);
    let started = Instant::now();
    let request = tokio::spawn(async move { link.request(Request::GetSpeed).await });
    let (sent_at, frame) = operator.next_frame().await;
    assert_eq!(sent_at, started, "written at once");
    assert_eq!(frame.id, 0);
    let err = request.await.unwrap().unwrap_err();
    assert_eq!(
        started.elapsed(),
        TIMEOUT,
        "gave up at its timeout, not before or after"
    );
    assert!(
        matches!(
            err,
            TalosError::Timeout {
                command: CommandValue::GetSpeed,
                id: 0,
                after: TIMEOUT,
            }
        ),
        "{err:?}"
    );
}

#[tokio::test(start_paused = true)]
async fn an_icd_reply_after_its_timeout_is_reported_late_and_answers_nothing_else() {
    let (link, mut events, mut operator) = link(Dialect::Icd);
    let first = {
        let link = link.clone();
        tokio::spawn(async move { link.request(Request::GetSpeed).await })
    };
    let (_, frame) = operator.next_frame().await;
    assert!(matches!(
        first.await.unwrap(),
        Err(TalosError::Timeout { .. })
    ));
    // The late reply comes just before the next request goes out.
    operator.reply(&speed_reply(1), frame.id).await;
    assert_eq!(
        events.recv().await,
        Some(TalosEvent::LateReply {
            id: 0,
            command: CommandValue::GetSpeed
        })
    );
    let second = tokio::spawn(async move { link.request(Request::GetSpeed).await });
    let (_, frame) = operator.next_frame().await;
    assert_eq!(frame.id, 2);
    operator.reply(&speed_reply(2), frame.id).await;
    let exchange = second.await.unwrap().unwrap();
    assert_eq!(exchange.id, 2);
    assert_eq!(exchange.answer, Answer::Reply(speed_reply(2)));
}

#[tokio::test(start_paused = true)]
async fn an_unacknowledged_stop_is_sent_three_times_150_ms_apart_then_fails() {
    let (link, mut events, mut operator) = link(Dialect::Ack);
    let started = Instant::now();
    let stop = tokio::spawn(async move { link.request(Request::PolarPanStop).await });
    let mut frames = Vec::new();
    for _ in 0..STOP_ACK_TRIES {
        let (at, frame) = operator.next_frame().await;
        frames.push((at - started, frame.command, frame.id));
    }
    let ms = Duration::from_millis;
    assert_eq!(
        frames,
        [
            (ms(0), 0x0004, 0),
            (ms(150), 0x0004, 2),
            (ms(300), 0x0004, 4)
        ],
        "three STOP frames, {STOP_ACK_INTERVAL:?} apart, each with its own id"
    );
    let err = stop.await.unwrap().unwrap_err();
    assert_eq!(started.elapsed(), STOP_ACK_INTERVAL * STOP_ACK_TRIES);
    assert!(
        matches!(
            err,
            TalosError::Timeout {
                command: CommandValue::PolarPanStop,
                ..
            }
        ),
        "{err:?}"
    );
    let mut expired = Vec::new();
    while let Ok(event) = events.try_recv() {
        if let TalosEvent::AckExpired { id, resent_as, .. } = event {
            expired.push((id, resent_as));
        }
    }
    assert_eq!(expired, [(0, Some(2)), (2, Some(4)), (4, None)]);
}

#[tokio::test(start_paused = true)]
async fn a_stop_acknowledged_on_its_second_frame_succeeds() {
    let (link, _events, mut operator) = link(Dialect::Ack);
    let started = Instant::now();
    let stop = tokio::spawn(async move { link.request(Request::PolarPanStop).await });
    let (_, first) = operator.next_frame().await;
    let (at, second) = operator.next_frame().await;
    assert_eq!((first.id, second.id), (0, 2));
    assert_eq!(at - started, STOP_ACK_INTERVAL);
    operator.ack().await;
    let exchange = stop.await.unwrap().unwrap();
    assert_eq!(exchange.id, 2, "answered by the re-sent frame's ACK");
    assert_eq!(exchange.answer, Answer::Ack);
}

#[tokio::test(start_paused = true)]
async fn a_late_ack_is_reported_late_and_the_next_stop_pairs_with_its_own() {
    let (link, mut events, mut operator) = link(Dialect::Ack);
    let start = {
        let link = link.clone();
        tokio::spawn(async move {
            link.request(Request::PolarPanStart {
                moving_azimuth: 1,
                moving_altitude: 0,
            })
            .await
        })
    };
    let (_, frame) = operator.next_frame().await;
    assert_eq!(frame.command, 0x0003);
    let err = start.await.unwrap().unwrap_err();
    assert!(matches!(err, TalosError::Timeout { .. }), "{err:?}");
    operator.ack().await;
    let late = loop {
        match events.recv().await {
            Some(TalosEvent::AckExpired { .. }) => continue,
            other => break other,
        }
    };
    assert_eq!(
        late,
        Some(TalosEvent::LateReply {
            id: 0,
            command: CommandValue::PolarPanStart
        })
    );
    let stop = tokio::spawn(async move { link.request(Request::PolarPanStop).await });
    let (_, frame) = operator.next_frame().await;
    assert_eq!(frame.id, 2);
    operator.ack().await;
    assert_eq!(stop.await.unwrap().unwrap().id, 2);
}
