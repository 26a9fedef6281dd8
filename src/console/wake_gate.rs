//! A stream polled only after it has asked to be: crossterm's `EventStream` spins on its reader
//! lock (a burst of `sched_yield`s) whenever it is polled while its reader thread waits for
//! input, and the event loop polls every input on each arm report (about 100 a second at rest).
//!
//! [`WakeGate`] polls the inner stream once, then again only after the inner stream woke the
//! task, or after it produced an item. The key path stays direct: the reader thread wakes the
//! event loop itself, with no task or channel in between.

use std::pin::Pin;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::task::{Context, Poll, Wake, Waker};

use futures::Stream;

/// Wraps `S`; see the module.
pub struct WakeGate<S> {
    inner: S,
    signal: Arc<Signal>,
    /// The inner stream's last answer was `Pending`: it will wake us when it has more.
    waiting: bool,
}

/// Set by the inner stream's wake; passes it on to the task polling the gate.
#[derive(Default)]
struct Signal {
    woken: AtomicBool,
    task: Mutex<Option<Waker>>,
}

impl Wake for Signal {
    fn wake(self: Arc<Self>) {
        self.wake_by_ref();
    }

    fn wake_by_ref(self: &Arc<Self>) {
        self.woken.store(true, Ordering::SeqCst);
        let task = self.task.lock().ok().and_then(|task| task.clone());
        if let Some(task) = task {
            task.wake();
        }
    }
}

impl<S> WakeGate<S> {
    pub fn new(inner: S) -> WakeGate<S> {
        WakeGate {
            inner,
            signal: Arc::default(),
            waiting: false,
        }
    }
}

impl<S: Stream + Unpin> Stream for WakeGate<S> {
    type Item = S::Item;

    fn poll_next(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<Option<S::Item>> {
        if let Ok(mut task) = self.signal.task.lock()
            && !task.as_ref().is_some_and(|t| t.will_wake(cx.waker()))
        {
            *task = Some(cx.waker().clone());
        }
        // Cleared before the inner poll: a wake during it polls again next time.
        if !self.signal.woken.swap(false, Ordering::SeqCst) && self.waiting {
            return Poll::Pending;
        }
        let waker = Waker::from(self.signal.clone());
        let polled = Pin::new(&mut self.inner).poll_next(&mut Context::from_waker(&waker));
        self.waiting = polled.is_pending();
        polled
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use futures::task::noop_waker;

    /// Counts its polls; pending until given an item, which it takes its saved waker to tell.
    #[derive(Default)]
    struct Probe {
        polls: usize,
        item: Option<u32>,
        waker: Option<Waker>,
    }

    impl Stream for Probe {
        type Item = u32;
        fn poll_next(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<Option<u32>> {
            self.polls += 1;
            match self.item.take() {
                Some(item) => Poll::Ready(Some(item)),
                None => {
                    self.waker = Some(cx.waker().clone());
                    Poll::Pending
                }
            }
        }
    }

    #[test]
    fn the_inner_stream_is_polled_again_only_after_it_woke_the_task() {
        let mut gate = WakeGate::new(Probe::default());
        let waker = noop_waker();
        let mut cx = Context::from_waker(&waker);
        let mut poll = |gate: &mut WakeGate<Probe>| Pin::new(gate).poll_next(&mut cx);

        assert_eq!(poll(&mut gate), Poll::Pending);
        assert_eq!(gate.inner.polls, 1, "the first poll goes through");
        for _ in 0..5 {
            assert_eq!(poll(&mut gate), Poll::Pending);
        }
        assert_eq!(
            gate.inner.polls, 1,
            "not polled while it waits and has not woken"
        );

        // An item comes: the inner stream wakes its task, and the next poll takes the item.
        gate.inner.item = Some(7);
        gate.inner.waker.take().expect("a waker was left").wake();
        assert_eq!(poll(&mut gate), Poll::Ready(Some(7)));
        assert_eq!(gate.inner.polls, 2);
        // After an item the inner stream is asked again (it may hold more).
        assert_eq!(poll(&mut gate), Poll::Pending);
        assert_eq!(gate.inner.polls, 3);
        assert_eq!(poll(&mut gate), Poll::Pending);
        assert_eq!(gate.inner.polls, 3);
    }

    #[test]
    fn the_inner_wake_wakes_the_task_polling_the_gate() {
        struct Flag(AtomicBool);
        impl Wake for Flag {
            fn wake(self: Arc<Self>) {
                self.0.store(true, Ordering::SeqCst);
            }
        }
        let flag = Arc::new(Flag(AtomicBool::new(false)));
        let waker = Waker::from(flag.clone());
        let mut gate = WakeGate::new(Probe::default());
        assert_eq!(
            Pin::new(&mut gate).poll_next(&mut Context::from_waker(&waker)),
            Poll::Pending
        );
        assert!(!flag.0.load(Ordering::SeqCst));
        gate.inner.waker.take().expect("a waker was left").wake();
        assert!(flag.0.load(Ordering::SeqCst), "the task was not woken");
    }
}
