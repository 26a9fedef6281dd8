//! A `select!` loop's deadline kept from turn to turn: a `sleep_until` in the loop is a new timer
//! each turn, and registering one earlier than the runtime's next wake-up costs a syscall and a
//! wake-up. A [`Deadline`] is re-armed only when it moves.

use std::pin::Pin;
use std::time::Duration;

use tokio::time::{Instant, Sleep};

pub struct Deadline {
    sleep: Pin<Box<Sleep>>,
    at: Option<Instant>,
}

impl Deadline {
    /// Off until [`Deadline::set`]. Needs the runtime.
    pub fn new() -> Deadline {
        Deadline {
            sleep: Box::pin(tokio::time::sleep(Duration::ZERO)),
            at: None,
        }
    }

    /// `None`: off ([`Deadline::armed`] is false).
    pub fn set(&mut self, at: Option<Instant>) {
        if at != self.at {
            if let Some(at) = at {
                self.sleep.as_mut().reset(at);
            }
            self.at = at;
        }
    }

    pub fn armed(&self) -> bool {
        self.at.is_some()
    }

    /// Ready once past (at once if past, every time asked); poll only while [`Deadline::armed`].
    pub fn fired(&mut self) -> &mut Pin<Box<Sleep>> {
        &mut self.sleep
    }
}

impl Default for Deadline {
    fn default() -> Self {
        Deadline::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[tokio::test(start_paused = true)]
    async fn fires_at_the_deadline_set_last_and_not_while_off() {
        let mut deadline = Deadline::new();
        assert!(!deadline.armed());
        let start = Instant::now();
        deadline.set(Some(start + Duration::from_millis(50)));
        deadline.set(Some(start + Duration::from_millis(20)));
        deadline.fired().await;
        assert_eq!(start.elapsed(), Duration::from_millis(20));
        // Passed, it stays ready until moved.
        deadline.fired().await;
        assert_eq!(start.elapsed(), Duration::from_millis(20));
        deadline.set(Some(start + Duration::from_millis(70)));
        deadline.fired().await;
        assert_eq!(start.elapsed(), Duration::from_millis(70));
        deadline.set(None);
        assert!(!deadline.armed());
    }
}
