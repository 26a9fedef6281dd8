//! The simulated arm's Kinova Modbus TCP server (tokio-modbus). Any unit id is answered.

use std::future::Future;
use std::net::SocketAddr;
use std::pin::Pin;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

use tokio::net::{TcpListener, TcpStream};
use tokio::sync::watch;
use tokio_modbus::server::Service;
use tokio_modbus::server::tcp::Server;
use tokio_modbus::{ExceptionCode, Request, Response, SlaveRequest};

use super::UnlistedReads;
use super::modbus_frames::{self, Relay};
use super::modbus_registers::{
    self as registers, COILS, DISCRETE_INPUTS, HOLDING_REGISTERS, INPUT_REGISTERS, Refused,
};
use super::talos_server::NetworkFaults;
use super::world::{SimArm, World};
use crate::kortex::registers::{MAX_REGISTERS_PER_WRITE, Table};

/// Most coils one write may carry (Modbus application protocol, FC 15); reads and register
/// writes are bounded by [`Table::max_read`] and [`MAX_REGISTERS_PER_WRITE`].
const MAX_WRITE_COILS: u16 = 1968;

/// Pause after a failed accept before accepting again.
const ACCEPT_RETRY: Duration = Duration::from_millis(50);

type Reply = Pin<Box<dyn Future<Output = Result<Option<Response>, ExceptionCode>> + Send>>;

struct ArmService {
    arm: SimArm,
    unlisted: UnlistedReads,
    faults: watch::Receiver<NetworkFaults>,
    replies: Arc<AtomicU64>,
    /// Ends the connection's frame relay with the service.
    _relay: Relay,
}

impl Service for ArmService {
    type Request = SlaveRequest<'static>;
    type Response = Option<Response>;
    type Exception = ExceptionCode;
    type Future = Reply;

    fn call(&self, req: Self::Request) -> Self::Future {
        let arm = self.arm.clone();
        let faults = self.faults.borrow().clone();
        let n = self.replies.fetch_add(1, Ordering::Relaxed) + 1;
        let request = req.request;
        let unlisted = self.unlisted;
        Box::pin(async move {
            let answer = arm
                .with_world(move |world| serve(world, &request, unlisted))
                .await
                .map_err(|_| ExceptionCode::ServerDeviceFailure)?;
            if !faults.reply_delay.is_zero() {
                tokio::time::sleep(faults.reply_delay).await;
            }
            let nth = u64::from(faults.drop_every_nth_reply);
            if nth != 0 && n.is_multiple_of(nth) {
                return Ok(None);
            }
            answer.map(Some)
        })
    }
}

fn refused(r: Refused) -> ExceptionCode {
    match r {
        Refused::IllegalAddress => ExceptionCode::IllegalDataAddress,
        Refused::IllegalValue => ExceptionCode::IllegalDataValue,
    }
}

/// One request against the world.
fn serve(
    world: &mut World,
    request: &Request<'static>,
    unlisted: UnlistedReads,
) -> Result<Response, ExceptionCode> {
    let snapshot = || world.arm.snapshot();
    let check = |ranges: &[(u16, u16)], start: u16, count: u16, max: u16| {
        if count == 0 || count > max {
            Err(ExceptionCode::IllegalDataValue)
        } else if !registers::listed(ranges, start, count) {
            Err(ExceptionCode::IllegalDataAddress)
        } else {
            Ok(usize::from(start)..usize::from(start) + usize::from(count))
        }
    };
    // A read may span unlisted addresses inside the image when the arm answers them.
    let check_read = |ranges: &[(u16, u16)], table: Table, start: u16, count: u16| {
        let max = table.max_read();
        let image = [(0, ranges.iter().map(|(_, end)| *end).max().unwrap_or(0))];
        match unlisted {
            UnlistedReads::Refuse => check(ranges, start, count, max),
            UnlistedReads::Zero => check(&image, start, count, max),
        }
    };
    match request {
        Request::ReadDiscreteInputs(start, count) => {
            let range = check_read(&DISCRETE_INPUTS, Table::DiscreteInputs, *start, *count)?;
            let bits = registers::discrete_inputs(&snapshot());
            Ok(Response::ReadDiscreteInputs(bits[range].to_vec()))
        }
        Request::ReadCoils(start, count) => {
            let range = check_read(&COILS, Table::Coils, *start, *count)?;
            Ok(Response::ReadCoils(vec![false; range.len()]))
        }
        Request::ReadInputRegisters(start, count) => {
            let range = check_read(&INPUT_REGISTERS, Table::InputRegisters, *start, *count)?;
            let words = registers::input_registers(&snapshot());
            Ok(Response::ReadInputRegisters(words[range].to_vec()))
        }
        Request::ReadHoldingRegisters(start, count) => {
            let range = check_read(&HOLDING_REGISTERS, Table::HoldingRegisters, *start, *count)?;
            let words = registers::holding_registers(&snapshot(), &world.command_block);
            Ok(Response::ReadHoldingRegisters(words[range].to_vec()))
        }
        Request::WriteSingleRegister(addr, value) => {
            registers::write_registers(world, *addr, &[*value]).map_err(refused)?;
            Ok(Response::WriteSingleRegister(*addr, *value))
        }
        Request::WriteMultipleRegisters(addr, values) => {
            let count = u16::try_from(values.len()).map_err(|_| ExceptionCode::IllegalDataValue)?;
            if count == 0 || count > MAX_REGISTERS_PER_WRITE {
                return Err(ExceptionCode::IllegalDataValue);
            }
            registers::write_registers(world, *addr, values).map_err(refused)?;
            Ok(Response::WriteMultipleRegisters(*addr, count))
        }
        Request::WriteSingleCoil(addr, value) => {
            registers::write_coil(world, *addr, *value).map_err(refused)?;
            Ok(Response::WriteSingleCoil(*addr, *value))
        }
        Request::WriteMultipleCoils(addr, values) => {
            let count = u16::try_from(values.len()).map_err(|_| ExceptionCode::IllegalDataValue)?;
            let range = check(&COILS, *addr, count, MAX_WRITE_COILS)?;
            for (coil_addr, v) in range.zip(values.iter()) {
                // `check` keeps the range inside the listed coils, so it fits a u16.
                let coil_addr =
                    u16::try_from(coil_addr).map_err(|_| ExceptionCode::IllegalDataAddress)?;
                registers::write_coil(world, coil_addr, *v).map_err(refused)?;
            }
            Ok(Response::WriteMultipleCoils(*addr, count))
        }
        _ => Err(ExceptionCode::IllegalFunction),
    }
}

/// Serves Modbus TCP on `listener` until the task is aborted.
pub async fn serve_on(
    listener: TcpListener,
    arm: SimArm,
    faults: watch::Receiver<NetworkFaults>,
    unlisted: UnlistedReads,
) {
    let replies = Arc::new(AtomicU64::new(0));
    let on_connected = move |stream: TcpStream, peer: SocketAddr| {
        tracing::info!("sim modbus: client {peer} connected");
        let (stream, relay) = modbus_frames::guard(stream);
        let service = ArmService {
            arm: arm.clone(),
            unlisted,
            faults: faults.clone(),
            replies: replies.clone(),
            _relay: relay,
        };
        async move { Ok(Some((service, stream))) }
    };
    let on_error = |e| tracing::warn!("sim modbus: {e}");
    let server = Server::new(listener);
    // `serve` returns on a failed accept: serve again after a pause.
    loop {
        if let Err(e) = server.serve(&on_connected, on_error).await {
            tracing::warn!(
                "sim modbus: accepting failed ({e}); its open connections were closed; serving again in {ACCEPT_RETRY:?}"
            );
        }
        tokio::time::sleep(ACCEPT_RETRY).await;
    }
}
