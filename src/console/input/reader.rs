//! The terminal, read by the console itself on a thread of its own: on each wake every readable
//! byte is read and decoded at once (up to [`READ_BUDGET`]), so a key waits behind nothing that
//! came before it. The thread hands events to the event loop over a bounded channel: when the
//! loop falls behind, the thread waits and the terminal holds the rest, never this process.
//! (tokio's `AsyncFd` would need `unsafe` to register the descriptor.)

use std::io;
use std::os::fd::{AsFd, OwnedFd};
use std::pin::Pin;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::task::{Context, Poll};
use std::time::{Duration, Instant};

use crossterm::event::Event;
use futures::Stream;
use rustix::event::{PollFd, PollFlags, Timespec};
use tokio::sync::mpsc;

use super::burst::{BURST_LIMIT, Burst, Verdict};
use super::decoder::{Decoded, Decoder, PASTE_LIMIT};

/// The most read in one wake before what it made is handed over.
pub const READ_BUDGET: usize = 1024 * 1024;
/// A paste or sequence that has begun and gets no more bytes for this long has stalled.
pub const STALL: Duration = Duration::from_millis(300);
const READ_SIZE: usize = 64 * 1024;
/// Events handed over and not yet taken, at most.
const QUEUE: usize = 1024;

/// What the terminal gave.
#[derive(Debug, Clone, PartialEq)]
pub enum TerminalEvent {
    Event(Event),
    /// Bracketed-paste text: never keys.
    Paste(String),
    /// Input that was dropped unread: the console stops and says why.
    Refused(Refusal),
}

/// Why input was dropped.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum Refusal {
    #[error("paste ignored: {bytes} bytes is over the {PASTE_LIMIT}-byte limit")]
    PasteTooLong { bytes: usize },
    #[error("paste ignored: its end never came ({bytes} bytes)")]
    PasteUnfinished { bytes: usize },
    #[error("keys ignored: over {BURST_LIMIT} bytes came faster than anyone types")]
    Flood,
}

/// The terminal's input as a stream of [`TerminalEvent`]s.
pub struct TerminalInput {
    events: mpsc::Receiver<io::Result<TerminalEvent>>,
    window_changes: Option<tokio::signal::unix::Signal>,
    /// Set by the thread from the moment the terminal is readable until what it read is
    /// handed over: input that has arrived but is not yet an event.
    reading: Arc<AtomicBool>,
}

/// The controlling terminal, opened for reading on its own (non-blocking) file description:
/// stdin's own stays blocking, and so does the stdout it may share.
pub fn open() -> io::Result<TerminalInput> {
    use rustix::fs::{Mode, OFlags};
    use std::io::IsTerminal;
    let flags = OFlags::RDONLY | OFlags::NONBLOCK | OFlags::CLOEXEC | OFlags::NOCTTY;
    let stdin = std::io::stdin();
    let path = match stdin.is_terminal() {
        true => rustix::termios::ttyname(stdin.as_fd(), Vec::new())?,
        false => c"/dev/tty".into(),
    };
    let fd: OwnedFd = rustix::fs::open(path.as_c_str(), flags, Mode::empty())?;
    let window_changes =
        tokio::signal::unix::signal(tokio::signal::unix::SignalKind::window_change())?;
    let mut input = TerminalInput::spawn(fd)?;
    input.window_changes = Some(window_changes);
    Ok(input)
}

impl TerminalInput {
    /// Reads `fd` (non-blocking) on a new thread until it ends or the stream is dropped.
    pub fn spawn<F: AsFd + Send + 'static>(fd: F) -> io::Result<TerminalInput> {
        let (sender, events) = mpsc::channel(QUEUE);
        let reading = Arc::new(AtomicBool::new(false));
        let flag = reading.clone();
        std::thread::Builder::new()
            .name("terminal input".into())
            .spawn(move || {
                let mut reader = Reader::new(sender, flag);
                if let Err(e) = reader.run(fd) {
                    let _ = reader.sender.blocking_send(Err(e));
                }
            })?;
        Ok(TerminalInput {
            events,
            window_changes: None,
            reading,
        })
    }

    /// Whether input has arrived that the event loop has not taken yet: events handed over,
    /// or bytes the thread is reading and decoding now. (Bytes still unread on the terminal
    /// are [`crate::console::terminal::input_waiting`]'s to tell.)
    pub fn input_arrived(&self) -> bool {
        self.reading.load(Ordering::SeqCst) || !self.events.is_empty()
    }
}

impl Stream for TerminalInput {
    type Item = io::Result<TerminalEvent>;

    fn poll_next(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<Option<Self::Item>> {
        if let Some(changes) = &mut self.window_changes
            && changes.poll_recv(cx).is_ready()
            && let Ok((width, height)) = crossterm::terminal::size()
        {
            return Poll::Ready(Some(Ok(TerminalEvent::Event(Event::Resize(width, height)))));
        }
        self.events.poll_recv(cx)
    }
}

/// The reading thread's state.
struct Reader {
    decoder: Decoder,
    burst: Burst,
    buffer: Box<[u8]>,
    sender: mpsc::Sender<io::Result<TerminalEvent>>,
    /// [`TerminalInput::input_arrived`]'s flag.
    reading: Arc<AtomicBool>,
}

/// The event loop has gone (or the terminal has closed): the thread ends.
struct Gone;

impl Reader {
    fn new(sender: mpsc::Sender<io::Result<TerminalEvent>>, reading: Arc<AtomicBool>) -> Reader {
        Reader {
            decoder: Decoder::default(),
            burst: Burst::default(),
            buffer: vec![0; READ_SIZE].into_boxed_slice(),
            sender,
            reading,
        }
    }

    fn run(&mut self, fd: impl AsFd) -> io::Result<()> {
        loop {
            // Inside a paste or sequence the rest comes at once, or it has stalled.
            let stall = Timespec {
                tv_sec: 0,
                tv_nsec: STALL.as_nanos() as i64,
            };
            let timeout = self.decoder.waiting().then_some(&stall);
            let mut fds = [PollFd::new(&fd, PollFlags::IN)];
            let handed = match rustix::event::poll(&mut fds, timeout) {
                Ok(0) => {
                    let mut decoded = Vec::new();
                    self.decoder.stalled(&mut decoded);
                    self.hand_over(decoded, Verdict::Keys)
                }
                Ok(_) => {
                    // Set before the bytes leave the terminal, cleared once they are events.
                    self.reading.store(true, Ordering::SeqCst);
                    let drained = self.drain(&fd);
                    self.reading.store(false, Ordering::SeqCst);
                    drained?
                }
                Err(rustix::io::Errno::INTR) => Ok(()),
                Err(e) => return Err(e.into()),
            };
            if handed.is_err() {
                return Ok(());
            }
        }
    }

    /// Reads every readable byte (up to the budget), handing over what each read makes: a
    /// flood is judged, and its keys dropped, a read at a time, so it is never held.
    fn drain(&mut self, fd: &impl AsFd) -> io::Result<Result<(), Gone>> {
        let mut total = 0;
        while total < READ_BUDGET {
            let mut decoded = Vec::new();
            let key_bytes_before = self.decoder.key_bytes();
            let closed = match rustix::io::read(fd, &mut self.buffer[..]) {
                Ok(0) => true,
                Ok(read) => {
                    self.decoder.feed(&self.buffer[..read], &mut decoded);
                    total += read;
                    false
                }
                Err(rustix::io::Errno::INTR) => continue,
                Err(rustix::io::Errno::AGAIN) => {
                    self.decoder.end_of_input(&mut decoded);
                    total = READ_BUDGET;
                    false
                }
                Err(e) => return Err(e.into()),
            };
            let key_bytes = self.decoder.key_bytes() - key_bytes_before;
            let verdict = match key_bytes {
                0 => Verdict::Keys,
                _ => self.burst.read(key_bytes, Instant::now()),
            };
            if let Err(gone) = self.hand_over(decoded, verdict) {
                return Ok(Err(gone));
            }
            if closed {
                return Ok(Err(Gone));
            }
        }
        Ok(Ok(()))
    }

    fn hand_over(&mut self, decoded: Vec<Decoded>, verdict: Verdict) -> Result<(), Gone> {
        if verdict == Verdict::FloodBegins {
            self.send(TerminalEvent::Refused(Refusal::Flood))?;
        }
        for item in decoded {
            let event = match item {
                // A flood's keys are dropped; its pastes and focus changes are not keys.
                Decoded::Event(Event::Key(_)) if verdict != Verdict::Keys => continue,
                Decoded::Event(event) => TerminalEvent::Event(event),
                Decoded::Paste(text) => TerminalEvent::Paste(text),
                Decoded::PasteRefused { bytes, finished } => {
                    TerminalEvent::Refused(match finished {
                        true => Refusal::PasteTooLong { bytes },
                        false => Refusal::PasteUnfinished { bytes },
                    })
                }
            };
            self.send(event)?;
        }
        Ok(())
    }

    fn send(&self, event: TerminalEvent) -> Result<(), Gone> {
        self.sender.blocking_send(Ok(event)).map_err(|_| Gone)
    }
}
