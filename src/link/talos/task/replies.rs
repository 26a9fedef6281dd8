//! Replies read by the link task: paired with their pending requests, rejections reported, and
//! requests whose callers gave up forgotten.

use std::time::Duration;

use super::LinkTask;
use crate::link::talos::{Answer, Exchange, TalosError, TalosEvent};
use crate::talos::Reply;
use crate::talos::frame::{Rejection, TalosFrame};

impl LinkTask {
    pub(super) fn on_frame(&mut self, frame: TalosFrame) {
        let Some(pending) = self
            .pending
            .remove(&(frame.id & !1))
            .filter(|_| frame.id & 1 == 1)
        else {
            self.event(TalosEvent::UnpairedReply {
                id: frame.id,
                command: frame.command,
            });
            return;
        };
        let id = frame.id & !1;
        let command = pending.request.command();
        let reply_bytes = frame.to_bytes(self.checksum).unwrap_or_default();
        let result = match Reply::from_frame(&frame) {
            Ok(reply) if reply.command() == command => Ok(Exchange {
                id,
                request: pending.request,
                answer: Answer::Reply(reply),
                request_bytes: pending.request_bytes,
                reply_bytes,
                latency: pending.sent.elapsed(),
            }),
            Ok(reply) => Err(TalosError::WrongReply {
                command,
                id,
                answered: reply.command(),
            }),
            Err(source) => Err(TalosError::MalformedReply {
                command,
                id,
                source,
            }),
        };
        if pending.answer.send(result).is_err() {
            self.event(TalosEvent::LateReply { id, command });
        }
    }

    pub(super) fn on_rejection(&mut self, rejection: Rejection) {
        // A corrupt reply whose header names a pending request fails that request now.
        let owner = rejection
            .header
            .filter(|h| h.id & 1 == 1)
            .and_then(|h| self.pending.remove(&(h.id & !1)));
        match owner {
            Some(pending) => {
                let command = pending.request.command();
                let id = rejection.header.map_or(0, |h| h.id & !1);
                let failed = pending.answer.send(Err(TalosError::Checksum {
                    command,
                    id,
                    rejection,
                }));
                // Its caller gave up (timed out) before the reply was given up on: the rejection
                // still tells what the operator speaks.
                if failed.is_err() {
                    self.event(TalosEvent::Rejected(rejection));
                }
            }
            None => self.event(TalosEvent::Rejected(rejection)),
        }
    }

    /// Forgets requests whose callers gave up, so the map stays bounded. A reply that still
    /// comes for one is reported as unpaired.
    pub(super) fn sweep(&mut self) {
        let stale =
            |p: &super::Pending| p.answer.is_closed() && p.sent.elapsed() > Duration::from_secs(5);
        self.pending.retain(|_, p| !stale(p));
    }
}
