//! The simulated Talos operator logs every frame it rejects, with the peer and the reason, in
//! both dialects, and limits that log per connection.

use crate::log_capture;

use std::time::Duration;

use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;

use armjog::link::Dialect;
use armjog::sim::{SimConfig, Simulator};
use armjog::talos::{Checksum, Request, TalosFrame};

async fn sim(dialect: Dialect, checksum: Checksum) -> Simulator {
    let mut config = SimConfig::ephemeral();
    config.modbus_listen = None;
    config.talos.dialect = dialect;
    config.talos.checksum = checksum;
    Simulator::start(config).await.expect("simulator starts")
}

fn bytes(frame: TalosFrame, checksum: Checksum) -> Vec<u8> {
    frame.to_bytes(checksum).unwrap()
}

/// Reads exactly `n` bytes, within 10 s.
async fn read_n(stream: &mut TcpStream, n: usize) -> Vec<u8> {
    let mut buf = vec![0u8; n];
    tokio::time::timeout(Duration::from_secs(10), stream.read_exact(&mut buf))
        .await
        .expect("the server answers within 10 s")
        .unwrap();
    buf
}

#[tokio::test]
async fn the_ack_dialect_logs_each_ignored_frame_with_its_reason() {
    let log = log_capture::capture();
    let sim = sim(Dialect::Ack, Checksum::Xor8).await;
    let mut stream = TcpStream::connect(sim.talos_addr).await.unwrap();
    let peer = stream.local_addr().unwrap().to_string();

    let mut corrupt = bytes(Request::PolarPanStop.to_frame(2).unwrap(), Checksum::Xor8);
    let last = corrupt.len() - 1;
    corrupt[last] ^= 0x5A;
    // Get Speed (0x0009) is in the ICD but not in the deployed operator.
    let unsupported = bytes(Request::GetSpeed.to_frame(4).unwrap(), Checksum::Xor8);
    // Continuous START with an azimuth direction of 5.
    let malformed = bytes(TalosFrame::new(6, 0x0003, vec![5, 0]), Checksum::Xor8);
    // Pan to a point far out of reach: decoded, supported, refused by the arm.
    let unreachable = bytes(
        Request::PolarPan {
            delta_azimuth: 0,
            delta_altitude: -170,
            delay_ms: 0,
            time_ms: 0,
        }
        .to_frame(8)
        .unwrap(),
        Checksum::Xor8,
    );
    let fine = bytes(Request::PolarPanStop.to_frame(10).unwrap(), Checksum::Xor8);
    let mut all = corrupt;
    for frame in [&unsupported, &malformed, &unreachable, &fine] {
        all.extend_from_slice(frame);
    }
    stream.write_all(&all).await.unwrap();
    assert_eq!(read_n(&mut stream, 20).await, b"ACK\0".repeat(5));

    let from = format!("rejected a frame from {peer}");
    let checksum = log.wait_for(&[&from, "bad checksum"]).await;
    assert!(
        checksum.contains("frame id 2") && checksum.contains("INFO"),
        "{checksum}"
    );
    let line = log.wait_for(&[&from, "frame id 4"]).await;
    assert!(
        line.contains("0x0009") && line.contains("implements only commands 0x0000-0x0004"),
        "{line}"
    );
    let line = log.wait_for(&[&from, "frame id 6"]).await;
    assert!(
        line.contains("malformed payload") && line.contains("direction 5"),
        "{line}"
    );
    let line = log.wait_for(&[&from, "frame id 8"]).await;
    assert!(line.contains("refused with"), "{line}");
    assert!(
        log.lines_with(&[&from, "frame id 10"]).is_empty(),
        "a good frame is not a rejection"
    );
}

#[tokio::test]
async fn the_icd_dialect_logs_undecodable_requests_and_reply_values() {
    let log = log_capture::capture();
    let sim = sim(Dialect::Icd, Checksum::Crc16).await;
    let mut stream = TcpStream::connect(sim.talos_addr).await.unwrap();
    let peer = stream.local_addr().unwrap().to_string();
    // Set Speed with two payload bytes, then a Get Speed reply value sent to the server.
    let mut all = bytes(TalosFrame::new(6, 0x000A, vec![1, 2]), Checksum::Crc16);
    all.extend(bytes(
        TalosFrame::new(8, 0x8009, vec![0, 0, 50]),
        Checksum::Crc16,
    ));
    stream.write_all(&all).await.unwrap();
    read_n(&mut stream, 28).await; // two bare replies of 14 bytes

    let from = format!("rejected a frame from {peer}");
    let line = log.wait_for(&[&from, "frame id 6"]).await;
    assert!(line.contains("unexpected bytes"), "{line}");
    let line = log.wait_for(&[&from, "frame id 8"]).await;
    assert!(line.contains("a reply value"), "{line}");
}

#[tokio::test]
async fn a_flood_of_rejected_frames_is_logged_twenty_a_second_then_summarised() {
    let log = log_capture::capture();
    let sim = sim(Dialect::Ack, Checksum::Xor8).await;
    let mut stream = TcpStream::connect(sim.talos_addr).await.unwrap();
    let peer = stream.local_addr().unwrap().to_string();
    const FLOOD: usize = 200;
    let frame = bytes(Request::GetSpeed.to_frame(0).unwrap(), Checksum::Xor8);
    stream.write_all(&frame.repeat(FLOOD)).await.unwrap();
    read_n(&mut stream, 4 * FLOOD).await;
    drop(stream);
    // What is still suppressed is summarised when the connection ends, before the last line.
    log.wait_for(&[&peer, "disconnected"]).await;

    let full = log
        .lines_with(&[&format!("rejected a frame from {peer}")])
        .len();
    let suppressed: usize = log
        .lines_with(&[&format!("more rejected frames from {peer} suppressed")])
        .iter()
        .map(|line| {
            let words: Vec<&str> = line.split_whitespace().collect();
            let at = words.iter().position(|w| *w == "more").expect("a count");
            words[at - 1].parse::<usize>().expect("a number")
        })
        .sum();
    assert_eq!(full + suppressed, FLOOD, "every rejection is counted");
    // 200 frames take far less than the 9 s it would need to log them all in full.
    assert!((20..FLOOD).contains(&full), "{full} full lines");
    assert!(suppressed > 0);
}
