//! Signals as one channel, fed by a task per signal: a tokio signal receiver re-registers on every
//! poll, and the event loop polls its inputs on every turn.

use tokio::signal::unix::{SignalKind, signal};
use tokio::sync::mpsc;

/// Each signal in `signals` sends its value on the returned channel. All are registered before any
/// is awaited, so a failure leaves none half set up. Tasks end with the receiver or runtime.
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
