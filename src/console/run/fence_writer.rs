//! Writes a taught fence into its profile off the event loop, one write at a time: a change made
//! while one is written waits, and only the newest waiting one is written (it holds the others).

use tokio::sync::mpsc;

use crate::console::app::FenceChange;
use crate::console::fence_file::{FenceSave, write_fence};

pub struct FenceWriter {
    writing: bool,
    waiting: Option<FenceChange>,
    done: mpsc::UnboundedSender<Result<(), String>>,
    /// Each write's outcome, for `Input::FenceSaved`.
    pub outcomes: mpsc::UnboundedReceiver<Result<(), String>>,
}

impl FenceWriter {
    pub fn new() -> FenceWriter {
        let (done, outcomes) = mpsc::unbounded_channel();
        FenceWriter {
            writing: false,
            waiting: None,
            done,
            outcomes,
        }
    }

    /// Writes `change` now, or once the write under way has ended.
    pub fn write(&mut self, change: FenceChange) {
        if self.writing {
            self.waiting = Some(change);
            return;
        }
        self.writing = true;
        let done = self.done.clone();
        tokio::task::spawn_blocking(move || {
            let save = FenceSave {
                file: change.file,
                arm: change.arm,
                fence: change.fence,
                new_profile: change.new_profile,
            };
            let _ = done.send(write_fence(&save).map_err(|e| e.to_string()));
        });
    }

    /// A write ended: the one waiting, if any, goes next.
    pub fn ended(&mut self) {
        self.writing = false;
        if let Some(next) = self.waiting.take() {
            self.write(next);
        }
    }
}
