//! The Modbus link's timing over in-memory streams on tokio's paused clock: the read timeout
//! and the reconnect back-off, measured exactly with no real sleeps.

use std::sync::{Arc, Mutex};
use std::time::Duration;

use tokio::io::{AsyncReadExt, AsyncWriteExt, DuplexStream};
use tokio::time::Instant;

use armjog::kortex::{ReferenceFrame, Twist};
use armjog::link::{ModbusConfig, ModbusError, ModbusEvent, ModbusLink};

fn config() -> ModbusConfig {
    let mut config = ModbusConfig::new("duplex");
    config.poll_rate_hz = None;
    config.request_timeout = Duration::from_millis(500);
    config.reconnect_delay = Duration::from_millis(100);
    config.reconnect_max_delay = Duration::from_secs(2);
    config
}

#[tokio::test(start_paused = true)]
async fn a_read_with_no_reply_times_out_at_exactly_the_request_timeout() {
    // The arm's end stays open but never answers.
    let arm_end: Arc<Mutex<Vec<DuplexStream>>> = Arc::default();
    let held = arm_end.clone();
    let (link, _events) = ModbusLink::connect_via(config(), move || {
        let (ours, theirs) = tokio::io::duplex(4096);
        held.lock().unwrap().push(theirs);
        async move { Ok(ours) }
    })
    .await
    .unwrap();
    let started = Instant::now();
    let err = link.read_telemetry().await.unwrap_err();
    assert_eq!(started.elapsed(), config().request_timeout);
    assert!(
        matches!(err, ModbusError::Timeout { after, .. } if after == config().request_timeout),
        "{err:?}"
    );
    assert!(err.breaks_connection());
}

#[tokio::test(start_paused = true)]
async fn a_lost_connection_is_retried_with_doubling_delays_up_to_the_cap() {
    let attempts: Arc<Mutex<Vec<Instant>>> = Arc::default();
    let seen = attempts.clone();
    let mut config = config();
    // Polling finds the loss.
    config.poll_rate_hz = Some(10.0);
    let (link, mut events) = ModbusLink::connect_via(config, move || {
        let mut seen = seen.lock().unwrap();
        let first = seen.is_empty();
        seen.push(Instant::now());
        async move {
            if first {
                // The arm's end closes at once: the first poll finds the connection gone.
                let (ours, _theirs) = tokio::io::duplex(4096);
                Ok(ours)
            } else {
                Err(std::io::Error::new(
                    std::io::ErrorKind::ConnectionRefused,
                    "the arm is not listening",
                ))
            }
        }
    })
    .await
    .unwrap();
    let lost_at = loop {
        match events.recv().await {
            Some(ModbusEvent::Disconnected { .. }) => break Instant::now(),
            Some(_) => continue,
            None => panic!("the link ended without reporting the loss"),
        }
    };
    tokio::time::sleep(Duration::from_secs(10)).await;
    // Jobs sent meanwhile are refused, never queued for after the reconnect.
    let refused = link.read_telemetry().await.unwrap_err();
    assert!(
        matches!(refused, ModbusError::Disconnected { .. }),
        "{refused:?}"
    );
    let attempts = attempts.lock().unwrap().clone();
    let retries: Vec<Duration> = attempts[1..].iter().map(|at| *at - lost_at).collect();
    let ms = Duration::from_millis;
    assert_eq!(
        &retries[..7],
        [
            ms(0),
            ms(100),
            ms(300),
            ms(700),
            ms(1500),
            ms(3100),
            ms(5100)
        ],
        "first retry at once, then 100 ms doubling, capped at 2 s"
    );
}

/// A register write the arm received: when, the first register, and the values.
type Received = (Instant, u16, Vec<u16>);

/// A minimal Modbus TCP arm on the far end of `stream`: answers reads with zeros, echoes
/// writes as accepted, and records every register write.
async fn answer_everything(mut stream: DuplexStream, writes: Arc<Mutex<Vec<Received>>>) {
    loop {
        let mut header = [0u8; 7];
        if stream.read_exact(&mut header).await.is_err() {
            return;
        }
        let len = u16::from_be_bytes([header[4], header[5]]) as usize;
        let mut pdu = vec![0u8; len - 1];
        if stream.read_exact(&mut pdu).await.is_err() {
            return;
        }
        let word = |at: usize| u16::from_be_bytes([pdu[at], pdu[at + 1]]);
        let reply: Vec<u8> = match pdu[0] {
            0x03 | 0x04 => {
                let count = word(3) as usize;
                let mut r = vec![pdu[0], (count * 2) as u8];
                r.resize(2 + count * 2, 0);
                r
            }
            0x01 | 0x02 => {
                let bytes = (word(3) as usize).div_ceil(8);
                let mut r = vec![pdu[0], bytes as u8];
                r.resize(2 + bytes, 0);
                r
            }
            0x10 => {
                let values = (0..word(3) as usize).map(|i| word(6 + 2 * i)).collect();
                writes
                    .lock()
                    .unwrap()
                    .push((Instant::now(), word(1), values));
                pdu[..5].to_vec()
            }
            0x06 => {
                writes
                    .lock()
                    .unwrap()
                    .push((Instant::now(), word(1), vec![word(3)]));
                pdu[..5].to_vec()
            }
            _ => pdu[..5].to_vec(),
        };
        let mut frame = header[..4].to_vec();
        frame.extend_from_slice(&((reply.len() + 1) as u16).to_be_bytes());
        frame.push(header[6]);
        frame.extend_from_slice(&reply);
        if stream.write_all(&frame).await.is_err() {
            return;
        }
    }
}

#[tokio::test(start_paused = true)]
async fn an_unrefreshed_twist_is_stopped_exactly_when_its_hold_runs_out() {
    let writes: Arc<Mutex<Vec<Received>>> = Arc::default();
    let recorded = writes.clone();
    let hold = Duration::from_millis(400);
    let mut config = config();
    config.twist_hold = Some(hold);
    let (link, _events) = ModbusLink::connect_via(config, move || {
        let (ours, theirs) = tokio::io::duplex(4096);
        tokio::spawn(answer_everything(theirs, recorded.clone()));
        async move { Ok(ours) }
    })
    .await
    .unwrap();
    let twist = Twist {
        x: 0.25,
        ..Twist::ZERO
    };
    link.jog_twist(ReferenceFrame::Base, twist).await.unwrap();
    let last_refresh = Instant::now();
    // Refreshing keeps it going past the first hold...
    for _ in 0..3 {
        tokio::time::sleep(Duration::from_millis(300)).await;
        link.jog_twist(ReferenceFrame::Base, twist).await.unwrap();
    }
    let refreshed_at = Instant::now();
    assert_eq!(refreshed_at - last_refresh, Duration::from_millis(900));
    let stop = |w: &Received| w.1 == 200 && w.2 == [2];
    assert!(
        !writes.lock().unwrap().iter().any(stop),
        "stopped while refreshed"
    );
    // ...and silence stops it, exactly one hold after the last refresh.
    tokio::time::sleep(Duration::from_secs(2)).await;
    let writes = writes.lock().unwrap().clone();
    let stops: Vec<Duration> = writes
        .iter()
        .filter(|w| stop(w))
        .map(|w| w.0 - refreshed_at)
        .collect();
    assert_eq!(stops, [hold], "{writes:?}");
}
