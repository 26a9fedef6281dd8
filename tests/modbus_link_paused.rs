//! The Modbus link's timing over in-memory streams on tokio's paused clock: the read timeout
//! and the reconnect back-off, measured exactly with no real sleeps.

use std::sync::{Arc, Mutex};
use std::time::Duration;

use tokio::io::DuplexStream;
use tokio::time::Instant;

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
