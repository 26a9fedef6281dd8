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
//! The same slot lets the link's handle write a motion (a jog's START or refresh, a home) in
//! its caller's turn, the driver's, rather than the link task's ([`Through`]): that turn cost a
//! press some 5 us on the way to the wire, and under load every us before the write costs the
//! press more than itself (`docs/development.md`). Only while the link task has nothing queued
//! or taken and not yet written (counted here, under the slot's lock), is not writing and has
//! nothing half written: the wire keeps the order requests were submitted in. Otherwise, and
//! for everything but a motion, the request is queued as before. The frame's answer goes to its
//! caller as any other's. Once the link task ends nothing is written through, and what was is
//! taken first, so the stop set it then owes counts it.
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

use super::AnswerTx;
use crate::key_stages::{self, Stage};
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
    written: Vec<WrittenAhead>,
    /// What the socket did not take of a write here: the link task writes it first.
    unwritten: Vec<u8>,
    /// Requests in the link task's queue, or taken from it and not yet written: a motion
    /// written through would overtake them.
    queued: usize,
    /// The link task is ending: no motion is written through any more.
    through_closed: bool,
}

/// A frame written here, and who waits for its answer: nobody for the stop set, the caller
/// for a motion written through ([`Through::write_through`]).
#[derive(Debug)]
pub(super) struct WrittenAhead {
    pub(super) frame: AheadFrame,
    pub(super) answer: Option<AnswerTx>,
}

/// What the link task takes before it writes: frames written ahead, and bytes of theirs still
/// to write (before its own).
#[derive(Debug, Default)]
pub(super) struct Taken {
    pub(super) frames: Vec<WrittenAhead>,
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
        let armed = self.armed.drain(..);
        self.written.extend(armed.map(|frame| WrittenAhead {
            frame,
            answer: None,
        }));
        AheadOutcome::Written
    }

    /// Writes `frame` if the link task has nothing queued, nothing of its own being written and
    /// nothing left half written; gives it back otherwise, or when the socket took none of it.
    fn write_through(
        &mut self,
        frame: AheadFrame,
        answer: AnswerTx,
    ) -> Result<(), (AheadFrame, AnswerTx)> {
        if self.through_closed || self.link_writing || !self.unwritten.is_empty() || self.queued > 0
        {
            return Err((frame, answer));
        }
        let Some(socket) = self.socket.as_mut() else {
            return Err((frame, answer));
        };
        key_stages::mark(Stage::Encoded);
        let taken = loop {
            match socket.write(&frame.bytes) {
                Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                Err(_) | Ok(0) => return Err((frame, answer)),
                Ok(taken) => break taken,
            }
        };
        key_stages::mark(Stage::Written);
        self.unwritten = frame.bytes[taken..].to_vec();
        let answer = Some(answer);
        self.written.push(WrittenAhead { frame, answer });
        Ok(())
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

    /// `n` requests taken from the queue were written (or failed): no longer queued.
    pub(super) fn written_out(&self, n: usize) {
        let mut slot = self.ahead.lock();
        if slot.generation == self.generation {
            slot.queued = slot.queued.saturating_sub(n);
        }
    }

    /// The frames written here since the link task last took them.
    pub(super) fn take_written(&self) -> Vec<WrittenAhead> {
        std::mem::take(&mut self.ahead.lock().written)
    }

    /// Whether bytes written here wait for the link task to finish them.
    pub(super) fn unfinished(&self) -> bool {
        !self.ahead.lock().unwritten.is_empty()
    }

    /// The link task is ending (its callers gone, or the link lost): nothing more is written
    /// through; what was is taken after this, so its stop is owed.
    pub(super) fn close_through(&self) {
        self.ahead.lock().through_closed = true;
    }

    /// The way in for the link's handles (see [`Through`]).
    pub(super) fn through(&self) -> Through {
        Through {
            ahead: self.ahead.clone(),
            generation: self.generation,
        }
    }

    pub(super) fn written_signal(&self) -> Arc<Notify> {
        self.ahead.written.clone()
    }
}

/// A link handle's way into the slot, for motions written through: only while its own link
/// is the one attached (a handle of a link that ended writes nothing there and counts nothing).
#[derive(Debug, Clone)]
pub(super) struct Through {
    ahead: StopAhead,
    generation: u64,
}

impl Through {
    /// Writes a motion request's frame at once, in the caller's own turn, when the link task
    /// has nothing queued ([`Self::queue_one`]) and is not writing; the frame is the link
    /// task's then, its answer `answer`'s. Gives the frame back, for the link's queue, when it
    /// cannot be written so. Gives an operator on this machine the CPU after it.
    pub(super) fn write_through(
        &self,
        frame: AheadFrame,
        answer: AnswerTx,
    ) -> Result<(), (AheadFrame, AnswerTx)> {
        let give_way = {
            let mut slot = self.ahead.lock();
            if slot.generation != self.generation {
                return Err((frame, answer));
            }
            slot.write_through(frame, answer)?;
            slot.give_way
        };
        self.ahead.written.notify_one();
        if give_way {
            hand_off::give_way();
        }
        Ok(())
    }

    /// A request is going into the link task's queue: nothing is written through until the
    /// link task has written it ([`Attached::written_out`]). Called before it is queued.
    pub(super) fn queue_one(&self) {
        let mut slot = self.ahead.lock();
        if slot.generation == self.generation {
            slot.queued += 1;
        }
    }

    /// A request counted by [`Self::queue_one`] never reached the queue.
    pub(super) fn unqueue_one(&self) {
        let mut slot = self.ahead.lock();
        if slot.generation == self.generation {
            slot.queued = slot.queued.saturating_sub(1);
        }
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
            taken.frames.iter().map(|f| f.frame.id).collect::<Vec<_>>(),
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

    fn start(id: u32) -> AheadFrame {
        let request = Request::PolarPanStart {
            moving_azimuth: 1,
            moving_altitude: 0,
        };
        frame(id, request, b"start")
    }

    fn answer() -> AnswerTx {
        tokio::sync::oneshot::channel().0
    }

    #[test]
    fn a_motion_is_written_through_only_while_the_link_has_nothing_queued_or_in_a_write() {
        let ahead = StopAhead::new();
        let (sock, got) = socket(1024);
        let attached = ahead.attach(Box::new(sock), false);
        let through = attached.through();

        through.queue_one();
        assert!(through.write_through(start(2), answer()).is_err(), "queued");
        attached.written_out(1);
        let _ = attached.begin_write();
        assert!(
            through.write_through(start(4), answer()).is_err(),
            "writing"
        );
        attached.end_write();
        through.queue_one();
        through.unqueue_one();
        assert!(written(&got).is_empty(), "nothing written through");

        assert!(through.write_through(start(6), answer()).is_ok());
        assert_eq!(written(&got), b"start");
        let taken = attached.take_written();
        assert_eq!(taken.len(), 1);
        assert_eq!(taken[0].frame.id, 6);
        assert!(taken[0].answer.is_some(), "its caller waits for its answer");
    }

    #[test]
    fn a_motion_written_through_and_then_the_stop_set_are_the_links_in_wire_order() {
        let ahead = StopAhead::new();
        let (sock, got) = socket(1024);
        let attached = ahead.attach(Box::new(sock), false);
        attached.arm(vec![frame(2, Request::PolarPanStop, b"stop")]);
        assert!(attached.through().write_through(start(4), answer()).is_ok());
        assert_eq!(ahead.write_now(), AheadOutcome::Written);
        assert_eq!(written(&got), b"startstop");
        let taken = attached.begin_write().frames;
        let order: Vec<(u32, bool)> = taken
            .iter()
            .map(|w| (w.frame.id, w.answer.is_some()))
            .collect();
        assert_eq!(order, [(4, true), (2, false)]);
    }

    #[test]
    fn a_motion_half_written_leaves_its_rest_first_and_nothing_follows_it_through() {
        let ahead = StopAhead::new();
        let (sock, got) = socket(2);
        let attached = ahead.attach(Box::new(sock), false);
        let through = attached.through();
        assert!(through.write_through(start(2), answer()).is_ok());
        assert_eq!(written(&got), b"st");
        assert!(attached.unfinished());
        assert!(through.write_through(start(4), answer()).is_err());
        assert_eq!(attached.begin_write().unwritten, b"art");
    }

    #[test]
    fn a_socket_that_takes_nothing_gives_the_motion_back_for_the_queue() {
        let ahead = StopAhead::new();
        let (sock, _) = socket(0);
        let attached = ahead.attach(Box::new(sock), false);
        let (frame, _) = attached
            .through()
            .write_through(start(2), answer())
            .expect_err("not taken");
        assert_eq!(frame.id, 2);
        assert!(attached.take_written().is_empty());
    }

    #[test]
    fn the_handle_of_a_link_that_ended_writes_nothing_through_and_counts_nothing() {
        let ahead = StopAhead::new();
        let (first, first_got) = socket(1024);
        let old = ahead.attach(Box::new(first), false);
        let old_through = old.through();
        let (second, got) = socket(1024);
        let new = ahead.attach(Box::new(second), false);
        drop(old);
        assert!(old_through.write_through(start(2), answer()).is_err());
        old_through.queue_one();
        assert!(
            new.through().write_through(start(4), answer()).is_ok(),
            "the old link's queue is not the new one's"
        );
        assert!(written(&first_got).is_empty());
        assert_eq!(written(&got), b"start");
        drop(new);
        assert!(old_through.write_through(start(6), answer()).is_err());
    }
}
