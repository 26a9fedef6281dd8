//! The one simulated arm both servers drive: a task owning it and the operator, in real time.

use std::time::Duration;

use tokio::sync::{mpsc, oneshot};
use tokio::time::{Instant, MissedTickBehavior};

use super::arm_model::{Arm, ArmSnapshot, STEP};
use super::operator::Operator;

/// How often the task wakes to advance the arm when nobody asks anything.
const TICK: Duration = Duration::from_millis(10);
/// Longest stretch of simulated time caught up at once (after a suspended process, say).
const MAX_CATCH_UP_STEPS: u64 = 2_000;

/// The simulated robot: the arm, the operator's state, the Modbus command block.
#[derive(Debug, Clone, Default)]
pub struct World {
    pub arm: Arm,
    pub operator: Operator,
    /// Holding registers 200-219 as last written.
    pub command_block: [u16; 20],
}

type Job = Box<dyn FnOnce(&mut World) + Send>;

/// The simulated arm's task has ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("the simulated arm has stopped")]
pub struct SimGone;

/// A handle on the simulated arm. Cheap to clone; the task ends when every handle is dropped.
#[derive(Clone, Debug)]
pub struct SimArm {
    jobs: mpsc::Sender<Job>,
}

impl SimArm {
    pub fn spawn(arm: Arm, operator: Operator) -> SimArm {
        let (jobs, rx) = mpsc::channel::<Job>(256);
        let world = World {
            arm,
            operator,
            command_block: [0; 20],
        };
        tokio::spawn(run(world, rx));
        SimArm { jobs }
    }

    /// Runs `f` on the whole world, the arm brought up to the present first.
    pub async fn with_world<R, F>(&self, f: F) -> Result<R, SimGone>
    where
        R: Send + 'static,
        F: FnOnce(&mut World) -> R + Send + 'static,
    {
        let (tx, rx) = oneshot::channel();
        let job: Job = Box::new(move |world| {
            let _ = tx.send(f(world));
        });
        self.jobs.send(job).await.map_err(|_| SimGone)?;
        rx.await.map_err(|_| SimGone)
    }

    /// Runs `f` on the arm and the Talos operator state.
    pub async fn with<R, F>(&self, f: F) -> Result<R, SimGone>
    where
        R: Send + 'static,
        F: FnOnce(&mut Arm, &mut Operator) -> R + Send + 'static,
    {
        self.with_world(move |w| f(&mut w.arm, &mut w.operator))
            .await
    }

    pub async fn snapshot(&self) -> Result<ArmSnapshot, SimGone> {
        self.with(|arm, _| arm.snapshot()).await
    }
}

async fn run(mut world: World, mut jobs: mpsc::Receiver<Job>) {
    let mut clock = Instant::now();
    let mut tick = tokio::time::interval(TICK);
    tick.set_missed_tick_behavior(MissedTickBehavior::Delay);
    let step = Duration::from_secs_f64(STEP);
    let mut catch_up = |arm: &mut Arm| {
        let behind = Instant::now().saturating_duration_since(clock);
        let steps = u64::try_from(behind.as_nanos() / step.as_nanos()).unwrap_or(u64::MAX);
        for _ in 0..steps.min(MAX_CATCH_UP_STEPS) {
            arm.step();
        }
        // Time beyond the cap is dropped rather than simulated.
        clock += Duration::from_nanos(step.as_nanos() as u64 * steps.min(1 << 40));
    };
    loop {
        tokio::select! {
            job = jobs.recv() => match job {
                Some(job) => {
                    catch_up(&mut world.arm);
                    job(&mut world);
                }
                None => return,
            },
            _ = tick.tick() => catch_up(&mut world.arm),
        }
    }
}
