//! A TCP connection within a deadline, lookup included, failing alike for both links.

use std::time::Duration;

use tokio::net::TcpStream;

use super::io_error_words;

/// Why no connection was opened: the address and the failure in words, never an errno.
#[derive(Debug, thiserror::Error)]
pub enum ConnectError {
    #[error("cannot resolve {addr}: {}", io_error_words(.source))]
    Resolve {
        addr: String,
        source: std::io::Error,
    },
    /// Every address was tried and none accepted: refused, unreachable, reset, ...
    #[error("cannot connect to {addr}: {}", io_error_words(.source))]
    Refused {
        addr: String,
        source: std::io::Error,
    },
    #[error("cannot connect to {addr}: timed out after {after:?}")]
    Timeout { addr: String, after: Duration },
}

/// Tries every address `addr` resolves to within `timeout`; Nagle off for small exchanges.
pub async fn connect_with_timeout(
    addr: &str,
    timeout: Duration,
) -> Result<TcpStream, ConnectError> {
    let connect = async {
        let addrs: Vec<_> = tokio::net::lookup_host(addr)
            .await
            .map_err(|source| ConnectError::Resolve {
                addr: addr.to_string(),
                source,
            })?
            .collect();
        let mut last = None;
        for a in addrs {
            match TcpStream::connect(a).await {
                Ok(stream) => return Ok(stream),
                Err(e) => last = Some(e),
            }
        }
        Err(ConnectError::Refused {
            addr: addr.to_string(),
            source: last
                .unwrap_or_else(|| std::io::Error::other("the name resolved to no address")),
        })
    };
    let timed_out = |_| ConnectError::Timeout {
        addr: addr.to_string(),
        after: timeout,
    };
    let stream = tokio::time::timeout(timeout, connect)
        .await
        .map_err(timed_out)??;
    let _ = stream.set_nodelay(true);
    Ok(stream)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[tokio::test]
    async fn a_closed_port_is_refused_naming_the_address() {
        let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
        let addr = listener.local_addr().unwrap().to_string();
        drop(listener);
        let err = connect_with_timeout(&addr, Duration::from_secs(5))
            .await
            .unwrap_err();
        assert!(matches!(err, ConnectError::Refused { .. }), "{err:?}");
        assert!(err.to_string().contains(&addr), "{err}");
        assert!(err.to_string().contains("connection refused"), "{err}");
        assert!(!err.to_string().contains("os error"), "{err}");
    }

    #[tokio::test]
    async fn an_unresolvable_name_says_so() {
        let err = connect_with_timeout("no-such-host.invalid:1", Duration::from_secs(5))
            .await
            .unwrap_err();
        assert!(err.to_string().contains("no-such-host.invalid:1"), "{err}");
    }
}
