//! The ack dialect's side of the link task: frames on the wire waiting for their ACK, in the
//! order sent, the ACKs paired with them, and overdue frames given up on (an overdue STOP sent
//! again while it has tries left).

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use tokio::io::AsyncWrite;

use super::{LinkTask, Pending};
use crate::link::talos::{
    Answer, Exchange, STOP_ACK_INTERVAL, STOP_ACK_TRIES, TalosError, TalosEvent, ack_deadline,
};
use crate::talos::ack::ACK;
use crate::talos::{CommandValue, RequestClass};

/// Ack dialect: one frame on the wire waiting for its ACK.
pub(super) struct AckWait {
    pub(super) pending: Pending,
    /// When the frame is given up (and a STOP sent again).
    expires: tokio::time::Instant,
    /// Frames sent for this request so far.
    tries: u32,
    /// When the request's first frame went out, for the latency.
    first_sent: Instant,
}

/// Ack dialect: a frame whose ACK did not come in time and may still arrive.
pub(super) struct ExpiredAck {
    id: u32,
    command: CommandValue,
    /// After this an ACK is no longer taken for this frame's.
    forget_at: tokio::time::Instant,
}

impl LinkTask {
    pub(super) fn queue_ack_wait(&mut self, pending: Pending, tries: u32, first_sent: Instant) {
        let wait = if pending.request.class() == RequestClass::Stop {
            STOP_ACK_INTERVAL
        } else {
            self.request_timeout
        };
        self.ack_queue.push_back(AckWait {
            pending,
            expires: tokio::time::Instant::now() + wait,
            tries,
            first_sent,
        });
    }

    pub(super) fn next_ack_expiry(&self) -> Option<tokio::time::Instant> {
        self.ack_queue.iter().map(|w| w.expires).min()
    }

    /// Takes frames whose ACK is overdue out of the queue, so later ACKs pair with later
    /// frames; sends an overdue STOP again while it has tries left, and fails the rest.
    pub(super) async fn expire_acks<W: AsyncWrite + Unpin>(
        &mut self,
        writer: &mut W,
    ) -> Result<(), String> {
        let now = tokio::time::Instant::now();
        let (overdue, waiting): (VecDeque<AckWait>, VecDeque<AckWait>) =
            self.ack_queue.drain(..).partition(|w| w.expires <= now);
        self.ack_queue = waiting;
        let forget_after = self.request_timeout.max(Duration::from_secs(1));
        for wait in overdue {
            let AckWait {
                pending,
                tries,
                first_sent,
                ..
            } = wait;
            let command = pending.request.command();
            self.expired_acks.push_back(ExpiredAck {
                id: pending.id,
                command,
                forget_at: now + forget_after,
            });
            if pending.request.class() == RequestClass::Stop && tries < STOP_ACK_TRIES {
                let id = self.ids.next();
                tracing::warn!(
                    "{command} (id {}) not acknowledged within {STOP_ACK_INTERVAL:?}: sending it again as id {id}",
                    pending.id
                );
                self.event(TalosEvent::AckExpired {
                    id: pending.id,
                    command,
                    resent_as: Some(id),
                });
                let frame = match pending.request.to_frame(id) {
                    Ok(frame) => frame,
                    Err(source) => {
                        let _ = pending
                            .answer
                            .send(Err(TalosError::Encode { command, source }));
                        continue;
                    }
                };
                let request_bytes = self.encode(&frame);
                let resent = Pending {
                    id,
                    request_bytes: request_bytes.clone().unwrap_or_default(),
                    sent: Instant::now(),
                    ..pending
                };
                self.queue_ack_wait(resent, tries + 1, first_sent);
                self.write(writer, &request_bytes?).await?;
            } else {
                tracing::warn!("{command} (id {}) not acknowledged in time", pending.id);
                self.event(TalosEvent::AckExpired {
                    id: pending.id,
                    command,
                    resent_as: None,
                });
                let _ = pending.answer.send(Err(TalosError::Timeout {
                    command,
                    id: pending.id,
                    after: ack_deadline(&pending.request, self.request_timeout),
                }));
            }
        }
        Ok(())
    }

    /// Pairs an ACK with the oldest frame still waiting. With none waiting it belongs to a
    /// frame given up on (reported late), or to nothing (reported unexpected).
    pub(super) fn on_ack(&mut self) {
        let Some(wait) = self.ack_queue.pop_front() else {
            let now = tokio::time::Instant::now();
            while self
                .expired_acks
                .front()
                .is_some_and(|e| e.forget_at <= now)
            {
                self.expired_acks.pop_front();
            }
            match self.expired_acks.pop_front() {
                Some(late) => self.event(TalosEvent::LateReply {
                    id: late.id,
                    command: late.command,
                }),
                None => self.event(TalosEvent::UnexpectedAckBytes(ACK.len())),
            }
            return;
        };
        let pending = wait.pending;
        let id = pending.id;
        let exchange = Exchange {
            id,
            request: pending.request,
            answer: Answer::Ack,
            request_bytes: pending.request_bytes,
            reply_bytes: ACK.to_vec(),
            latency: wait.first_sent.elapsed(),
        };
        let command = exchange.request.command();
        if pending.answer.send(Ok(exchange)).is_err() {
            self.event(TalosEvent::LateReply { id, command });
        }
    }
}
