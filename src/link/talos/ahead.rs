//! The stop set written ahead: encoded by the link task whenever it owes one, written by the
//! console's terminal reader the moment it reads the release of the jog key that moves the arm.
//!
//! Why: a release's STOP otherwise goes through the app, the driver and the link task before it
//! is written, and under load that path is most of the key's latency (`benches/pty_latency.py`,
//! issue 21). Written ahead, the stop set leaves in the read's own turn. It is an addition, not a
//! replacement: the release still reaches the app, which decides the stop as before, and its own
//! stop set follows through the link task. Whenever the stop set cannot be written whole and at
//! once (no link, nothing owed, the link task mid-write) nothing is written here and the app's
//! stop set is the only one.
//!
//! Two writers on one socket, so:
//! - The stop set is written only between the link task's writes, never inside one
//!   ([`StopAhead::write_now`] refuses while the link task writes), under the slot's lock.
//! - Bytes the socket did not take are written by the link task before anything of its own.
//! - The frames written here become the link task's (pending, their replies paired, an ack-dialect
//!   STOP sent again without its ACK) before it writes anything or reads a reply: so the
//!   ack dialect's in-order pairing holds.
//! - Their ids are taken from the link's own count when they are encoded: never reused.

use std::io::{self, Write};
use std::sync::{Arc, Mutex, MutexGuard};

use tokio::sync::Notify;

use crate::net::hand_off;
use crate::talos::Request;

/// A socket the stop set can be written to without waiting: the link's own, duplicated.
pub type AheadSocket = Box<dyn Write + Send>;

/// The slot a console shares with its Talos link: the link arms it, the terminal reader fires
/// it. Cheap to clone.
#[derive(Clone, Default)]
pub struct StopAhead {
    slot: Arc<Mutex<Slot>>,
    /// Told when the stop set was written: the link task takes its frames.
    written: Arc<Notify>,
}

impl std::fmt::Debug for StopAhead {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("StopAhead")
    }
}

/// What [`StopAhead::write_now`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AheadOutcome {
    /// The stop set went to the socket (all of it, or the rest is the link task's to write).
    Written,
    /// No link is attached.
    NoLink,
    /// The link owes no stop, or the armed set was written already.
    NothingOwed,
    /// The link task is in a write: the app's stop set follows it.
    LinkWriting,
    /// The socket took nothing (full, or failed): the app's stop set goes the usual way.
    NotTaken(io::ErrorKind),
}

/// One frame of the stop set: its id, what it asks, its bytes.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct AheadFrame {
    pub(super) id: u32,
    pub(super) request: Request,
    pub(super) bytes: Vec<u8>,
}

#[derive(Default)]
struct Slot {
    socket: Option<AheadSocket>,
    /// Which link attached the socket: a link that ended detaches only its own.
    generation: u64,
    /// The link gives an operator on this machine the CPU after a STOP ([`hand_off`]).
    give_way: bool,
    /// The stop set the link owes, encoded; empty when it owes none.
    armed: Vec<AheadFrame>,
    /// The link task is writing: nothing may go between its bytes.
    link_writing: bool,
    /// Frames written here that the link task has not taken yet, in the order written.
    written: Vec<AheadFrame>,
    /// What the socket did not take of a write here: the link task writes it first.
    unwritten: Vec<u8>,
}

/// What the link task takes before it writes: frames written ahead, and bytes of theirs still
/// to write (before its own).
#[derive(Debug, Default)]
pub(super) struct Taken {
    pub(super) frames: Vec<AheadFrame>,
    pub(super) unwritten: Vec<u8>,
}

impl StopAhead {
    pub fn new() -> StopAhead {
        StopAhead::default()
    }

    /// Writes the armed stop set now, if it can be written between the link's writes; gives
    /// an operator on this machine the CPU after it, as the link task would.
    pub fn write_now(&self) -> AheadOutcome {
        let (outcome, give_way) = {
            let mut slot = self.lock();
            (slot.write_now(), slot.give_way)
        };
        if outcome == AheadOutcome::Written {
            self.written.notify_one();
            if give_way {
                hand_off::give_way();
            }
        }
        outcome
    }

    fn lock(&self) -> MutexGuard<'_, Slot> {
        // A panic while the lock was held left nothing half-done that matters more than a
        // stop: the slot is used as it is.
        self.slot
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
    }

    /// The link task's socket, until the returned guard is dropped (the link task ends).
    pub(super) fn attach(&self, socket: AheadSocket, give_way: bool) -> Attached {
        let mut slot = self.lock();
        let generation = slot.generation + 1;
        *slot = Slot {
            socket: Some(socket),
            generation,
            give_way,
            ..Slot::default()
        };
        Attached {
            ahead: self.clone(),
            generation,
        }
    }
}

impl Slot {
    fn write_now(&mut self) -> AheadOutcome {
        if self.link_writing || !self.unwritten.is_empty() {
            return AheadOutcome::LinkWriting;
        }
        let Some(socket) = self.socket.as_mut() else {
            return AheadOutcome::NoLink;
        };
        if self.armed.is_empty() {
            return AheadOutcome::NothingOwed;
        }
        let bytes: Vec<u8> = self.armed.iter().flat_map(|f| f.bytes.clone()).collect();
        let taken = loop {
            match socket.write(&bytes) {
                Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                Err(e) => return AheadOutcome::NotTaken(e.kind()),
                Ok(0) => return AheadOutcome::NotTaken(io::ErrorKind::WriteZero),
                Ok(taken) => break taken,
            }
        };
        self.unwritten = bytes[taken..].to_vec();
        self.written.append(&mut self.armed);
        AheadOutcome::Written
    }
}

/// The link task's hold on the slot: the socket is detached when it is dropped, so a link that
/// ended leaves no descriptor of its connection open and nothing armed.
pub(super) struct Attached {
    ahead: StopAhead,
    generation: u64,
}

impl Attached {
    /// Arms the stop set the link owes (empty: none).
    pub(super) fn arm(&self, frames: Vec<AheadFrame>) {
        self.ahead.lock().armed = frames;
    }

    /// Before the link task writes: nothing is written here until [`Self::end_write`]; what
    /// was written here is the link task's now.
    pub(super) fn begin_write(&self) -> Taken {
        let mut slot = self.ahead.lock();
        slot.link_writing = true;
        Taken {
            frames: std::mem::take(&mut slot.written),
            unwritten: std::mem::take(&mut slot.unwritten),
        }
    }

    pub(super) fn end_write(&self) {
        self.ahead.lock().link_writing = false;
    }

    /// The frames written here since the link task last took them.
    pub(super) fn take_written(&self) -> Vec<AheadFrame> {
        std::mem::take(&mut self.ahead.lock().written)
    }

    /// Whether bytes written here wait for the link task to finish them.
    pub(super) fn unfinished(&self) -> bool {
        !self.ahead.lock().unwritten.is_empty()
    }

    pub(super) fn written_signal(&self) -> Arc<Notify> {
        self.ahead.written.clone()
    }
}

impl Drop for Attached {
    fn drop(&mut self) {
        let mut slot = self.ahead.lock();
        if slot.generation == self.generation {
            *slot = Slot {
                generation: slot.generation,
                ..Slot::default()
            };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A socket that takes at most `room` bytes in all, and keeps them.
    #[derive(Clone)]
    struct Socket {
        got: Arc<Mutex<Vec<u8>>>,
        room: usize,
    }

    impl Write for Socket {
        fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
            let mut got = self.got.lock().expect("lock");
            let room = self.room.saturating_sub(got.len());
            if room == 0 {
                return Err(io::ErrorKind::WouldBlock.into());
            }
            let n = buf.len().min(room);
            got.extend_from_slice(&buf[..n]);
            Ok(n)
        }

        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    fn socket(room: usize) -> (Socket, Arc<Mutex<Vec<u8>>>) {
        let got = Arc::new(Mutex::new(Vec::new()));
        (
            Socket {
                got: got.clone(),
                room,
            },
            got,
        )
    }

    fn frame(id: u32, request: Request, bytes: &[u8]) -> AheadFrame {
        AheadFrame {
            id,
            request,
            bytes: bytes.to_vec(),
        }
    }

    fn written(got: &Arc<Mutex<Vec<u8>>>) -> Vec<u8> {
        got.lock().expect("lock").clone()
    }

    #[test]
    fn the_armed_set_is_written_once_whole_and_handed_to_the_link() {
        let ahead = StopAhead::new();
        assert_eq!(ahead.write_now(), AheadOutcome::NoLink);
        let (sock, got) = socket(1024);
        let attached = ahead.attach(Box::new(sock), false);
        assert_eq!(ahead.write_now(), AheadOutcome::NothingOwed);
        attached.arm(vec![
            frame(2, Request::CartesianMoveStop, b"cart"),
            frame(4, Request::PolarPanStop, b"polar"),
        ]);
        assert_eq!(ahead.write_now(), AheadOutcome::Written);
        assert_eq!(written(&got), b"cartpolar");
        assert_eq!(
            ahead.write_now(),
            AheadOutcome::NothingOwed,
            "written once, not twice"
        );
        let taken = attached.begin_write();
        assert_eq!(
            taken.frames.iter().map(|f| f.id).collect::<Vec<_>>(),
            [2, 4]
        );
        assert!(taken.unwritten.is_empty());
        attached.end_write();
        assert!(attached.take_written().is_empty(), "taken once");
    }

    #[test]
    fn nothing_is_written_inside_a_link_write() {
        let ahead = StopAhead::new();
        let (sock, got) = socket(1024);
        let attached = ahead.attach(Box::new(sock), false);
        attached.arm(vec![frame(2, Request::PolarPanStop, b"stop")]);
        let _ = attached.begin_write();
        assert_eq!(ahead.write_now(), AheadOutcome::LinkWriting);
        assert!(written(&got).is_empty());
        attached.end_write();
        assert_eq!(ahead.write_now(), AheadOutcome::Written);
        assert_eq!(written(&got), b"stop");
    }

    #[test]
    fn what_the_socket_did_not_take_goes_first_in_the_links_next_write() {
        let ahead = StopAhead::new();
        let (sock, got) = socket(3);
        let attached = ahead.attach(Box::new(sock), false);
        attached.arm(vec![frame(2, Request::PolarPanStop, b"stop")]);
        assert_eq!(ahead.write_now(), AheadOutcome::Written);
        assert_eq!(written(&got), b"sto");
        assert!(attached.unfinished());
        attached.arm(vec![frame(6, Request::PolarPanStop, b"again")]);
        assert_eq!(
            ahead.write_now(),
            AheadOutcome::LinkWriting,
            "a frame half written: nothing may follow it but its rest"
        );
        let taken = attached.begin_write();
        assert_eq!(taken.unwritten, b"p");
        assert_eq!(taken.frames.len(), 1);
    }

    #[test]
    fn a_full_socket_takes_nothing_and_the_set_stays_armed() {
        let ahead = StopAhead::new();
        let (sock, got) = socket(0);
        let attached = ahead.attach(Box::new(sock), false);
        attached.arm(vec![frame(2, Request::PolarPanStop, b"stop")]);
        assert_eq!(
            ahead.write_now(),
            AheadOutcome::NotTaken(io::ErrorKind::WouldBlock)
        );
        assert!(written(&got).is_empty());
        assert!(attached.take_written().is_empty());
        assert!(!attached.unfinished());
    }

    #[test]
    fn a_link_that_ended_leaves_nothing_armed_and_only_its_own_socket_goes() {
        let ahead = StopAhead::new();
        let (first, _) = socket(1024);
        let old = ahead.attach(Box::new(first), false);
        old.arm(vec![frame(2, Request::PolarPanStop, b"stop")]);
        let (second, got) = socket(1024);
        let new = ahead.attach(Box::new(second), false);
        assert_eq!(ahead.write_now(), AheadOutcome::NothingOwed, "new link");
        drop(old);
        new.arm(vec![frame(8, Request::PolarPanStop, b"new")]);
        assert_eq!(ahead.write_now(), AheadOutcome::Written);
        assert_eq!(written(&got), b"new");
        new.arm(vec![frame(10, Request::PolarPanStop, b"more")]);
        drop(new);
        assert_eq!(ahead.write_now(), AheadOutcome::NoLink);
    }
}
