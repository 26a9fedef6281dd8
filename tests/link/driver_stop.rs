//! The arm driver's STOP never waits behind a connect: with the Talos operator stalled in its
//! handshake, a STOP reaches the Modbus arm at once; links unreachable at start are retried.
//! Real loopback sockets; the Modbus arm is a small recording server that timestamps every
//! write as it arrives.

use crate::common;

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::mpsc;

use armjog::link::driver::{Driver, DriverConfig};
use armjog::link::interface::{ArmCommand, ArmEvent, CommandKind, LinkStatus};
use armjog::link::{Dialect, ModbusConfig, TalosConfig};
use armjog::talos::{Checksum, TalosFrame};
use common::{Action, TestOperator};

/// The Kinova action command register: 2 is STOP.
const ACTION_REGISTER: u16 = 200;
const ACTION_STOP: u16 = 2;

/// One holding-register write as it reached the arm.
#[derive(Debug)]
pub(crate) struct RegisterWrite {
    at: Instant,
    address: u16,
    values: Vec<u16>,
}

/// A Modbus TCP server that answers every read with zeros and every write with its echo, and
/// reports each register write with the time it arrived.
pub(crate) async fn recording_arm(listener: TcpListener) -> mpsc::UnboundedReceiver<RegisterWrite> {
    let (tx, rx) = mpsc::unbounded_channel();
    tokio::spawn(async move {
        while let Ok((stream, _)) = listener.accept().await {
            tokio::spawn(serve_modbus(stream, tx.clone()));
        }
    });
    rx
}

async fn serve_modbus(mut stream: TcpStream, writes: mpsc::UnboundedSender<RegisterWrite>) {
    let _ = stream.set_nodelay(true);
    loop {
        let mut header = [0u8; 7];
        if stream.read_exact(&mut header).await.is_err() {
            return;
        }
        let length = usize::from(u16::from_be_bytes([header[4], header[5]]));
        let mut pdu = vec![0u8; length.saturating_sub(1)];
        if stream.read_exact(&mut pdu).await.is_err() {
            return;
        }
        let at = Instant::now();
        let word = |i: usize| u16::from_be_bytes([pdu[i], pdu[i + 1]]);
        let function = pdu[0];
        let reply: Vec<u8> = match function {
            // Read coils / discrete inputs: all off.
            0x01 | 0x02 => {
                let bytes = word(3).div_ceil(8) as u8;
                let mut r = vec![function, bytes];
                r.resize(2 + usize::from(bytes), 0);
                r
            }
            // Read holding / input registers: all zero.
            0x03 | 0x04 => {
                let bytes = (word(3) * 2) as u8;
                let mut r = vec![function, bytes];
                r.resize(2 + usize::from(bytes), 0);
                r
            }
            0x06 => {
                let _ = writes.send(RegisterWrite {
                    at,
                    address: word(1),
                    values: vec![word(3)],
                });
                pdu[..5].to_vec()
            }
            0x10 => {
                let count = usize::from(word(3));
                let values = (0..count).map(|i| word(6 + 2 * i)).collect();
                let _ = writes.send(RegisterWrite {
                    at,
                    address: word(1),
                    values,
                });
                pdu[..5].to_vec()
            }
            // Coil writes: echo.
            0x05 | 0x0F => pdu[..5].to_vec(),
            other => vec![other | 0x80, 0x01],
        };
        let mut frame = header.to_vec();
        frame[4..6].copy_from_slice(&((reply.len() + 1) as u16).to_be_bytes());
        frame.extend_from_slice(&reply);
        if stream.write_all(&frame).await.is_err() {
            return;
        }
    }
}

/// A Talos "operator" that accepts connections and never answers: the handshake stalls.
async fn stalled_operator() -> (String, Arc<AtomicUsize>) {
    let listener = TcpListener::bind("127.0.0.1:0").await.expect("bind");
    let addr = listener.local_addr().expect("addr").to_string();
    let bytes_in = Arc::new(AtomicUsize::new(0));
    let counter = bytes_in.clone();
    tokio::spawn(async move {
        while let Ok((mut stream, _)) = listener.accept().await {
            let counter = counter.clone();
            tokio::spawn(async move {
                let mut buf = [0u8; 256];
                while let Ok(n @ 1..) = stream.read(&mut buf).await {
                    counter.fetch_add(n, Ordering::SeqCst);
                }
            });
        }
    });
    (addr, bytes_in)
}

/// Waits for the first event `pick` accepts; panics after `within`.
pub(crate) async fn wait_for<T>(
    events: &mut mpsc::UnboundedReceiver<ArmEvent>,
    within: Duration,
    what: &str,
    mut pick: impl FnMut(&ArmEvent) -> Option<T>,
) -> T {
    let until = tokio::time::Instant::now() + within;
    loop {
        match tokio::time::timeout_at(until, events.recv()).await {
            Ok(Some(event)) => {
                if let Some(found) = pick(&event) {
                    return found;
                }
            }
            Ok(None) => panic!("the driver ended while waiting for {what}"),
            Err(_) => panic!("no {what} within {within:?}"),
        }
    }
}

/// The next STOP write (register 200 <- 2); panics after `within`.
pub(crate) async fn next_stop_write(
    writes: &mut mpsc::UnboundedReceiver<RegisterWrite>,
    within: Duration,
) -> Instant {
    let until = tokio::time::Instant::now() + within;
    loop {
        match tokio::time::timeout_at(until, writes.recv()).await {
            Ok(Some(w))
                if w.address == ACTION_REGISTER && w.values.first() == Some(&ACTION_STOP) =>
            {
                return w.at;
            }
            Ok(Some(_)) => {}
            Ok(None) => panic!("the recording arm ended"),
            Err(_) => panic!("no STOP reached the arm within {within:?}"),
        }
    }
}

/// The real target is 50 ms; loaded CI machines get 500 ms, and the figure is printed.
const STOP_TARGET: Duration = Duration::from_millis(50);
const STOP_BOUND_ON_CI: Duration = Duration::from_millis(500);

#[tokio::test]
async fn a_stop_reaches_modbus_within_50ms_while_the_talos_handshake_stalls() {
    let listener = TcpListener::bind("127.0.0.1:0").await.expect("bind");
    let modbus_addr = listener.local_addr().expect("addr").to_string();
    let mut writes = recording_arm(listener).await;
    let (talos_addr, talos_bytes) = stalled_operator().await;

    let mut talos = TalosConfig::new(talos_addr);
    // The handshake hangs for its whole timeout: every STOP below is sent inside it.
    let handshake_stall = Duration::from_secs(10);
    talos.request_timeout = handshake_stall;
    let (driver, mut events) = Driver::spawn(DriverConfig::new(
        Some(talos),
        Some(ModbusConfig::new(modbus_addr)),
    ));
    let started = Instant::now();
    wait_for(
        &mut events,
        Duration::from_secs(5),
        "Modbus telemetry",
        |e| matches!(e, ArmEvent::Telemetry(_)).then_some(()),
    )
    .await;
    assert!(
        talos_bytes.load(Ordering::SeqCst) > 0,
        "the handshake frame reached the stalled operator"
    );

    let stop_handle = driver.stop_handle();
    let mut latencies = Vec::new();
    for i in 0..5 {
        let sent = Instant::now();
        // One of them the way the panic hook sends it.
        if i == 2 {
            stop_handle.stop();
        } else {
            assert!(driver.send(ArmCommand::Stop));
        }
        let arrived = next_stop_write(&mut writes, Duration::from_secs(5)).await;
        latencies.push(arrived.saturating_duration_since(sent));
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    let all_inside_handshake = started.elapsed() < handshake_stall;
    let worst = latencies.iter().max().copied().unwrap_or_default();
    eprintln!(
        "STOP -> Modbus write while Talos handshakes: {latencies:?} (worst {worst:?}, target {STOP_TARGET:?})"
    );
    assert!(
        all_inside_handshake,
        "the STOPs were meant to be sent while the handshake stalled"
    );
    assert!(
        worst < STOP_BOUND_ON_CI,
        "a STOP took {worst:?} to reach the Modbus arm"
    );
    // The Talos link is still not up: nothing claimed it was.
    while let Ok(event) = events.try_recv() {
        if let ArmEvent::Status(LinkStatus::Up { description }) = event {
            panic!("the link was reported up ({description}) with Talos stalled");
        }
    }
}

#[tokio::test]
async fn a_modbus_arm_down_at_start_is_connected_once_it_appears() {
    // A free port, closed for now.
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("free port")
        .port();
    let addr = format!("127.0.0.1:{port}");
    let (driver, mut events) = Driver::spawn(DriverConfig::new(
        None,
        Some(ModbusConfig::new(addr.clone())),
    ));
    let reason = wait_for(
        &mut events,
        Duration::from_secs(5),
        "a Down status",
        |e| match e {
            ArmEvent::Status(LinkStatus::Down { reason }) => Some(reason.clone()),
            _ => None,
        },
    )
    .await;
    assert!(reason.contains(&addr), "the reason names the arm: {reason}");

    let listener = TcpListener::bind(&addr).await.expect("rebind the port");
    let appeared = Instant::now();
    let mut writes = recording_arm(listener).await;
    wait_for(&mut events, Duration::from_secs(10), "an Up status", |e| {
        matches!(e, ArmEvent::Status(LinkStatus::Up { .. })).then_some(())
    })
    .await;
    eprintln!("Modbus up {:?} after the arm appeared", appeared.elapsed());
    // The link works: a STOP reaches the arm.
    assert!(driver.send(ArmCommand::Stop));
    next_stop_write(&mut writes, Duration::from_secs(5)).await;
}

#[tokio::test]
async fn a_talos_operator_that_stalls_the_first_handshake_is_retried() {
    // The first handshake gets no answer; later ones get their ACK.
    let handshakes = Arc::new(AtomicUsize::new(0));
    let seen = handshakes.clone();
    let script: common::Script = Arc::new(move |f: &TalosFrame| {
        if f.command == 0x0000 && seen.fetch_add(1, Ordering::SeqCst) == 0 {
            return Vec::new();
        }
        vec![Action::Write(b"ACK\0".to_vec())]
    });
    let op = TestOperator::start(Checksum::Xor8, script).await;
    let mut talos = TalosConfig::new(op.addr.clone());
    talos.dialect = Dialect::Ack;
    talos.checksum = Checksum::Xor8;
    talos.request_timeout = Duration::from_millis(300);
    let (driver, mut events) = Driver::spawn(DriverConfig::new(Some(talos), None));
    let reason = wait_for(
        &mut events,
        Duration::from_secs(5),
        "a Down status",
        |e| match e {
            ArmEvent::Status(LinkStatus::Down { reason }) => Some(reason.clone()),
            _ => None,
        },
    )
    .await;
    assert!(reason.contains("handshake"), "{reason}");
    wait_for(&mut events, Duration::from_secs(10), "an Up status", |e| {
        matches!(e, ArmEvent::Status(LinkStatus::Up { .. })).then_some(())
    })
    .await;
    assert_eq!(handshakes.load(Ordering::SeqCst), 2);
    assert!(driver.send(ArmCommand::Stop));
    let done = wait_for(
        &mut events,
        Duration::from_secs(5),
        "the STOP's outcome",
        |e| match e {
            ArmEvent::Done { command } if command.is_stop() => Some(true),
            ArmEvent::Failed {
                command: CommandKind::Stop,
                ..
            } => Some(false),
            _ => None,
        },
    )
    .await;
    assert!(done, "the STOP was acknowledged");
}
