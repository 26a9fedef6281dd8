//! The link task's side of frames written ahead of it through the console's slot
//! ([`crate::link::talos::ahead`]): taken as its own, in wire order, and the stop set armed for
//! the next writer.

use std::time::Instant;

use tokio::io::AsyncWrite;

use super::{LinkTask, Pending};
use crate::link::talos::ahead::{AheadFrame, Attached, WrittenAhead};

impl LinkTask {
    /// Makes frames written ahead ([`super::ahead`]) this task's, in the order written: noted
    /// (as stops, or as the motion written through), and pending (replies paired, an
    /// ack-dialect STOP without its ACK sent again); nobody waits for the stop set's answers,
    /// a motion's caller for its own.
    pub(super) fn own_ahead(&mut self, frames: Vec<WrittenAhead>) {
        let stops: Vec<u32> = frames
            .iter()
            .filter(|written| written.answer.is_none())
            .map(|written| written.frame.id)
            .collect();
        if !stops.is_empty() {
            tracing::info!("stop set written ahead at a jog key's release (ids {stops:?})");
            // Written: armed no more.
            self.ahead_owed.clear();
        }
        let sent = Instant::now();
        for WrittenAhead { frame, answer } in frames {
            self.motion.note(&frame.request);
            let (answer, ahead) = match answer {
                Some(answer) => (answer, false),
                // The receiver is dropped: the answer is only logged.
                None => (tokio::sync::oneshot::channel().0, true),
            };
            let pending = Pending {
                id: frame.id,
                request: frame.request,
                request_bytes: frame.bytes,
                sent,
                answer,
                ahead,
            };
            self.insert_pending(pending, sent);
        }
    }

    /// Nothing more is written through ([`super::ahead::Through`]), and what was is this task's:
    /// noted as moving the arm before the stop set owed is worked out.
    pub(super) fn close_through(&mut self) {
        if let Some(ahead) = &self.ahead {
            ahead.close_through();
        }
        self.take_ahead();
    }

    /// Takes what was written ahead since the last write or reply, and arms what is owed now.
    pub(super) fn take_ahead(&mut self) {
        let frames = match &self.ahead {
            Some(ahead) => ahead.take_written(),
            None => return,
        };
        self.own_ahead(frames);
        self.arm_ahead();
    }

    /// The terminal reader wrote the stop set: it is this task's now, and bytes of it the socket
    /// did not take are written at once.
    pub(super) async fn on_written_ahead<W: AsyncWrite + Unpin>(
        &mut self,
        writer: &mut W,
    ) -> Result<(), String> {
        self.take_ahead();
        if self.ahead.as_ref().is_some_and(Attached::unfinished) {
            self.write(writer, &[]).await?;
        }
        Ok(())
    }

    /// Arms the stop set the link owes now for the terminal reader, its ids taken; disarms it
    /// when none is owed. Unchanged while the set owed is.
    pub(super) fn arm_ahead(&mut self) {
        let Some(ahead) = &self.ahead else {
            return;
        };
        let owed = self.motion.owed();
        if owed == self.ahead_owed.as_slice() {
            return;
        }
        let owed = owed.to_vec();
        let mut frames = Vec::with_capacity(owed.len());
        for request in &owed {
            let id = self.ids.next();
            let bytes = match request.to_frame(id) {
                Ok(frame) => self.encode(&frame),
                Err(e) => Err(e.to_string()),
            };
            match bytes {
                Ok(bytes) => frames.push(AheadFrame {
                    id,
                    request: request.clone(),
                    bytes,
                }),
                // The stop set encodes by construction; nothing is armed if that ever changes.
                Err(e) => {
                    tracing::error!("cannot arm {} ahead: {e}", request.command());
                    frames.clear();
                    break;
                }
            }
        }
        ahead.arm(frames);
        self.ahead_owed = owed;
    }
}
