//! Signals as one channel: a tokio signal receiver re-registers on every poll.

use tokio::signal::unix::{SignalKind, signal};
use tokio::sync::mpsc;

/// Sends each signal of `signals` on one channel; all registered before any is awaited.
pub fn forward<T: Copy + Send + 'static>(
    signals: &[(SignalKind, T)],
) -> std::io::Result<mpsc::UnboundedReceiver<T>> {
    let registered = signals
        .iter()
        .map(|&(kind, value)| signal(kind).map(|s| (s, value)))
        .collect::<std::io::Result<Vec<_>>>()?;
    let (tx, rx) = mpsc::unbounded_channel();
    for (mut signal, value) in registered {
        let tx = tx.clone();
        tokio::spawn(async move {
            // `None`: the runtime is shutting down and delivers no more signals.
            while signal.recv().await.is_some() {
                if tx.send(value).is_err() {
                    return;
                }
            }
        });
    }
    Ok(rx)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[tokio::test]
    async fn a_signal_arrives_as_its_value_on_the_channel() {
        let mut got = forward(&[
            (SignalKind::user_defined1(), "SIGUSR1"),
            (SignalKind::user_defined2(), "SIGUSR2"),
        ])
        .expect("signals");
        let sent = std::process::Command::new("kill")
            .args(["-USR2", &std::process::id().to_string()])
            .status()
            .expect("kill");
        assert!(sent.success());
        let first = tokio::time::timeout(std::time::Duration::from_secs(5), got.recv()).await;
        assert_eq!(first, Ok(Some("SIGUSR2")));
    }
}
