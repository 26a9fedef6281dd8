//! One request on the wire: connect, a read or write within the timeout, a typed result.

use std::borrow::Cow;
use std::time::Duration;

use tokio_modbus::client::{Client, Context};
use tokio_modbus::{Request, Response, Slave};

use super::{ModbusConfig, ModbusError, Operation};
use crate::kortex::{ReadBlock, RegisterImage, Table, Write};
use crate::net::connect_with_timeout;

/// Opens a fresh connection (TCP, or in-memory in tests), for the first and every reconnect.
pub(super) type Connector = std::sync::Arc<
    dyn Fn() -> futures::future::BoxFuture<'static, Result<Context, ModbusError>> + Send + Sync,
>;

/// The connector that dials `config.addr` over TCP within the connect timeout (lookup included),
/// trying every address.
pub(super) fn tcp_connector(config: &ModbusConfig) -> Connector {
    let config = config.clone();
    std::sync::Arc::new(move || {
        let config = config.clone();
        Box::pin(async move {
            let stream = connect_with_timeout(&config.addr, config.connect_timeout).await?;
            Ok(attach(stream, &config))
        })
    })
}

/// Runs the Modbus TCP client over an already connected transport.
pub(super) fn attach<T>(transport: T, config: &ModbusConfig) -> Context
where
    T: tokio::io::AsyncRead + tokio::io::AsyncWrite + Send + Unpin + std::fmt::Debug + 'static,
{
    tokio_modbus::client::tcp::attach_slave(transport, Slave(config.unit))
}

/// Sends one request and returns its response, or the typed reason there is none.
async fn call(
    ctx: &mut Context,
    operation: &Operation,
    request: Request<'_>,
    timeout: Duration,
) -> Result<Response, ModbusError> {
    match tokio::time::timeout(timeout, ctx.call(request)).await {
        Err(_) => Err(ModbusError::Timeout {
            operation: operation.clone(),
            after: timeout,
        }),
        Ok(Err(tokio_modbus::Error::Transport(source))) => Err(ModbusError::Transport {
            operation: operation.clone(),
            source,
        }),
        Ok(Err(tokio_modbus::Error::Protocol(e))) => Err(ModbusError::Protocol {
            operation: operation.clone(),
            detail: e.to_string(),
        }),
        Ok(Ok(Err(exception))) => Err(ModbusError::Exception {
            operation: operation.clone(),
            exception,
        }),
        Ok(Ok(Ok(response))) => Ok(response),
    }
}

fn mismatch(operation: &Operation, response: &Response) -> ModbusError {
    ModbusError::Protocol {
        operation: operation.clone(),
        detail: format!("unexpected response {response:?}"),
    }
}

/// Reads one block into the image. A reply of the wrong kind or length is a protocol error.
pub(super) async fn read(
    ctx: &mut Context,
    block: ReadBlock,
    image: &mut RegisterImage,
    timeout: Duration,
) -> Result<(), ModbusError> {
    let operation = Operation::Read(block);
    let request = match block.table {
        Table::Coils => Request::ReadCoils(block.start, block.count),
        Table::DiscreteInputs => Request::ReadDiscreteInputs(block.start, block.count),
        Table::InputRegisters => Request::ReadInputRegisters(block.start, block.count),
        Table::HoldingRegisters => Request::ReadHoldingRegisters(block.start, block.count),
    };
    let response = call(ctx, &operation, request, timeout).await?;
    let stored = match (&block.table, &response) {
        (Table::DiscreteInputs, Response::ReadDiscreteInputs(bits)) => {
            image.store_bits(block, bits)
        }
        (Table::InputRegisters, Response::ReadInputRegisters(words))
        | (Table::HoldingRegisters, Response::ReadHoldingRegisters(words)) => {
            image.store_words(block, words)
        }
        _ => return Err(mismatch(&operation, &response)),
    };
    stored.map_err(|e| ModbusError::Protocol {
        operation,
        detail: e.to_string(),
    })
}

/// Sends one write and checks the arm's echo of it.
pub(super) async fn write(
    ctx: &mut Context,
    write: &Write,
    timeout: Duration,
) -> Result<(), ModbusError> {
    let operation = Operation::Write(write.clone());
    match write {
        Write::Registers { addr, values } => {
            let request = Request::WriteMultipleRegisters(*addr, Cow::Borrowed(values));
            match call(ctx, &operation, request, timeout).await? {
                Response::WriteMultipleRegisters(a, n)
                    if a == *addr && usize::from(n) == values.len() =>
                {
                    Ok(())
                }
                other => Err(mismatch(&operation, &other)),
            }
        }
        Write::Coil { addr, value } => {
            let request = Request::WriteSingleCoil(*addr, *value);
            match call(ctx, &operation, request, timeout).await? {
                Response::WriteSingleCoil(a, v) if a == *addr && v == *value => Ok(()),
                other => Err(mismatch(&operation, &other)),
            }
        }
    }
}
