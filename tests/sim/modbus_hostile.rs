//! Hostile addresses and counts against the simulator's Modbus server, over a real socket with a
//! raw tokio-modbus client: a range that leaves the 16-bit address space (or the listed
//! addresses) is refused with "illegal data address", a count of 0 or over Modbus's cap with
//! "illegal data value", and after each the arm still answers Modbus and a Talos handshake.

use std::time::Duration;

use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;

use tokio_modbus::client::{Context, Reader, Writer, tcp};
use tokio_modbus::{ExceptionCode, Slave};

use armjog::link::{Answer, TalosConfig, TalosLink};
use armjog::sim::{SimConfig, Simulator};
use armjog::talos::hardware::{HwReply, HwRequest};
use armjog::talos::{Reply, Request};

const READY: u16 = 7;
const ADDRESS: ExceptionCode = ExceptionCode::IllegalDataAddress;
const VALUE: ExceptionCode = ExceptionCode::IllegalDataValue;

async fn sim() -> Simulator {
    Simulator::start(SimConfig::ephemeral())
        .await
        .expect("simulator starts")
}

async fn client(sim: &Simulator) -> Context {
    let addr = sim.modbus_addr.expect("the Modbus server runs");
    tcp::connect_slave(addr, Slave(1))
        .await
        .expect("connect to the sim's Modbus server")
}

fn exception_of<T: std::fmt::Debug>(what: &str, result: tokio_modbus::Result<T>) -> ExceptionCode {
    match result {
        Ok(Err(code)) => code,
        Ok(Ok(value)) => panic!("{what}: answered {value:?}, expected an exception"),
        Err(e) => panic!("{what}: transport error {e}"),
    }
}

/// The arm still serves: a normal Modbus read on a fresh connection, and a Talos handshake
/// followed by a GET_ARM_STATE request.
async fn assert_still_answers(sim: &Simulator, after: &str) {
    let mut ctx = client(sim).await;
    let state = ctx
        .read_input_registers(0, 1)
        .await
        .unwrap_or_else(|e| panic!("after {after}: transport error {e}"))
        .unwrap_or_else(|e| panic!("after {after}: robot state read refused: {e:?}"));
    assert_eq!(state, vec![READY], "after {after}: robot state");

    let mut config = TalosConfig::new(sim.talos_addr.to_string());
    config.request_timeout = Duration::from_secs(5);
    let (link, _events) = TalosLink::connect(config)
        .await
        .unwrap_or_else(|e| panic!("after {after}: Talos handshake failed: {e}"));
    let request = HwRequest::GetArmState;
    let exchange = link
        .request(Request::HardwareOperation {
            subcommand: request.subcommand(),
            reserved: 0,
            payload: request.encode_payload().expect("encodes"),
        })
        .await
        .unwrap_or_else(|e| panic!("after {after}: GET_ARM_STATE failed: {e}"));
    let Answer::Reply(Reply::HardwareOperation {
        subcommand,
        payload,
        ..
    }) = exchange.answer
    else {
        panic!("after {after}: unexpected answer {:?}", exchange.answer)
    };
    assert!(
        matches!(
            HwReply::decode(subcommand, &payload),
            Ok(HwReply::GetArmState { .. })
        ),
        "after {after}: not an arm state: {payload:02x?}"
    );
}

#[tokio::test]
async fn reads_at_the_top_of_the_address_space_are_refused_and_the_arm_keeps_serving() {
    let sim = sim().await;
    for (start, count, expected) in [
        (65535, 1, ADDRESS),
        (65535, 2, ADDRESS),
        (65534, 2, ADDRESS),
        (0, 0, VALUE),
        (65535, 0, VALUE),
    ] {
        let mut ctx = client(&sim).await;
        let what = format!("FC1 {start}+{count}");
        let r = ctx.read_coils(start, count).await;
        assert_eq!(exception_of(&what, r), expected, "{what}");
        let what = format!("FC2 {start}+{count}");
        let r = ctx.read_discrete_inputs(start, count).await;
        assert_eq!(exception_of(&what, r), expected, "{what}");
        let what = format!("FC3 {start}+{count}");
        let r = ctx.read_holding_registers(start, count).await;
        assert_eq!(exception_of(&what, r), expected, "{what}");
        let what = format!("FC4 {start}+{count}");
        let r = ctx.read_input_registers(start, count).await;
        assert_eq!(exception_of(&what, r), expected, "{what}");
        assert_still_answers(&sim, &format!("reads at {start}+{count}")).await;
    }
}

#[tokio::test]
async fn reads_over_the_modbus_caps_are_refused_as_illegal_values() {
    let sim = sim().await;
    let mut ctx = client(&sim).await;
    let r = ctx.read_coils(0, 2001).await;
    assert_eq!(exception_of("FC1 0+2001", r), VALUE);
    let r = ctx.read_discrete_inputs(0, 2001).await;
    assert_eq!(exception_of("FC2 0+2001", r), VALUE);
    let r = ctx.read_holding_registers(0, 126).await;
    assert_eq!(exception_of("FC3 0+126", r), VALUE);
    let r = ctx.read_input_registers(0, 126).await;
    assert_eq!(exception_of("FC4 0+126", r), VALUE);
    // At the top of the address space too: the count is judged first.
    let r = ctx.read_input_registers(65535, 126).await;
    assert_eq!(exception_of("FC4 65535+126", r), VALUE);
    assert_still_answers(&sim, "reads over the caps").await;
}

#[tokio::test]
async fn writes_at_the_top_of_the_address_space_are_refused_and_the_arm_keeps_serving() {
    let sim = sim().await;
    let mut ctx = client(&sim).await;
    let r = ctx.write_single_coil(65535, true).await;
    assert_eq!(exception_of("FC5 65535", r), ADDRESS);
    let r = ctx.write_single_register(65535, 2).await;
    assert_eq!(exception_of("FC6 65535", r), ADDRESS);
    let r = ctx.write_multiple_coils(65535, &[true]).await;
    assert_eq!(exception_of("FC15 65535+1", r), ADDRESS);
    let r = ctx.write_multiple_coils(65535, &[true, true]).await;
    assert_eq!(exception_of("FC15 65535+2", r), ADDRESS);
    let r = ctx.write_multiple_registers(65535, &[2]).await;
    assert_eq!(exception_of("FC16 65535+1", r), ADDRESS);
    let r = ctx.write_multiple_registers(65535, &[2, 0]).await;
    assert_eq!(exception_of("FC16 65535+2", r), ADDRESS);
    // Past the listed coils and the command block, inside the address space.
    let r = ctx.write_multiple_coils(2, &[false, false]).await;
    assert_eq!(exception_of("FC15 2+2", r), ADDRESS);
    let r = ctx.write_multiple_registers(219, &[0, 0]).await;
    assert_eq!(exception_of("FC16 219+2", r), ADDRESS);
    assert_still_answers(&sim, "writes at 65535").await;
    // A refused quick stop at 65535 must not have faulted the arm: still ready, no fault flags.
    let flags = ctx
        .read_input_registers(2, 2)
        .await
        .expect("transport")
        .expect("fault flags read");
    assert_eq!(flags, vec![0, 0], "no fault raised by refused writes");
}

#[tokio::test]
async fn writes_of_no_values_or_over_the_modbus_caps_are_refused_as_illegal_values() {
    let sim = sim().await;
    let mut ctx = client(&sim).await;
    let r = ctx.write_multiple_coils(0, &[]).await;
    assert_eq!(exception_of("FC15 0+0", r), VALUE);
    let r = ctx.write_multiple_coils(65535, &[]).await;
    assert_eq!(exception_of("FC15 65535+0", r), VALUE);
    // 1969 coils still fit a frame (247 bytes), one over the FC 15 cap of 1968.
    let r = ctx.write_multiple_coils(0, &[false; 1969]).await;
    assert_eq!(exception_of("FC15 0+1969", r), VALUE);
    let r = ctx.write_multiple_registers(200, &[]).await;
    assert_eq!(exception_of("FC16 200+0", r), VALUE);
    let r = ctx.write_multiple_registers(65535, &[]).await;
    assert_eq!(exception_of("FC16 65535+0", r), VALUE);
    // Over Modbus's frame size (253-byte PDU): tokio-modbus's client will not send these and its
    // server closes the connection on them before the request reaches the arm; either way the
    // write is refused (exception 03 or no reply) and the arm keeps serving.
    let mut body = vec![0x00, 200, 0x00, 126, 252];
    body.extend([0u8; 252]);
    assert_refused_as_value(raw_exchange(&sim, 0x10, &body).await, "FC16 200+126");
    let mut body = vec![0xFF, 0xFF, 0x00, 126, 252];
    body.extend([0u8; 252]);
    assert_refused_as_value(raw_exchange(&sim, 0x10, &body).await, "FC16 65535+126");
    let mut body = vec![0x00, 0x00, 0x07, 0xD1, 251];
    body.extend([0u8; 251]);
    assert_refused_as_value(raw_exchange(&sim, 0x0F, &body).await, "FC15 0+2001");
    assert_still_answers(&sim, "writes of bad counts").await;
}

fn assert_refused_as_value(reply: Option<[u8; 9]>, what: &str) {
    if let Some(reply) = reply {
        assert_eq!(
            reply[7] & 0x80,
            0x80,
            "{what}: an exception reply: {reply:02x?}"
        );
        assert_eq!(reply[8], 0x03, "{what}: illegal data value: {reply:02x?}");
    }
}

/// Sends one Modbus TCP frame (unit 1) built by hand; the 9-byte exception reply, or None if the
/// server closed the connection without one.
async fn raw_exchange(sim: &Simulator, function: u8, body: &[u8]) -> Option<[u8; 9]> {
    let addr = sim.modbus_addr.expect("the Modbus server runs");
    let mut stream = TcpStream::connect(addr).await.expect("connect");
    let length = u16::try_from(2 + body.len()).expect("frame fits");
    let mut frame = vec![0x00, 0x01, 0x00, 0x00];
    frame.extend(length.to_be_bytes());
    frame.extend([0x01, function]);
    frame.extend(body);
    stream.write_all(&frame).await.expect("send");
    let mut reply = [0u8; 9];
    let read = tokio::time::timeout(Duration::from_secs(10), stream.read_exact(&mut reply))
        .await
        .unwrap_or_else(|_| {
            panic!("function {function:#04x}: neither a reply nor a close in 10 s")
        });
    read.ok().map(|_| reply)
}

/// Panics raised inside tokio-modbus (its per-connection tasks), recorded by a chained hook.
static LIBRARY_PANICS: std::sync::Mutex<Vec<String>> = std::sync::Mutex::new(Vec::new());

fn record_library_panics() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if let Some(location) = info.location()
                && location.file().contains("tokio-modbus")
                && let Ok(mut panics) = LIBRARY_PANICS.lock()
            {
                panics.push(info.to_string());
            }
            previous(info);
        }));
    });
}

#[tokio::test]
async fn write_frames_whose_counts_disagree_with_their_data_close_the_connection_without_a_panic() {
    record_library_panics();
    let sim = sim().await;
    // FC 15: 2001 coils announced, one data byte sent.
    let reply = raw_exchange(&sim, 0x0F, &[0x00, 0x00, 0x07, 0xD1, 1, 0xFF]).await;
    assert_refused_as_value(reply, "FC15 0+2001 in 1 byte");
    // FC 16: 32768 registers announced (the decoder's quantity * 2 overflows), none sent.
    let reply = raw_exchange(&sim, 0x10, &[0x00, 200, 0x80, 0x00, 0]).await;
    assert_refused_as_value(reply, "FC16 200+32768 in 0 bytes");
    // FC 23: the same in its write half.
    let reply = raw_exchange(&sim, 0x17, &[0, 100, 0, 1, 0, 200, 0x80, 0x00, 0]).await;
    if let Some(reply) = reply {
        assert_eq!(
            reply[7] & 0x80,
            0x80,
            "FC23: an exception reply: {reply:02x?}"
        );
    }
    assert_still_answers(&sim, "malformed write frames").await;
    let panics = LIBRARY_PANICS.lock().map(|p| p.clone()).unwrap_or_default();
    assert!(panics.is_empty(), "tokio-modbus panicked: {panics:?}");
}
