//! Every path that stops the Talos side sends the same stop set, and it is the set written by
//! hand from the ICDs (`common::stop_set`): the STOP and QUICK STOP keys, the panic hook's
//! `StopHandle`, quit (a STOP, then the driver's exit), the driver's exit alone, and a dropped
//! link. (A failed link that can still write is in `talos_stall.rs`, on the paused clock.)
//! Real loopback sockets against the scripted operator, in both dialects.

use crate::common::{self, TestOperator, stop_set, wire};

use std::time::Duration;

use tokio::sync::mpsc::UnboundedReceiver;

use armjog::link::driver::{Driver, DriverConfig};
use armjog::link::interface::{ArmCommand, ArmEvent, LinkStatus};
use armjog::link::{Dialect, TalosConfig, TalosLink};
use armjog::talos::hardware::subcommand;
use armjog::talos::{Checksum, Request, TalosFrame};

/// How long the operator must stay quiet before the frames of one path are taken as complete.
const SETTLE: Duration = Duration::from_millis(400);

fn checksum(dialect: Dialect) -> Checksum {
    match dialect {
        Dialect::Icd => Checksum::Crc16,
        Dialect::Ack => Checksum::Xor8,
    }
}

async fn operator(dialect: Dialect) -> TestOperator {
    let script = match dialect {
        Dialect::Icd => common::answering(Checksum::Crc16),
        Dialect::Ack => common::acking(),
    };
    TestOperator::start(checksum(dialect), script).await
}

fn talos_config(addr: &str, dialect: Dialect) -> TalosConfig {
    let mut config = TalosConfig::new(addr);
    config.dialect = dialect;
    config.checksum = checksum(dialect);
    config
}

/// The telemetry polls of a Talos-only ICD link: not part of any stop.
fn is_poll(frame: &TalosFrame) -> bool {
    let sub = frame
        .payload
        .get(..2)
        .map(|b| u16::from_be_bytes([b[0], b[1]]));
    frame.command == 0x0008
        && matches!(
            sub,
            Some(subcommand::GET_ARM_STATE | subcommand::GET_ACTUATOR_FEEDBACK)
        )
}

/// The stop set `n` times over, as the wire carries it.
fn stop_sets(dialect: Dialect, n: usize) -> Vec<(u16, Vec<u8>)> {
    let set = stop_set(dialect);
    set.iter().cloned().cycle().take(n * set.len()).collect()
}

async fn frames_after(op: &mut TestOperator) -> Vec<TalosFrame> {
    let mut frames = op.frames_until_quiet(SETTLE).await;
    frames.retain(|f| !is_poll(f));
    frames
}

/// A driver on a Talos-only link, up, with the operator's connection traffic drained.
async fn driver_up(dialect: Dialect) -> (Driver, UnboundedReceiver<ArmEvent>, TestOperator) {
    let mut op = operator(dialect).await;
    let mut config = DriverConfig::new(Some(talos_config(&op.addr, dialect)), None);
    config.hw_telemetry_hz = 0.5;
    let (driver, mut events) = Driver::spawn(config);
    let up = tokio::time::timeout(Duration::from_secs(5), async {
        while let Some(event) = events.recv().await {
            if matches!(event, ArmEvent::Status(LinkStatus::Up { .. })) {
                return true;
            }
        }
        false
    })
    .await;
    assert_eq!(up, Ok(true), "the link came up");
    let connect = frames_after(&mut op).await;
    assert!(
        connect
            .iter()
            .all(|f| f.command == 0x0000 || f.command == 0x0009),
        "only the handshake and the speed read before any stop: {connect:?}"
    );
    (driver, events, op)
}

async fn key_path(dialect: Dialect, command: ArmCommand) -> Vec<TalosFrame> {
    let (driver, _events, mut op) = driver_up(dialect).await;
    assert!(driver.send(command));
    let frames = frames_after(&mut op).await;
    drop(driver);
    frames
}

#[tokio::test]
async fn the_stop_key_sends_the_stop_set() {
    for dialect in Dialect::ALL {
        let frames = key_path(dialect, ArmCommand::Stop).await;
        assert_eq!(wire(&frames), stop_set(dialect), "{dialect}");
    }
}

#[tokio::test]
async fn the_quick_stop_key_sends_the_stop_set() {
    for dialect in Dialect::ALL {
        let frames = key_path(dialect, ArmCommand::QuickStop).await;
        assert_eq!(wire(&frames), stop_set(dialect), "{dialect}");
    }
}

#[tokio::test]
async fn the_panic_hooks_stop_handle_sends_the_stop_set() {
    for dialect in Dialect::ALL {
        let (driver, _events, mut op) = driver_up(dialect).await;
        // What `install_panic_hook` calls.
        driver.stop_handle().stop();
        let frames = frames_after(&mut op).await;
        assert_eq!(wire(&frames), stop_set(dialect), "{dialect}");
    }
}

/// The console runs on one thread (`main.rs`): its panic hook asks for the stop and returns, the
/// panic ends at the console task's edge, and the driver, on that same thread, still carries
/// the stop set (a hook that waited in place would hold the only thread the driver has).
#[tokio::test(flavor = "current_thread")]
async fn a_task_panicking_on_the_drivers_thread_still_gets_the_stop_set_out() {
    for dialect in Dialect::ALL {
        let (driver, _events, mut op) = driver_up(dialect).await;
        let console = tokio::spawn(async move {
            // What the hook calls, before the panic unwinds through the task holding the driver.
            driver.stop_handle().stop();
            std::panic::resume_unwind(Box::new("the console's task panicked"));
        });
        let ended = console.await;
        assert!(ended.is_err_and(|e| e.is_panic()), "{dialect}");
        // The hook's stop, then the driver's exit (its last handle dropped in the unwinding),
        // which sends it twice.
        let frames = frames_after(&mut op).await;
        assert_eq!(wire(&frames), stop_sets(dialect, 3), "{dialect}");
    }
}

#[tokio::test]
async fn the_drivers_exit_sends_the_stop_set_twice_100_ms_apart() {
    for dialect in Dialect::ALL {
        let (driver, _events, mut op) = driver_up(dialect).await;
        let started = std::time::Instant::now();
        driver.shutdown().await;
        // The second set waits for the first's answers and then 100 ms: another console's jog
        // refresh that crossed the first has landed by then.
        assert!(
            started.elapsed() >= Duration::from_millis(100),
            "{dialect}: the exit took {:?}",
            started.elapsed()
        );
        let frames = frames_after(&mut op).await;
        assert_eq!(wire(&frames), stop_sets(dialect, 2), "{dialect}");
    }
}

#[tokio::test]
async fn quit_sends_the_stop_set_then_the_exit_sends_it_twice_more() {
    for dialect in Dialect::ALL {
        let (driver, _events, mut op) = driver_up(dialect).await;
        // As the console quits: a STOP, then the driver's shutdown.
        assert!(driver.send(ArmCommand::Stop));
        driver.shutdown().await;
        let frames = frames_after(&mut op).await;
        assert_eq!(wire(&frames), stop_sets(dialect, 3), "{dialect}");
    }
}

#[tokio::test]
async fn a_dropped_link_sends_the_stop_set() {
    for dialect in Dialect::ALL {
        let mut op = operator(dialect).await;
        let (link, _events) = TalosLink::connect(talos_config(&op.addr, dialect))
            .await
            .expect("connect");
        // A motion each dialect can carry: a discrete polar pan (0x0001).
        link.request(Request::PolarPan {
            delta_azimuth: 100,
            delta_altitude: 0,
            delay_ms: 0,
            time_ms: 0,
        })
        .await
        .expect("the pan is answered");
        assert_eq!(op.next_frame().await.command, 0x0001);
        drop(link);
        let frames = frames_after(&mut op).await;
        assert_eq!(wire(&frames), stop_set(dialect), "{dialect}");
    }
}
