//! Fuzzing the simulator's Modbus server over a real loopback socket: random bytes and
//! near-requests (odd function codes, addresses and counts at the edges, lengths that lie in the
//! MBAP header, FC 15/16/23 whose byte counts disagree with their quantities), then one valid
//! read on the same connection. MBAP framing has no resync marker, so after garbage the server
//! may close the connection; what it must not do is hang, answer the read wrongly, or stop
//! serving: a fresh connection's read is answered and the arm task lives.

use crate::attack_support;

use std::cell::Cell;
use std::time::Duration;

use proptest::prelude::*;
use proptest::test_runner::{Config, TestCaseError, TestRunner};
use tokio::io::AsyncWriteExt;
use tokio::net::TcpStream;

use armjog::sim::{SimConfig, Simulator};

use attack_support::{
    ModbusOutcome, REPLY_BOUND, is_state_reply, modbus_read_state, modbus_reply_to,
    modbus_state_answered,
};

const CASES: u32 = 128;
/// Transaction ids of the valid reads; garbage uses lower ones.
const VALID_TRANSACTIONS: u16 = 0xF000;
/// Longest MBAP length field Modbus TCP allows: unit id + a 253-byte PDU.
const MAX_MBAP_LENGTH: usize = 254;

/// One hostile input.
#[derive(Debug, Clone)]
enum Piece {
    Random(Vec<u8>),
    Request {
        transaction: u16,
        protocol: u16,
        unit: u8,
        /// `None` for the true length of unit id + PDU.
        length: Option<u16>,
        pdu: Vec<u8>,
    },
}

fn address() -> impl Strategy<Value = u16> {
    prop_oneof![
        Just(0u16),
        Just(1),
        Just(100),
        Just(200),
        Just(219),
        Just(65534),
        Just(65535),
        any::<u16>()
    ]
}

fn count() -> impl Strategy<Value = u16> {
    prop_oneof![
        Just(0u16),
        Just(1),
        Just(2),
        Just(0x7F),
        Just(0x80),
        Just(123),
        Just(124),
        Just(125),
        Just(126),
        Just(1968),
        Just(1969),
        Just(2000),
        Just(2001),
        Just(0x8000),
        Just(65535),
        any::<u16>()
    ]
}

fn be(values: &[u16]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_be_bytes()).collect()
}

/// A byte count for `data_needed` bytes: the right one or any other.
fn byte_count_and_data(data_needed: usize) -> impl Strategy<Value = (u8, Vec<u8>)> {
    let right = u8::try_from(data_needed).unwrap_or(u8::MAX);
    (
        prop_oneof![Just(right), any::<u8>()],
        prop_oneof![Just(None), (0..48usize).prop_map(Some)],
        any::<u8>(),
    )
        .prop_map(move |(count, data_len, fill)| {
            // By default as many data bytes as the byte count says; sometimes another number.
            let len = data_len.unwrap_or(usize::from(count));
            (count, vec![fill; len])
        })
}

fn pdu() -> impl Strategy<Value = Vec<u8>> {
    prop_oneof![
        (1..=4u8, address(), count()).prop_map(|(fc, a, c)| [vec![fc], be(&[a, c])].concat()),
        (
            5..=6u8,
            address(),
            prop_oneof![Just(0xFF00u16), Just(0), Just(1), Just(2), any::<u16>()]
        )
            .prop_map(|(fc, a, v)| [vec![fc], be(&[a, v])].concat()),
        (address(), count()).prop_flat_map(|(a, q)| {
            byte_count_and_data(usize::from(q).div_ceil(8))
                .prop_map(move |(n, data)| [vec![0x0F], be(&[a, q]), vec![n], data].concat())
        }),
        (address(), count()).prop_flat_map(|(a, q)| {
            byte_count_and_data(usize::from(q) * 2)
                .prop_map(move |(n, data)| [vec![0x10], be(&[a, q]), vec![n], data].concat())
        }),
        (address(), count(), address(), count()).prop_flat_map(|(ra, rq, wa, wq)| {
            byte_count_and_data(usize::from(wq) * 2).prop_map(move |(n, data)| {
                [vec![0x17], be(&[ra, rq, wa, wq]), vec![n], data].concat()
            })
        }),
        (any::<u8>(), prop::collection::vec(any::<u8>(), 0..24)).prop_map(|(fc, body)| [
            vec![fc],
            body
        ]
        .concat()),
    ]
}

fn piece() -> impl Strategy<Value = Piece> {
    prop_oneof![
        1 => prop::collection::vec(any::<u8>(), 0..300).prop_map(Piece::Random),
        4 => (
            0..VALID_TRANSACTIONS,
            prop_oneof![8 => Just(0u16), 1 => any::<u16>()],
            prop_oneof![Just(1u8), Just(0), Just(255), any::<u8>()],
            prop_oneof![
                6 => Just(None),
                1 => prop_oneof![Just(0u16), Just(1), Just(2), Just(254), Just(255), Just(65535), any::<u16>()]
                    .prop_map(Some),
            ],
            pdu(),
        )
            .prop_map(|(transaction, protocol, unit, length, pdu)| Piece::Request {
                transaction,
                protocol,
                unit,
                length,
                pdu,
            }),
    ]
}

fn render(piece: &Piece) -> Vec<u8> {
    match piece {
        Piece::Random(bytes) => bytes.clone(),
        Piece::Request {
            transaction,
            protocol,
            unit,
            length,
            pdu,
        } => {
            let true_length = u16::try_from(pdu.len() + 1).unwrap_or(u16::MAX);
            let length = length.unwrap_or(true_length);
            [
                be(&[*transaction, *protocol, length]),
                vec![*unit],
                pdu.clone(),
            ]
            .concat()
        }
    }
}

/// Where MBAP framing, read from the start of the stream, puts the valid request.
#[derive(Debug, PartialEq, Eq)]
enum Framing {
    /// A frame starts exactly at it.
    Aligned,
    /// A frame (with a length Modbus allows) ends exactly at the end of the stream, having
    /// swallowed the valid request: the server answers that frame, if at all, then waits for more.
    SwallowedToEnd,
    /// The stream ends inside a frame, or a header the server refuses comes first.
    Other,
}

fn framing(stream: &[u8], valid_start: usize) -> Framing {
    let mut at = 0;
    loop {
        if at == valid_start {
            return Framing::Aligned;
        }
        if at == stream.len() {
            return Framing::SwallowedToEnd;
        }
        let Some(header) = stream.get(at..at + 7) else {
            return Framing::Other;
        };
        let protocol = u16::from_be_bytes([header[2], header[3]]);
        let length = usize::from(u16::from_be_bytes([header[4], header[5]]));
        if protocol != 0 || length == 0 || length > MAX_MBAP_LENGTH {
            return Framing::Other;
        }
        at += 6 + length;
        if at > stream.len() {
            return Framing::Other;
        }
    }
}

/// How the valid read after the garbage fared (all allowed; counted so the test shows it
/// exercised each).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Fate {
    Answered,
    Closed,
    Swallowed,
}

async fn case(sim: &Simulator, pieces: &[Piece], chunk: usize, n: u32) -> Result<Fate, String> {
    let addr = sim.modbus_addr.ok_or("the Modbus server is not running")?;
    let transaction = VALID_TRANSACTIONS + (n % 0x0800) as u16;
    let mut input: Vec<u8> = pieces.iter().flat_map(render).collect();
    let valid_start = input.len();
    input.extend(modbus_read_state(transaction));
    let expected = framing(&input, valid_start);
    let mut stream = TcpStream::connect(addr)
        .await
        .map_err(|e| format!("connect: {e}"))?;
    let mut fate = Fate::Closed;
    let mut sent = true;
    for part in input.chunks(chunk.max(1)) {
        if stream.write_all(part).await.is_err() {
            // Closed on the garbage already: allowed.
            sent = false;
            break;
        }
    }
    if sent {
        // A swallowed request gets no answer; the frame that swallowed it is answered at once.
        let bound = match expected {
            Framing::SwallowedToEnd => Duration::from_millis(1500),
            _ => REPLY_BOUND,
        };
        match modbus_reply_to(&mut stream, transaction, bound).await {
            ModbusOutcome::Reply(pdu) if is_state_reply(&pdu) => fate = Fate::Answered,
            ModbusOutcome::Reply(pdu) => {
                return Err(format!(
                    "wrong reply to the valid read: {pdu:02x?} ({expected:?})"
                ));
            }
            ModbusOutcome::Closed => {}
            ModbusOutcome::Silent if expected == Framing::SwallowedToEnd => fate = Fate::Swallowed,
            ModbusOutcome::Silent => {
                return Err(format!(
                    "neither a reply nor a close within {bound:?} ({expected:?})"
                ));
            }
        }
    }
    drop(stream);
    modbus_state_answered(addr, VALID_TRANSACTIONS - 1)
        .await
        .map_err(|e| format!("fresh connection after the case: {e}"))?;
    sim.arm
        .snapshot()
        .await
        .map_err(|e| format!("the arm task is gone: {e:?}"))?;
    Ok(fate)
}

#[test]
fn the_modbus_server_answers_or_closes_after_any_garbage_and_keeps_serving() {
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .expect("a tokio runtime");
    let sim = runtime
        .block_on(Simulator::start(SimConfig::ephemeral()))
        .expect("simulator starts");
    let mut runner = TestRunner::new(Config {
        cases: CASES,
        failure_persistence: None,
        max_shrink_iters: 16,
        max_shrink_time: 30_000,
        ..Config::default()
    });
    let counter = Cell::new(0u32);
    let fates = std::cell::RefCell::new(Vec::new());
    let strategy = (
        prop::collection::vec(piece(), 0..5),
        prop_oneof![Just(usize::MAX), 1..64usize],
    );
    let result = runner.run(&strategy, |(pieces, chunk)| {
        let n = counter.get();
        counter.set(n + 1);
        let fate = runtime
            .block_on(case(&sim, &pieces, chunk, n))
            .map_err(TestCaseError::fail)?;
        fates.borrow_mut().push(fate);
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
    let fates = fates.into_inner();
    let count = |f: Fate| fates.iter().filter(|&&x| x == f).count();
    let answered = count(Fate::Answered);
    eprintln!(
        "modbus: {} cases: valid read answered {answered}, connection closed {}, read swallowed by a lying length {}",
        fates.len(),
        count(Fate::Closed),
        count(Fate::Swallowed)
    );
    assert!(
        answered * 10 >= fates.len(),
        "only {answered} of {} valid reads answered: the garbage hardly ever lets one through",
        fates.len()
    );
}
