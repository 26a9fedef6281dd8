//! The simulated Talos operator stops the continuous motion a client holds as soon as that
//! client's connection closes (docs/hardware-icd.md: the server SHALL stop every joint), not at
//! the watchdog; another client leaving does not stop it.

use crate::log_capture;

use std::time::Duration;

use bytes::BytesMut;
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;
use tokio_util::codec::Decoder;

use armjog::sim::arm_model::SimMotion;
use armjog::sim::talos_server::NetworkFaults;
use armjog::sim::{SimConfig, Simulator};
use armjog::talos::frame::Decoded;
use armjog::talos::hardware::{ActuatorCommand, HwRequest};
use armjog::talos::{Checksum, FrameCodec, Reply, Request, TalosFrame};

/// A watchdog far longer than any test: whatever stops a motion here, it is not the watchdog.
const LONG_WATCHDOG_S: f64 = 600.0;

async fn sim_with_long_watchdog() -> Simulator {
    let mut config = SimConfig::ephemeral();
    config.modbus_listen = None;
    config.arm.set_watchdog_period(LONG_WATCHDOG_S);
    Simulator::start(config).await.expect("simulator starts")
}

fn jog(joint: u8, velocity_deg_s: f32) -> Request {
    let hw = HwRequest::SendActuatorCommand {
        joint,
        command: ActuatorCommand::jog(0.0, velocity_deg_s),
    };
    Request::HardwareOperation {
        subcommand: hw.subcommand(),
        reserved: 0,
        payload: hw.encode_payload().unwrap(),
    }
}

/// A raw client: no link task that could send a STOP when it goes.
struct RawClient {
    stream: TcpStream,
    buffer: BytesMut,
    codec: FrameCodec,
    next_id: u32,
}

impl RawClient {
    async fn connect(sim: &Simulator) -> RawClient {
        RawClient {
            stream: TcpStream::connect(sim.talos_addr).await.unwrap(),
            buffer: BytesMut::new(),
            codec: FrameCodec::new(Checksum::Crc16),
            next_id: 0,
        }
    }

    fn addr(&self) -> String {
        self.stream.local_addr().unwrap().to_string()
    }

    async fn request(&mut self, request: Request) -> Reply {
        let frame = request.to_frame(self.next_id).unwrap();
        self.next_id += 2;
        let bytes = frame.to_bytes(Checksum::Crc16).unwrap();
        self.stream.write_all(&bytes).await.unwrap();
        let reply = tokio::time::timeout(Duration::from_secs(10), self.read_frame())
            .await
            .expect("a reply within 10 s");
        Reply::from_frame(&reply).unwrap()
    }

    async fn read_frame(&mut self) -> TalosFrame {
        loop {
            if let Some(item) = self.codec.decode(&mut self.buffer).unwrap() {
                match item {
                    Decoded::TalosFrame(frame) => return frame,
                    Decoded::Rejected(r) => panic!("bad reply: {r}"),
                }
            }
            let n = self.stream.read_buf(&mut self.buffer).await.unwrap();
            assert!(n > 0, "the server closed the connection");
        }
    }
}

async fn moving(sim: &Simulator) -> bool {
    sim.arm.snapshot().await.unwrap().moving
}

/// Polls (up to 10 s) until the arm stands.
async fn wait_until_stopped(sim: &Simulator) {
    for _ in 0..1000 {
        if !moving(sim).await {
            return;
        }
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    panic!("the arm still moves 10 s after the client closed");
}

#[tokio::test]
async fn a_joint_jog_stops_when_its_connection_closes() {
    let log = log_capture::capture();
    let sim = sim_with_long_watchdog().await;
    let mut a = RawClient::connect(&sim).await;
    assert!(a.request(jog(1, 10.0)).await.return_code().is_ok());
    let motion = sim.arm.with(|arm, _| arm.motion().clone()).await.unwrap();
    assert!(matches!(motion, SimMotion::JointVelocity { joint: 0, .. }));
    let peer = a.addr();
    drop(a);
    wait_until_stopped(&sim).await;
    let line = log
        .wait_for(&[&peer, "disconnected", "stopped the continuous motion"])
        .await;
    assert!(line.contains("end of stream"), "{line}");
}

#[tokio::test]
async fn a_continuous_start_stops_when_its_connection_closes() {
    let sim = sim_with_long_watchdog().await;
    let mut a = RawClient::connect(&sim).await;
    let start = Request::CartesianMoveStart {
        moving_x: 1,
        moving_y: 0,
        moving_z: 0,
    };
    assert!(a.request(start).await.return_code().is_ok());
    assert!(moving(&sim).await);
    drop(a);
    wait_until_stopped(&sim).await;
}

#[tokio::test]
async fn an_injected_close_stops_the_jog_of_that_connection() {
    let log = log_capture::capture();
    let sim = sim_with_long_watchdog().await;
    sim.set_faults(NetworkFaults {
        close_after_frames: Some(1),
        ..Default::default()
    });
    let mut a = RawClient::connect(&sim).await;
    let peer = a.addr();
    assert!(a.request(jog(3, -8.0)).await.return_code().is_ok());
    wait_until_stopped(&sim).await;
    log.wait_for(&[
        &peer,
        "closed by fault injection",
        "stopped the continuous motion",
    ])
    .await;
}

#[tokio::test]
async fn another_client_leaving_does_not_stop_the_jog() {
    let log = log_capture::capture();
    let sim = sim_with_long_watchdog().await;
    let mut a = RawClient::connect(&sim).await;
    assert!(a.request(jog(1, 10.0)).await.return_code().is_ok());
    let mut b = RawClient::connect(&sim).await;
    let b_peer = b.addr();
    assert!(b.request(Request::GetSpeed).await.return_code().is_ok());
    drop(b);
    // Once the server has handled B's end, A's jog must still run.
    let line = log.wait_for(&[&b_peer, "disconnected"]).await;
    assert!(!line.contains("stopped"), "{line}");
    assert!(moving(&sim).await, "B leaving stopped A's jog");
    // A's own stop still works, of course.
    let stop = HwRequest::StopAllJoints;
    let stop = Request::HardwareOperation {
        subcommand: stop.subcommand(),
        reserved: 0,
        payload: stop.encode_payload().unwrap(),
    };
    assert!(a.request(stop).await.return_code().is_ok());
    assert!(!moving(&sim).await);
}
