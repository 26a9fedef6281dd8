//! The terminal, read on the runtime's own thread: each wake reads and decodes every readable
//! byte (up to [`READ_BUDGET`]), so a key waits behind nothing and no other thread is woken
//! between a key and its frame; it reads again only once the loop took what it made, so a backlog
//! stays in the terminal. The descriptor is registered through tokio's pipe receiver
//! (unchecked: a tty polls as a FIFO does); `AsyncFd` would need `unsafe`.

use std::collections::VecDeque;
use std::io;
use std::os::fd::{AsFd, OwnedFd};
use std::pin::Pin;
use std::task::{Context, Poll, ready};
use std::time::{Duration, Instant};

use crossterm::event::Event;
use futures::Stream;
use rustix::event::{PollFd, PollFlags, Timespec};
use tokio::net::unix::pipe;

use super::burst::{BURST_LIMIT, Burst, Verdict};
use super::decoder::{Decoded, Decoder, PASTE_LIMIT};

/// The most read in one wake before what it made is handed over.
pub const READ_BUDGET: usize = 1024 * 1024;
/// A paste or sequence that has begun and gets no more bytes for this long has stalled.
pub const STALL: Duration = Duration::from_millis(300);
const READ_SIZE: usize = 64 * 1024;

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
    fd: pipe::Receiver,
    reader: Reader,
    /// Events read and not yet taken: what one wake's reads made.
    events: VecDeque<io::Result<TerminalEvent>>,
    /// While a paste or sequence is unfinished: when it has stalled.
    stall: Option<Pin<Box<tokio::time::Sleep>>>,
    /// SIGWINCH, passed on by a task ([`crate::console::signals`]): a turn polls a channel.
    window_changes: Option<tokio::sync::mpsc::UnboundedReceiver<()>>,
    /// The terminal closed (or failed): the stream ends once `events` is empty.
    closed: bool,
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
    let window_changes = crate::console::signals::forward(&[(
        tokio::signal::unix::SignalKind::window_change(),
        (),
    )])?;
    let mut input = TerminalInput::new(fd)?;
    input.window_changes = Some(window_changes);
    Ok(input)
}

impl TerminalInput {
    /// Reads `fd` (non-blocking) as the stream is polled, until it ends. Needs the runtime.
    pub fn new(fd: OwnedFd) -> io::Result<TerminalInput> {
        Ok(TerminalInput {
            fd: pipe::Receiver::from_owned_fd_unchecked(fd)?,
            reader: Reader::new(),
            events: VecDeque::new(),
            stall: None,
            window_changes: None,
            closed: false,
        })
    }

    /// Whether input has arrived that the event loop has not taken yet: events read, or bytes
    /// readable on the terminal now.
    pub fn input_arrived(&self) -> bool {
        if !self.events.is_empty() {
            return true;
        }
        let now = Timespec {
            tv_sec: 0,
            tv_nsec: 0,
        };
        let mut fds = [PollFd::new(&self.fd, PollFlags::IN)];
        matches!(rustix::event::poll(&mut fds, Some(&now)), Ok(n) if n > 0)
    }

    /// Reads and decodes what the terminal has, once the events read before are taken.
    fn poll_read(&mut self, cx: &mut Context<'_>) -> Poll<()> {
        loop {
            if !self.events.is_empty() || self.closed {
                return Poll::Ready(());
            }
            match self.fd.poll_read_ready(cx) {
                Poll::Ready(Ok(())) => {
                    // Emptied (a read short of the buffer, or one that found nothing), the
                    // readiness is cleared; otherwise it stays, and the next poll reads on.
                    match self.reader.drain(&self.fd, &mut self.events) {
                        Drained::Empty | Drained::More => {}
                        Drained::Closed => self.closed = true,
                        Drained::Failed(e) => {
                            self.events.push_back(Err(e));
                            self.closed = true;
                        }
                    }
                    self.stall = self
                        .reader
                        .decoder
                        .waiting()
                        .then(|| Box::pin(tokio::time::sleep(STALL)));
                }
                Poll::Ready(Err(e)) => {
                    self.events.push_back(Err(e));
                    self.closed = true;
                }
                Poll::Pending => {
                    let Some(stall) = &mut self.stall else {
                        return Poll::Pending;
                    };
                    ready!(stall.as_mut().poll(cx));
                    self.stall = None;
                    let mut decoded = Vec::new();
                    self.reader.decoder.stalled(&mut decoded);
                    self.reader
                        .hand_over(decoded, Verdict::Keys, &mut self.events);
                }
            }
        }
    }
}

impl Stream for TerminalInput {
    type Item = io::Result<TerminalEvent>;

    fn poll_next(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<Option<Self::Item>> {
        // Several changes waiting are one resize: the size is read once, as it is now.
        let mut resized = false;
        if let Some(changes) = &mut self.window_changes {
            while let Poll::Ready(Some(())) = changes.poll_recv(cx) {
                resized = true;
            }
        }
        if resized && let Ok((width, height)) = crossterm::terminal::size() {
            return Poll::Ready(Some(Ok(TerminalEvent::Event(Event::Resize(width, height)))));
        }
        ready!(self.poll_read(cx));
        Poll::Ready(self.events.pop_front())
    }
}

/// What one read got.
enum Read {
    Closed,
    /// A full buffer: more may be readable.
    Some(usize),
    /// Fewer bytes than the buffer holds: all the terminal had.
    AllThereWas(usize),
}

/// Reads what the terminal has. A short read took all there was and clears the readiness seen
/// before it (sparing the read that would find nothing); bytes that came after still wake.
fn read_all_there_is(fd: &pipe::Receiver, buffer: &mut [u8]) -> io::Result<Read> {
    let mut short = None;
    let read = fd.try_io(|| match fd.try_read(buffer) {
        Ok(read) if read > 0 && read < buffer.len() => {
            short = Some(read);
            // Not an error: how `try_io` is told to clear the readiness.
            Err(io::ErrorKind::WouldBlock.into())
        }
        other => other,
    });
    match (short, read) {
        (Some(read), _) => Ok(Read::AllThereWas(read)),
        (None, Ok(0)) => Ok(Read::Closed),
        (None, Ok(read)) => Ok(Read::Some(read)),
        (None, Err(e)) => Err(e),
    }
}

/// The decoding state.
struct Reader {
    decoder: Decoder,
    burst: Burst,
    buffer: Box<[u8]>,
}

/// What one wake's reads came to.
enum Drained {
    /// Everything readable was read.
    Empty,
    /// The budget was read: more may be readable, and is read at the next poll.
    More,
    /// The terminal closed.
    Closed,
    Failed(io::Error),
}

impl Reader {
    fn new() -> Reader {
        Reader {
            decoder: Decoder::default(),
            burst: Burst::default(),
            buffer: vec![0; READ_SIZE].into_boxed_slice(),
        }
    }

    /// Reads every readable byte (up to the budget), handing over what each read makes: a flood
    /// is judged, and its keys dropped, a read at a time, so it is never held.
    fn drain(
        &mut self,
        fd: &pipe::Receiver,
        out: &mut VecDeque<io::Result<TerminalEvent>>,
    ) -> Drained {
        let mut total = 0;
        while total < READ_BUDGET {
            let mut decoded = Vec::new();
            let key_bytes_before = self.decoder.key_bytes();
            let drained = match read_all_there_is(fd, &mut self.buffer) {
                Ok(Read::Closed) => Some(Drained::Closed),
                Ok(Read::Some(read)) => {
                    self.decoder.feed(&self.buffer[..read], &mut decoded);
                    total += read;
                    None
                }
                // What a read that found the terminal empty would have decided, decided now.
                Ok(Read::AllThereWas(read)) => {
                    self.decoder.feed(&self.buffer[..read], &mut decoded);
                    total += read;
                    self.decoder.end_of_input(&mut decoded);
                    Some(Drained::Empty)
                }
                Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => {
                    self.decoder.end_of_input(&mut decoded);
                    Some(Drained::Empty)
                }
                Err(e) => Some(Drained::Failed(e)),
            };
            let key_bytes = self.decoder.key_bytes() - key_bytes_before;
            let verdict = match key_bytes {
                0 => Verdict::Keys,
                _ => self.burst.read(key_bytes, Instant::now()),
            };
            self.hand_over(decoded, verdict, out);
            if let Some(drained) = drained {
                return drained;
            }
        }
        Drained::More
    }

    fn hand_over(
        &mut self,
        decoded: Vec<Decoded>,
        verdict: Verdict,
        out: &mut VecDeque<io::Result<TerminalEvent>>,
    ) {
        if verdict == Verdict::FloodBegins {
            out.push_back(Ok(TerminalEvent::Refused(Refusal::Flood)));
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
            out.push_back(Ok(event));
        }
    }
}
