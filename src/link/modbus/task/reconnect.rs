//! Reconnecting with backoff, refusing jobs meanwhile; an undeliverable owed stop on close ends it.

use super::{CLOSING_ATTEMPTS, Job, LinkTask, ModbusError, ModbusEvent, StopReason, wire};
use crate::kortex::{PollPlan, RegisterImage};
use crate::link::modbus::ModbusConfig;
use tokio_modbus::client::Context;

/// Opens a connection and checks that the arm answers: a frozen server's kernel still accepts
/// connections, so a TCP connect alone proves nothing.
async fn open_answering(
    connector: &wire::Connector,
    config: &ModbusConfig,
) -> Result<Context, ModbusError> {
    let mut ctx = connector().await?;
    let mut scratch = RegisterImage::default();
    if let Some(block) = PollPlan::IcdBlocks.blocks().first() {
        wire::read(&mut ctx, *block, &mut scratch, config.request_timeout).await?;
    }
    Ok(ctx)
}

impl LinkTask {
    /// Reconnects with backoff; false when the task should end.
    pub(super) async fn reconnect(&mut self) -> bool {
        let mut delay = self.config.reconnect_delay;
        let mut attempts = 0u32;
        loop {
            if self.closing {
                if !self.stop_owed {
                    self.answer_close(Ok(()));
                    return false;
                }
                if self.closing_attempts >= CLOSING_ATTEMPTS {
                    let e = ModbusError::Disconnected {
                        reason: format!(
                            "gave up writing the stop after {CLOSING_ATTEMPTS} reconnects: {}",
                            self.lost_reason
                        ),
                    };
                    self.stop_failed(StopReason::LinkClosed, &e);
                    self.answer_close(Err(e));
                    return false;
                }
                self.closing_attempts += 1;
            }
            attempts += 1;
            let (connector, config) = (self.connector.clone(), self.config.clone());
            let opened = self.refusing(open_answering(&connector, &config)).await;
            match opened {
                Ok(ctx) => {
                    self.ctx = Some(ctx);
                    self.slow_read_at = None;
                    tracing::info!("modbus link to {} reconnected", self.config.addr);
                    self.event(ModbusEvent::Reconnected { attempts });
                    return true;
                }
                Err(e) => {
                    tracing::debug!("reconnect attempt {attempts} failed: {e}");
                    self.lost_reason = e.to_string();
                }
            }
            self.refusing(tokio::time::sleep(delay)).await;
            delay = (delay * 2).min(self.config.reconnect_max_delay);
        }
    }

    /// Awaits `work`, refusing the jobs that come meanwhile.
    async fn refusing<T>(&mut self, work: impl Future<Output = T>) -> T {
        tokio::pin!(work);
        loop {
            tokio::select! {
                biased;
                job = self.jobs.recv(), if !self.jobs_closed => self.refuse(job),
                done = &mut work => return done,
            }
        }
    }

    /// Refuses a job while disconnected: a jog must not start when the connection returns.
    fn refuse(&mut self, job: Option<Job>) {
        let error = || self.not_connected();
        match job {
            None => {
                self.jobs_closed = true;
                self.closing = true;
            }
            Some(Job::Close(reply)) => {
                self.close_replies.push(reply);
                self.closing = true;
            }
            Some(Job::Read(reply)) => _ = reply.send(Err(error())),
            Some(
                Job::Twist { reply, .. }
                | Job::PolarPan { reply, .. }
                | Job::Stop(reply)
                | Job::Move { reply, .. }
                | Job::Plain { reply, .. },
            ) => _ = reply.send(Err(error())),
        }
    }
}
