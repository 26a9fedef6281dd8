//! Where a key's time goes on its way to the wire: marks at each stage of the key path, for
//! `benches/key_stages.py`. Built only with the `key-stages` feature; without it every mark is
//! an empty function the compiler drops, so the console's key path is unchanged.
//!
//! The marks are kept in memory on the thread that makes them (the runtime's one thread, which
//! carries the whole key path) and written out when the process ends, so measuring costs the
//! key path a clock read per stage and no IO.

/// A point on the key path, in the order a key passes them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub enum Stage {
    /// The runtime's thread woke from its wait for events (`on_thread_unpark`).
    Woken = 0,
    /// The terminal's bytes were read (`console/input/reader.rs`).
    Read = 1,
    /// The event loop has the key as the app's input (`console/run.rs`).
    Input = 2,
    /// `App::handle` returned its effects.
    Decided = 3,
    /// The effects' commands are with the driver.
    Handed = 4,
    /// The driver's task took a command (`link/driver/event_loop.rs`).
    DriverTook = 5,
    /// The driver routed it to a link.
    Routed = 6,
    /// The Talos link's task took the request (`link/talos/task.rs`).
    LinkTook = 7,
    /// The request's frame was encoded.
    Encoded = 8,
    /// The frame's write returned.
    Written = 9,
    /// The event loop went on after the frames were out.
    Resumed = 10,
    /// The runtime's thread went back to waiting (`on_thread_park`).
    Parked = 11,
}

#[cfg(feature = "key-stages")]
mod marks {
    use super::Stage;
    use std::cell::RefCell;
    use std::io::Write as _;
    use std::time::Instant;

    /// Enough for some hours of jogging; later marks are dropped, not grown into.
    const CAPACITY: usize = 1 << 20;

    thread_local! {
        static MARKS: RefCell<Vec<(Stage, Instant)>> = RefCell::new(Vec::with_capacity(CAPACITY));
    }

    pub fn watch_runtime(builder: &mut tokio::runtime::Builder) {
        builder
            .on_thread_unpark(|| mark(Stage::Woken))
            .on_thread_park(|| mark(Stage::Parked));
    }

    pub fn mark(stage: Stage) {
        let now = Instant::now();
        MARKS.with(|marks| {
            let mut marks = marks.borrow_mut();
            if marks.len() < CAPACITY {
                marks.push((stage, now));
            }
        });
    }

    /// Writes this thread's marks to the file `ARMJOG_KEY_STAGES` names, one `stage ns` line
    /// each (ns since the first mark). Nothing is written when the variable is unset.
    pub fn write_out() -> std::io::Result<()> {
        let Some(path) = std::env::var_os("ARMJOG_KEY_STAGES") else {
            return Ok(());
        };
        MARKS.with(|marks| {
            let marks = marks.borrow();
            let mut out = std::io::BufWriter::new(std::fs::File::create(&path)?);
            if let Some(&(_, first)) = marks.first() {
                for &(stage, at) in marks.iter() {
                    writeln!(
                        out,
                        "{} {}",
                        stage as u8,
                        at.duration_since(first).as_nanos()
                    )?;
                }
            }
            out.flush()
        })
    }
}

#[cfg(not(feature = "key-stages"))]
mod marks {
    use super::Stage;

    #[inline(always)]
    pub fn mark(_stage: Stage) {}

    pub fn watch_runtime(_builder: &mut tokio::runtime::Builder) {}

    pub fn write_out() -> std::io::Result<()> {
        Ok(())
    }
}

/// Marks `Woken` and `Parked` from the runtime's own hooks (the console's runtime only).
pub use marks::watch_runtime;
pub use marks::{mark, write_out};
