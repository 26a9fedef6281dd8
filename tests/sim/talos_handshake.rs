//! The simulated operator (ICD dialect) answers the handshakes real clients send: the ICD's
//! 2-byte OID and the empty payload of talos-rit/commander and the deployed interfaces.
//!
//! Every frame here is written by hand, field by field (wrapper | payload | checksum); the CRCs
//! are CRC-16/CCITT-FALSE worked out outside this crate.

use std::time::Duration;

use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;

use armjog::sim::{SimConfig, Simulator};
use armjog::talos::Checksum;

fn hex(s: &str) -> Vec<u8> {
    let digits: Vec<u8> = s
        .bytes()
        .filter(|c| c.is_ascii_hexdigit())
        .map(|c| (c as char).to_digit(16).expect("hex digit") as u8)
        .collect();
    digits.chunks(2).map(|p| p[0] << 4 | p[1]).collect()
}

async fn sim_with(checksum: Checksum) -> Simulator {
    let mut config = SimConfig::ephemeral();
    config.talos.checksum = checksum;
    Simulator::start(config).await.expect("simulator starts")
}

/// Writes `request` on one connection and reads `len` reply bytes.
async fn exchange(stream: &mut TcpStream, request: &[u8], len: usize) -> Vec<u8> {
    stream.write_all(request).await.unwrap();
    let mut reply = vec![0u8; len];
    tokio::time::timeout(Duration::from_secs(5), stream.read_exact(&mut reply))
        .await
        .expect("a reply within 5 s")
        .unwrap();
    reply
}

#[tokio::test]
async fn an_empty_handshake_and_the_icd_handshake_are_both_answered_ok() {
    let sim = sim_with(Checksum::Crc16).await;
    let mut stream = TcpStream::connect(sim.talos_addr).await.unwrap();
    // id 0, handshake, length 0: what talos-rit/commander sends.
    let empty = exchange(&mut stream, &hex("00000000 0000 0000 0000 | E139"), 16).await;
    // id 1, reply 0x8000, length 4: OK, version 1.0.
    assert_eq!(empty, hex("00000001 0000 8000 0004 | 0000 01 00 | 3695"));
    // id 2, the ICD's OID 1, on the same connection.
    let icd = exchange(
        &mut stream,
        &hex("00000002 0000 0000 0002 | 0001 | 3CDF"),
        16,
    )
    .await;
    assert_eq!(icd, hex("00000003 0000 8000 0004 | 0000 01 00 | 9626"));
}

#[tokio::test]
async fn the_commanders_xor_handshake_is_answered_ok() {
    let sim = sim_with(Checksum::Xor8).await;
    let mut stream = TcpStream::connect(sim.talos_addr).await.unwrap();
    // Every byte is 0, so is their XOR.
    let reply = exchange(&mut stream, &hex("00000000 0000 0000 0000 | 00"), 15).await;
    // 01 ^ 80 ^ 04 ^ 01 = 84.
    assert_eq!(reply, hex("00000001 0000 8000 0004 | 0000 01 00 | 84"));
}

#[tokio::test]
async fn a_one_byte_handshake_is_still_malformed() {
    let sim = sim_with(Checksum::Crc16).await;
    let mut stream = TcpStream::connect(sim.talos_addr).await.unwrap();
    let reply = exchange(&mut stream, &hex("00000004 0000 0000 0001 | 07 | 98B4"), 16).await;
    assert_eq!(&reply[..10], &hex("00000005 0000 8000 0004")[..]);
    // MALFORMED_PAYLOAD.
    assert_eq!(&reply[10..12], &[0x00, 0x02]);
}
