//! A START refresh never overtakes a key that has already arrived: when a refresh falls due with
//! input waiting, the loop takes the input first (for at most [`INPUT_FIRST`]), so a release stops
//! the arm instead of following a refresh onto the wire.

use std::time::Duration;

use futures::{Stream, StreamExt};

/// Ample to read and decode waiting input, far inside the operator's 500 ms watchdog.
pub const INPUT_FIRST: Duration = Duration::from_millis(20);

/// What the loop handles when its deadline fires: the next terminal event if a refresh is due and
/// `input_waiting` (within [`INPUT_FIRST`]); `None` for the tick itself.
pub async fn waiting_input<S: Stream + Unpin>(
    refresh_due: bool,
    input_waiting: impl FnOnce() -> bool,
    keys: &mut S,
) -> Option<Option<S::Item>> {
    if !refresh_due || !input_waiting() {
        return None;
    }
    tokio::time::timeout(INPUT_FIRST, keys.next()).await.ok()
}

#[cfg(test)]
mod tests {
    use super::*;
    use futures::stream;

    #[tokio::test(start_paused = true)]
    async fn a_due_refresh_takes_the_waiting_release_first() {
        let mut keys = stream::iter(["release"]);
        let got = waiting_input(true, || true, &mut keys).await;
        assert_eq!(got, Some(Some("release")));
    }

    #[tokio::test(start_paused = true)]
    async fn a_release_that_comes_within_the_wait_is_taken() {
        let (tx, rx) = tokio::sync::mpsc::unbounded_channel();
        let mut keys = tokio_stream_of(rx);
        tokio::spawn(async move {
            tokio::time::sleep(INPUT_FIRST / 2).await;
            let _ = tx.send("release");
        });
        let got = waiting_input(true, || true, &mut keys).await;
        assert_eq!(got, Some(Some("release")));
    }

    #[tokio::test(start_paused = true)]
    async fn readable_bytes_that_make_no_event_delay_the_tick_by_at_most_the_wait() {
        let mut keys = stream::pending::<&str>();
        let started = tokio::time::Instant::now();
        assert_eq!(waiting_input(true, || true, &mut keys).await, None);
        assert_eq!(started.elapsed(), INPUT_FIRST);
    }

    #[tokio::test(start_paused = true)]
    async fn without_a_refresh_due_or_input_waiting_the_tick_goes_at_once() {
        let started = tokio::time::Instant::now();
        let mut keys = stream::iter(["press"]);
        let mut asked = false;
        assert_eq!(
            waiting_input(
                false,
                || {
                    asked = true;
                    true
                },
                &mut keys
            )
            .await,
            None
        );
        assert!(!asked, "no refresh due: the terminal is not even asked");
        assert_eq!(waiting_input(true, || false, &mut keys).await, None);
        assert_eq!(started.elapsed(), Duration::ZERO);
        assert_eq!(
            keys.next().await,
            Some("press"),
            "the key is left for the loop"
        );
    }

    fn tokio_stream_of<T>(
        mut rx: tokio::sync::mpsc::UnboundedReceiver<T>,
    ) -> impl Stream<Item = T> + Unpin {
        Box::pin(stream::poll_fn(move |cx| rx.poll_recv(cx)))
    }
}
