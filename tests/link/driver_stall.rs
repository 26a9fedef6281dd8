//! The driver never waits on a link: a Talos operator that accepts, answers the handshake and
//! then never reads again fills its socket and the link's queue, while the Modbus link carries
//! motion. A STOP still reaches the Modbus arm at once, the Talos link is reported down soon
//! after, and the driver goes on taking commands. Real loopback sockets; the operator's receive
//! buffer is made small before it accepts. On loopback the sending side's buffer takes a
//! megabyte or more, so a burst fills the link's queue first and that ends the link; the
//! 500 ms write stall is measured exactly in `talos_stall.rs`, on the paused clock.

use crate::driver_stop::{next_stop_write, recording_arm, wait_for};

use std::time::{Duration, Instant};

use bytes::BytesMut;
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::{TcpListener, TcpSocket, TcpStream};
use tokio_util::codec::Decoder;

use armjog::link::driver::{Driver, DriverConfig};
use armjog::link::interface::{ArmCommand, ArmEvent, JogMotion, LinkStatus};
use armjog::link::{ModbusConfig, TalosConfig};
use armjog::talos::frame::Decoded;
use armjog::talos::{Checksum, FrameCodec};

/// A STOP reaches the Modbus arm within this of being sent (generous for a loaded CI machine).
const STOP_BOUND: Duration = Duration::from_millis(300);
/// The Talos link is reported down within this of the flood: the 500 ms stall plus slack.
const DOWN_BOUND: Duration = Duration::from_secs(3);

/// Answers the handshake and the speed read, then never reads again; the stream is kept open
/// (and unread) until the test ends.
async fn operator_that_stops_reading() -> (String, tokio::task::JoinHandle<Option<TcpStream>>) {
    let socket = TcpSocket::new_v4().expect("socket");
    socket.set_recv_buffer_size(4096).expect("SO_RCVBUF");
    socket
        .bind("127.0.0.1:0".parse().expect("addr"))
        .expect("bind");
    let addr = socket.local_addr().expect("addr").to_string();
    let listener = socket.listen(1).expect("listen");
    let task = tokio::spawn(async move {
        let (mut stream, _) = listener.accept().await.ok()?;
        let mut codec = FrameCodec::new(Checksum::Crc16);
        let mut buf = BytesMut::new();
        let mut answered = 0;
        while answered < 2 {
            while let Ok(Some(Decoded::TalosFrame(frame))) = codec.decode(&mut buf) {
                let reply = crate::common::ok_reply(&frame);
                let bytes = crate::common::reply_bytes(&reply, frame.id, Checksum::Crc16);
                stream.write_all(&bytes).await.ok()?;
                answered += 1;
            }
            if answered < 2 && stream.read_buf(&mut buf).await.ok()? == 0 {
                return None;
            }
        }
        Some(stream)
    });
    (addr, task)
}

async fn wait_for_talos_down(
    events: &mut tokio::sync::mpsc::UnboundedReceiver<ArmEvent>,
) -> String {
    wait_for(events, DOWN_BOUND, "the Talos link down", |e| match e {
        ArmEvent::Status(LinkStatus::Down { reason }) if reason.starts_with("talos") => {
            Some(reason.clone())
        }
        _ => None,
    })
    .await
}

#[tokio::test]
async fn a_talos_operator_that_stops_reading_never_holds_up_a_modbus_stop() {
    let listener = TcpListener::bind("127.0.0.1:0").await.expect("bind");
    let modbus_addr = listener.local_addr().expect("addr").to_string();
    let mut writes = recording_arm(listener).await;
    let (talos_addr, operator) = operator_that_stops_reading().await;
    let mut talos = TalosConfig::new(talos_addr);
    talos.request_timeout = Duration::from_secs(5);
    let (driver, mut events) = Driver::spawn(DriverConfig::new(
        Some(talos),
        Some(ModbusConfig::new(modbus_addr)),
    ));
    wait_for(&mut events, Duration::from_secs(5), "both links up", |e| {
        matches!(e, ArmEvent::Status(LinkStatus::Up { description })
            if description.contains("talos") && description.contains("modbus"))
        .then_some(())
    })
    .await;

    // Motion on both links: a cartesian jog goes over Talos, an orientation jog over Modbus.
    let cartesian = ArmCommand::Jog(JogMotion::Cartesian { x: 1, y: 0, z: 0 });
    let turn = ArmCommand::Jog(JogMotion::Orientation {
        rx: 0,
        ry: 0,
        rz: 1,
    });
    assert!(driver.send(cartesian));
    assert!(driver.send(turn.clone()));
    wait_for(&mut events, Duration::from_secs(5), "the turn done", |e| {
        matches!(e, ArmEvent::Done { command } if *command == turn).then_some(())
    })
    .await;
    while writes.try_recv().is_ok() {}

    // Fill the operator's socket and then the link's queue, then STOP at once.
    let flood_started = Instant::now();
    for i in 0..4000 {
        assert!(driver.send(ArmCommand::SavePosition {
            name: format!("{i:04}{}", "x".repeat(240)),
            anchor: false,
            parent: None,
        }));
    }
    let first_stop = Instant::now();
    assert!(driver.send(ArmCommand::Stop));
    let arrived = next_stop_write(&mut writes, Duration::from_secs(5)).await;
    let first_latency = arrived.saturating_duration_since(first_stop);

    let reason = wait_for_talos_down(&mut events).await;
    let down_after = flood_started.elapsed();
    assert!(
        reason.contains("write stalled") || reason.contains("queued unsent"),
        "the link ended for its stalled operator: {reason}"
    );

    // The driver still takes commands: a second STOP reaches Modbus at once.
    let second_stop = Instant::now();
    assert!(driver.send(ArmCommand::Stop));
    let arrived = next_stop_write(&mut writes, Duration::from_secs(5)).await;
    let second_latency = arrived.saturating_duration_since(second_stop);
    eprintln!(
        "stalled Talos: first STOP -> Modbus {first_latency:?}, Talos down {down_after:?} after the flood ({reason}), second STOP -> Modbus {second_latency:?}"
    );
    assert!(
        first_latency < STOP_BOUND,
        "first STOP took {first_latency:?}"
    );
    assert!(
        second_latency < STOP_BOUND,
        "second STOP took {second_latency:?}"
    );

    // The first STOP's Talos half could not be sent: it is not confirmed.
    let unconfirmed = wait_for(
        &mut events,
        Duration::from_secs(5),
        "the first STOP's outcome",
        |e| match e {
            ArmEvent::StopUnconfirmed { reason } => Some(reason.clone()),
            ArmEvent::StopConfirmed => Some(String::new()),
            _ => None,
        },
    )
    .await;
    assert!(
        unconfirmed.contains("Talos"),
        "a STOP whose Talos side failed is unconfirmed: {unconfirmed:?}"
    );
    drop(driver);
    operator.abort();
}
