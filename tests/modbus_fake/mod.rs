//! An in-process Kinova arm on loopback (tokio-modbus server): holds the ICD's tables, records
//! every request, and can be told to answer with exceptions, stall, or hang up.
#![allow(dead_code)]

use std::future::Future;
use std::net::SocketAddr;
use std::pin::Pin;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use tokio::net::{TcpListener, TcpStream};
use tokio_modbus::server::Service;
use tokio_modbus::server::tcp::Server;
use tokio_modbus::{ExceptionCode, Request, Response, SlaveRequest};

/// How the arm treats one request.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Behaviour {
    Answer,
    Exception(ExceptionCode),
    /// Send nothing for this long (the connection then serves nothing else).
    Stall(Duration),
    /// Close this connection without answering.
    HangUp,
}

/// Decides the behaviour for a request; the first rule returning `Some` applies.
pub type Rule = Box<dyn Fn(&Request<'static>) -> Option<Behaviour> + Send>;

/// One request the arm received.
#[derive(Debug, Clone, PartialEq)]
pub struct Logged {
    pub unit: u8,
    pub connection: usize,
    pub request: Request<'static>,
}

/// A write as the tests state them.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Written {
    Registers(u16, Vec<u16>),
    Coil(u16, bool),
}

pub struct ArmState {
    pub input_registers: Vec<u16>,
    pub holding_registers: Vec<u16>,
    pub discrete_inputs: Vec<bool>,
    pub coils: Vec<bool>,
    pub log: Vec<Logged>,
    pub rules: Vec<Rule>,
    pub connections: usize,
    /// Record requests in `log` (off for benchmarks, where it would only grow).
    pub record: bool,
    /// Refuse reads that touch an address the ICD does not list.
    pub strict_addresses: bool,
    killers: Vec<std::net::TcpStream>,
}

/// The address ranges the ICD lists, per table.
const DI_LISTED: [(u16, u16); 3] = [(0, 10), (32, 63), (64, 95)];
const IR_LISTED: [(u16, u16); 3] = [(0, 1), (2, 14), (34, 140)];
const HR_LISTED: [(u16, u16); 4] = [(0, 1), (100, 103), (104, 108), (200, 220)];

fn listed(ranges: &[(u16, u16)], start: u16, count: u16) -> bool {
    (start..start.saturating_add(count)).all(|a| ranges.iter().any(|(s, e)| a >= *s && a < *e))
}

/// Low word first, computed here rather than by the code under test.
pub fn cdab(value: f32) -> [u16; 2] {
    let bits = value.to_bits();
    [(bits & 0xFFFF) as u16, (bits >> 16) as u16]
}

pub fn from_cdab(words: &[u16]) -> f32 {
    f32::from_bits((u32::from(words[1]) << 16) | u32::from(words[0]))
}

impl ArmState {
    fn new() -> ArmState {
        ArmState {
            input_registers: vec![0; 140],
            holding_registers: vec![0; 220],
            discrete_inputs: vec![false; 95],
            coils: vec![false; 3],
            log: Vec::new(),
            rules: Vec::new(),
            connections: 0,
            record: true,
            strict_addresses: false,
            killers: Vec::new(),
        }
    }

    pub fn set_input_f32(&mut self, addr: usize, value: f32) {
        self.input_registers[addr..addr + 2].copy_from_slice(&cdab(value));
    }

    pub fn set_holding_f32(&mut self, addr: usize, value: f32) {
        self.holding_registers[addr..addr + 2].copy_from_slice(&cdab(value));
    }

    /// The writes received, in order.
    pub fn writes(&self) -> Vec<Written> {
        self.log
            .iter()
            .filter_map(|l| match &l.request {
                Request::WriteMultipleRegisters(a, v) => Some(Written::Registers(*a, v.to_vec())),
                Request::WriteSingleRegister(a, v) => Some(Written::Registers(*a, vec![*v])),
                Request::WriteSingleCoil(a, v) => Some(Written::Coil(*a, *v)),
                _ => None,
            })
            .collect()
    }

    /// The reads received, in order, as (function code, start, count).
    pub fn reads(&self) -> Vec<(u8, u16, u16)> {
        self.log
            .iter()
            .filter_map(|l| match &l.request {
                Request::ReadCoils(a, n) => Some((1, *a, *n)),
                Request::ReadDiscreteInputs(a, n) => Some((2, *a, *n)),
                Request::ReadHoldingRegisters(a, n) => Some((3, *a, *n)),
                Request::ReadInputRegisters(a, n) => Some((4, *a, *n)),
                _ => None,
            })
            .collect()
    }

    fn hang_up(&mut self, connection: usize) {
        if let Some(stream) = self.killers.get(connection - 1) {
            let _ = stream.shutdown(std::net::Shutdown::Both);
        }
    }

    fn apply(&mut self, request: &Request<'static>) -> Result<Response, ExceptionCode> {
        use ExceptionCode::IllegalDataAddress as Bad;
        let strict = self.strict_addresses;
        let read_words = |table: &[u16], a: u16, n: u16, ranges: &[(u16, u16)]| {
            let range = usize::from(a)..usize::from(a) + usize::from(n);
            if n == 0 || n > 125 || (strict && !listed(ranges, a, n)) {
                return Err(Bad);
            }
            table.get(range).map(<[u16]>::to_vec).ok_or(Bad)
        };
        match request {
            Request::ReadCoils(a, n) => {
                let range = usize::from(*a)..usize::from(*a) + usize::from(*n);
                self.coils
                    .get(range)
                    .map(|b| Response::ReadCoils(b.to_vec()))
                    .ok_or(Bad)
            }
            Request::ReadDiscreteInputs(a, n) => {
                if strict && !listed(&DI_LISTED, *a, *n) {
                    return Err(Bad);
                }
                let range = usize::from(*a)..usize::from(*a) + usize::from(*n);
                let bits = self.discrete_inputs.get(range).ok_or(Bad)?;
                Ok(Response::ReadDiscreteInputs(bits.to_vec()))
            }
            Request::ReadInputRegisters(a, n) => {
                read_words(&self.input_registers, *a, *n, &IR_LISTED)
                    .map(Response::ReadInputRegisters)
            }
            Request::ReadHoldingRegisters(a, n) => {
                read_words(&self.holding_registers, *a, *n, &HR_LISTED)
                    .map(Response::ReadHoldingRegisters)
            }
            Request::WriteSingleCoil(a, v) => {
                let coil = self.coils.get_mut(usize::from(*a)).ok_or(Bad)?;
                *coil = *v;
                Ok(Response::WriteSingleCoil(*a, *v))
            }
            Request::WriteMultipleRegisters(a, values) => {
                let end = usize::from(*a) + values.len();
                // Only the command block 200-219 is writable.
                if *a < 200 || end > 220 {
                    return Err(Bad);
                }
                self.holding_registers[usize::from(*a)..end].copy_from_slice(values);
                Ok(Response::WriteMultipleRegisters(*a, values.len() as u16))
            }
            _ => Err(ExceptionCode::IllegalFunction),
        }
    }
}

type Reply = Pin<Box<dyn Future<Output = Result<Option<Response>, ExceptionCode>> + Send>>;

struct FakeService {
    state: Arc<Mutex<ArmState>>,
    connection: usize,
}

impl Service for FakeService {
    type Request = SlaveRequest<'static>;
    type Response = Option<Response>;
    type Exception = ExceptionCode;
    type Future = Reply;

    fn call(&self, req: Self::Request) -> Self::Future {
        let mut state = self.state.lock().unwrap();
        let request = req.request;
        if state.record {
            state.log.push(Logged {
                unit: req.slave,
                connection: self.connection,
                request: request.clone(),
            });
        }
        let behaviour = state
            .rules
            .iter()
            .find_map(|rule| rule(&request))
            .unwrap_or(Behaviour::Answer);
        match behaviour {
            Behaviour::Answer => {
                let result = state.apply(&request).map(Some);
                Box::pin(std::future::ready(result))
            }
            Behaviour::Exception(code) => Box::pin(std::future::ready(Err(code))),
            Behaviour::Stall(d) => Box::pin(async move {
                tokio::time::sleep(d).await;
                Ok(None)
            }),
            Behaviour::HangUp => {
                state.hang_up(self.connection);
                Box::pin(std::future::ready(Ok(None)))
            }
        }
    }
}

/// A listening fake arm. Dropping it stops the server and closes its connections.
pub struct FakeArm {
    pub addr: SocketAddr,
    pub state: Arc<Mutex<ArmState>>,
    server: tokio::task::JoinHandle<()>,
}

impl FakeArm {
    pub async fn start() -> FakeArm {
        FakeArm::start_at("127.0.0.1:0".parse().unwrap()).await
    }

    /// Listens on `addr`: a fixed address brings an arm back where an earlier one was.
    pub async fn start_at(addr: SocketAddr) -> FakeArm {
        let listener = TcpListener::bind(addr).await.unwrap();
        let addr = listener.local_addr().unwrap();
        let state = Arc::new(Mutex::new(ArmState::new()));
        let shared = state.clone();
        let server = tokio::spawn(async move {
            let on_connected = move |stream: TcpStream, _peer: SocketAddr| {
                let state = shared.clone();
                async move {
                    // A duplicate of the socket lets the test hang up on the client.
                    let stream = stream.into_std()?;
                    let killer = stream.try_clone()?;
                    let stream = TcpStream::from_std(stream)?;
                    let connection = {
                        let mut s = state.lock().unwrap();
                        s.killers.push(killer);
                        s.connections += 1;
                        s.connections
                    };
                    Ok(Some((FakeService { state, connection }, stream)))
                }
            };
            let _ = Server::new(listener).serve(&on_connected, |_| {}).await;
        });
        FakeArm {
            addr,
            state,
            server,
        }
    }

    pub fn addr(&self) -> String {
        self.addr.to_string()
    }

    pub fn with<T>(&self, f: impl FnOnce(&mut ArmState) -> T) -> T {
        f(&mut self.state.lock().unwrap())
    }

    pub fn writes(&self) -> Vec<Written> {
        self.with(|s| s.writes())
    }

    pub fn rule(&self, rule: impl Fn(&Request<'static>) -> Option<Behaviour> + Send + 'static) {
        self.with(|s| s.rules.push(Box::new(rule)));
    }

    pub fn clear_rules(&self) {
        self.with(|s| s.rules.clear());
    }

    /// Closes every open connection.
    pub fn hang_up_all(&self) {
        self.with(|s| {
            for k in &s.killers {
                let _ = k.shutdown(std::net::Shutdown::Both);
            }
        });
    }

    /// Waits until `done` holds, or panics after `within`.
    pub async fn wait_for(&self, within: Duration, done: impl Fn(&ArmState) -> bool) {
        let deadline = tokio::time::Instant::now() + within;
        loop {
            if self.with(|s| done(s)) {
                return;
            }
            assert!(
                tokio::time::Instant::now() < deadline,
                "condition not met within {within:?}; writes: {:?}",
                self.writes()
            );
            tokio::time::sleep(Duration::from_millis(5)).await;
        }
    }
}

impl Drop for FakeArm {
    fn drop(&mut self) {
        self.server.abort();
        self.hang_up_all();
    }
}

/// The stop sequence: holding register 200 <- 2.
pub fn stop_write() -> Written {
    Written::Registers(200, vec![2])
}

/// A recognisable arm: every telemetry field set to a distinct value.
pub fn fill_known_telemetry(s: &mut ArmState) {
    s.input_registers[0] = 7; // ready
    s.input_registers[2] = 0x0011; // faults: bits 0 and 4
    s.input_registers[3] = 0x0080; // ... and bit 23
    s.input_registers[4] = 0x0004; // warnings: bit 2
    s.set_input_f32(6, 1.5);
    s.set_input_f32(8, 24.0);
    s.set_input_f32(10, 45.0);
    s.set_input_f32(12, 30.0);
    for j in 0..7 {
        let jf = j as f32;
        s.set_input_f32(34 + 2 * j, 10.0 + jf);
        s.set_input_f32(48 + 2 * j, 20.0 + jf);
        s.set_input_f32(62 + 2 * j, 30.0 + jf);
        s.set_input_f32(76 + 2 * j, 40.0 + jf);
        s.set_input_f32(90 + 2 * j, 50.0 + jf);
    }
    for (i, v) in [0.4566, 0.001, 0.4338, 90.0, 0.0, 90.0].iter().enumerate() {
        s.set_input_f32(104 + 2 * i, *v);
    }
    for (i, v) in [0.25, -0.5, 0.125, 1.0, 2.0, 3.0].iter().enumerate() {
        s.set_input_f32(116 + 2 * i, *v);
        s.set_input_f32(128 + 2 * i, *v * 4.0);
    }
    s.holding_registers[100] = 1; // completed
    s.holding_registers[101] = 2;
    s.holding_registers[102] = 3; // twist
    s.set_holding_f32(104, 0.5);
    s.set_holding_f32(106, 100.0);
    s.discrete_inputs[7] = true;
}
