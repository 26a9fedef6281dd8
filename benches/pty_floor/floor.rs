//! The compiled floor of `benches/pty_latency.py`: the least a console can do, in Rust and std
//! only. The harness puts the pty in raw mode and runs this with the operator's port; it reads
//! the terminal with one blocking read per wake and writes one Talos frame per key event:
//! START on a press of Right, STOP on its release. No runtime, no threads, no draws: what its
//! latency shows is the pty's, the kernel's and the harness's.
//!
//! Built by the harness: `rustc -O --edition 2024 benches/pty_floor/floor.rs`.

#![forbid(unsafe_code)]

use std::io::{Read, Write};
use std::net::TcpStream;

const PRESS_RIGHT: &[u8] = b"\x1b[1;1:1C";
const RELEASE_RIGHT: &[u8] = b"\x1b[1;1:3C";
const PRESS_Q: &[u8] = b"\x1b[113u";
const POLAR_START: u16 = 0x0003;
const POLAR_STOP: u16 = 0x0004;

/// An ack-dialect request frame with no payload: id u32, reserved u16, command u16, length u16,
/// then the xor8 checksum of those ten bytes.
fn frame(command: u16) -> [u8; 11] {
    let mut out = [0u8; 11];
    out[6..8].copy_from_slice(&command.to_be_bytes());
    out[10] = out[..10].iter().fold(0, |x, b| x ^ b);
    out
}

fn contains(haystack: &[u8], needle: &[u8]) -> bool {
    haystack.windows(needle.len()).any(|w| w == needle)
}

fn main() -> std::io::Result<()> {
    let port: u16 = std::env::args()
        .nth(1)
        .and_then(|p| p.parse().ok())
        .ok_or_else(|| std::io::Error::other("usage: floor PORT"))?;
    let mut socket = TcpStream::connect(("127.0.0.1", port))?;
    socket.set_nodelay(true)?;
    socket.write_all(&frame(0x0000))?;
    let mut stdin = std::io::stdin().lock();
    // Larger than stdin's own buffer, so each read goes straight to the terminal.
    let mut buffer = vec![0u8; 64 * 1024];
    loop {
        let read = stdin.read(&mut buffer)?;
        let data = &buffer[..read];
        if read == 0 || contains(data, PRESS_Q) {
            return Ok(());
        }
        if contains(data, RELEASE_RIGHT) {
            socket.write_all(&frame(POLAR_STOP))?;
        } else if contains(data, PRESS_RIGHT) {
            socket.write_all(&frame(POLAR_START))?;
        }
    }
}
