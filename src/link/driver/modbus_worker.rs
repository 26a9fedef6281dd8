//! The driver's Modbus half: in order; a STOP drops the refreshes queued before it.

use std::time::Duration;

use tokio::sync::mpsc;
use tokio::task::JoinHandle;

use super::JointPositions;
use super::speed::SpeedInForce;
use crate::kortex::{
    ControlCoil, PolarPanSettings, Pose, ReferenceFrame, SpeedLimits, Stored, Twist,
};
use crate::link::interface::{
    ArmCommand, ArmError, ArmEvent, CommandClass, JogMotion, LogEntry, Traffic,
};
use crate::link::modbus::{ModbusError, ModbusLink, Snapshot, WriteReport};
use crate::link::speed::{SpeedCap, fraction, is_settable};

pub struct ModbusWorker {
    commands: mpsc::UnboundedSender<ArmCommand>,
    task: JoinHandle<()>,
    link: ModbusLink,
}

struct State {
    link: ModbusLink,
    events: mpsc::UnboundedSender<ArmEvent>,
    cap: SpeedCap,
    /// The driver's speed in force: twists and capped moves scale with it.
    speed: SpeedInForce,
    /// The jog frame: the driver's one copy (`SetFrame` comes only here; Talos has none).
    frame: ReferenceFrame,
}

impl ModbusWorker {
    pub fn start(
        link: ModbusLink,
        cap: SpeedCap,
        events: mpsc::UnboundedSender<ArmEvent>,
        joints: JointPositions,
        speed: SpeedInForce,
    ) -> ModbusWorker {
        forward_telemetry(&link, events.clone(), joints);
        let (commands, rx) = mpsc::unbounded_channel();
        let state = State {
            link: link.clone(),
            events,
            cap,
            speed,
            frame: ReferenceFrame::Base,
        };
        let task = tokio::spawn(run(state, rx));
        ModbusWorker {
            commands,
            task,
            link,
        }
    }

    pub fn send(&self, command: ArmCommand) {
        let _ = self.commands.send(command);
    }

    /// Runs what is queued (a STOP last), then closes the link, which stops any twist.
    pub async fn close(self) {
        drop(self.commands);
        let _ = tokio::time::timeout(Duration::from_secs(1), self.task).await;
        let _ = tokio::time::timeout(Duration::from_secs(1), self.link.close()).await;
    }
}

fn forward_telemetry(
    link: &ModbusLink,
    events: mpsc::UnboundedSender<ArmEvent>,
    joints: JointPositions,
) {
    let mut snapshots = link.subscribe();
    tokio::spawn(async move {
        while snapshots.changed().await.is_ok() {
            let Some(s) = snapshots.borrow_and_update().clone() else {
                continue;
            };
            joints.send_replace(Some(s.telemetry.joints.map(|j| j.position)));
            let entry = LogEntry {
                ok: true,
                latency: Some(s.poll_time),
                poll: true,
                ..LogEntry::new("modbus poll", "OK".into())
            };
            let telemetry = ArmEvent::Telemetry(Box::new(s.telemetry));
            let sent = [
                ArmEvent::Log(entry),
                telemetry,
                ArmEvent::Latency(s.poll_time),
            ];
            if sent.into_iter().any(|event| events.send(event).is_err()) {
                break;
            }
        }
    });
}

async fn run(mut state: State, mut rx: mpsc::UnboundedReceiver<ArmCommand>) {
    while let Some(first) = rx.recv().await {
        let mut batch = vec![first];
        while let Ok(more) = rx.try_recv() {
            batch.push(more);
        }
        for command in without_stale_jogs(batch) {
            state.execute(command).await;
        }
    }
}

/// Drops jog commands queued before the last STOP: they were overtaken by it.
fn without_stale_jogs(batch: Vec<ArmCommand>) -> Vec<ArmCommand> {
    let Some(last_stop) = batch.iter().rposition(ArmCommand::is_stop) else {
        return batch;
    };
    batch
        .into_iter()
        .enumerate()
        .filter(|(i, c)| *i >= last_stop || !matches!(c, ArmCommand::Jog(_)))
        .map(|(_, c)| c)
        .collect()
}

impl State {
    fn latest<T>(&self, read: impl FnOnce(&Snapshot) -> T) -> Option<T> {
        self.link.subscribe().borrow().as_ref().map(read)
    }

    /// A stored run (home among them) with the limits lowered to the move cap.
    async fn start_stored(&self, stored: Stored) -> Result<Option<WriteReport>, ArmError> {
        wrap(self.link.start_stored(stored, Some(self.move_cap())).await)
    }

    /// A base-frame move to `pose` with the limits lowered to the move cap.
    async fn go_to(&self, pose: Pose) -> Result<Option<WriteReport>, ArmError> {
        let cap = Some(self.move_cap());
        wrap(self.link.go_to_pose(ReferenceFrame::Base, pose, cap).await)
    }

    /// A planned move's limits at the speed in force ([`SpeedCap::move_cap`]).
    fn move_cap(&self) -> SpeedLimits {
        self.cap.move_cap(self.speed.percent())
    }

    /// An orientation jog's rate, deg/s, never above the arm's own usable angular limit.
    fn angular_speed(&self) -> f32 {
        let wanted = self.cap.turn_rate(self.speed.percent()) * self.speed.fence_share();
        let arm_limit = self
            .latest(|s| s.telemetry.speed_limits.angular)
            .filter(|limit| limit.is_finite() && *limit > 0.0);
        arm_limit.map_or(wanted, |limit| wanted.min(limit))
    }

    /// A polar pan at the speed in force: rotation scaled, the tool point at most the tool speed.
    fn polar_settings(&self) -> PolarPanSettings {
        let configured = self.link.config().polar;
        let percent = self.speed.percent();
        let share = self.speed.fence_share();
        PolarPanSettings {
            angular_speed: configured.angular_speed * fraction(percent) as f32 * share,
            max_linear_speed: self
                .cap
                .polar_linear_bound(configured.max_linear_speed, percent)
                * share,
        }
    }

    async fn execute(&mut self, command: ArmCommand) {
        let result: Result<Option<WriteReport>, ArmError> = match &command {
            ArmCommand::Jog(JogMotion::Cartesian { x, y, z }) => {
                // The tool speed at the speed in force, less the fence's share: the one cap every
                // motion keeps.
                let speed = self.cap.twist_speed(self.speed.percent()) * self.speed.fence_share();
                let [x, y, z] = along([*x, *y, *z], speed);
                let twist = Twist {
                    x,
                    y,
                    z,
                    ..Twist::ZERO
                };
                wrap(self.link.jog_twist(self.frame, twist).await)
            }
            ArmCommand::Jog(JogMotion::Orientation { rx, ry, rz }) => {
                let twist = turn_twist([*rx, *ry, *rz], self.angular_speed());
                wrap(self.link.jog_twist(self.frame, twist).await)
            }
            ArmCommand::Jog(JogMotion::Polar { azimuth, altitude }) => wrap(
                self.link
                    .polar_pan_with(
                        f32::from(*azimuth),
                        f32::from(*altitude),
                        self.polar_settings(),
                    )
                    .await,
            ),
            ArmCommand::Jog(JogMotion::Joint { .. }) => Err(ArmError::Unsupported(
                "single-joint jog needs a Talos operator: Modbus cannot command joints",
            )),
            ArmCommand::Stop => wrap(self.link.stop().await),
            ArmCommand::QuickStop => wrap(self.link.pulse(ControlCoil::QuickStop).await),
            ArmCommand::FaultReset => wrap(self.link.pulse(ControlCoil::FaultReset).await),
            // Moves keep the arm's own planning, under lowered limits (`move_cap`).
            ArmCommand::Home => self.start_stored(self.link.config().home_action()).await,
            ArmCommand::StartStored(stored) => self.start_stored(*stored).await,
            ArmCommand::MoveToPose(pose) => self.go_to(*pose).await,
            ArmCommand::Step(step) => match self.latest(|s| s.telemetry.tcp.pose) {
                Some(pose) => self.go_to(step.target(pose)).await,
                None => Err(ArmError::NoPose),
            },
            // Never written to the arm's limits (216-219): those are the integrator's.
            ArmCommand::SetSpeed(speed) if is_settable(*speed) => {
                self.speed.set(*speed);
                let _ = self.events.send(ArmEvent::Speed(*speed));
                Ok(None)
            }
            ArmCommand::SetSpeed(speed) => Err(ArmError::SpeedOutOfRange {
                requested: *speed,
                in_force: self.speed.percent(),
            }),
            ArmCommand::SetFrame(frame) => {
                self.frame = *frame;
                Ok(None)
            }
            // Put in force by the driver before it got here: the next jog carries it.
            ArmCommand::FenceSpeed(_) => Ok(None),
            _ => Err(ArmError::Unsupported(
                "named positions over Modbus are kept by the console",
            )),
        };
        self.report(command, result);
    }

    fn report(&self, command: ArmCommand, result: Result<Option<WriteReport>, ArmError>) {
        let label = command.kind().label();
        match result {
            Ok(report) => {
                // A jog refresh that wrote nothing is not worth a log line.
                if let Some(report) = report.filter(|r| !r.writes.is_empty()) {
                    // An action's writes only start it: how it ends shows in the telemetry.
                    let starts =
                        matches!(command.class(), CommandClass::Motion { runs_to_end: true });
                    let _ = self.events.send(ArmEvent::Log(LogEntry {
                        count: 1,
                        name: label.to_string(),
                        outcome: format!(
                            "{} ({} writes)",
                            if starts { "started" } else { "OK" },
                            report.writes.len()
                        ),
                        ok: true,
                        latency: Some(report.elapsed),
                        traffic: Traffic::Modbus(report.writes),
                        ..LogEntry::default()
                    }));
                }
                let _ = self.events.send(ArmEvent::Done { command });
            }
            Err(error) => {
                let entry = LogEntry::new(label, error.to_string());
                let _ = self.events.send(ArmEvent::Log(entry));
                let _ = self.events.send(ArmEvent::failed(&command, error));
            }
        }
    }
}

/// A turn about the tool point at `rate` deg/s along the held directions (diagonals normalised).
fn turn_twist(directions: [i8; 3], rate: f32) -> Twist {
    let [theta_x, theta_y, theta_z] = along(directions, rate);
    Twist {
        theta_x,
        theta_y,
        theta_z,
        ..Twist::ZERO
    }
}

/// `total` along the held directions: a diagonal is normalised, never faster than `total`.
fn along(directions: [i8; 3], total: f32) -> [f32; 3] {
    let d = directions.map(f64::from);
    let each = f64::from(total) / d.iter().map(|v| v * v).sum::<f64>().sqrt().max(1.0);
    d.map(|v| (v * each) as f32)
}

fn wrap(result: Result<WriteReport, ModbusError>) -> Result<Option<WriteReport>, ArmError> {
    result.map(Some).map_err(|e| ArmError::Modbus(e.into()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::link::interface::StepMove;

    #[test]
    fn a_stop_drops_the_jogs_queued_before_it_but_keeps_other_commands() {
        let jog = ArmCommand::Jog(JogMotion::Polar {
            azimuth: 1,
            altitude: 0,
        });
        let batch = vec![
            jog.clone(),
            ArmCommand::SetSpeed(20),
            jog.clone(),
            ArmCommand::Stop,
        ];
        assert_eq!(
            without_stale_jogs(batch),
            [ArmCommand::SetSpeed(20), ArmCommand::Stop]
        );
        let after = vec![ArmCommand::Stop, jog.clone()];
        assert_eq!(without_stale_jogs(after.clone()), after);
    }

    #[test]
    fn a_turn_has_no_linear_part_and_its_diagonals_keep_the_rate() {
        let t = turn_twist([0, 0, -1], 15.0);
        assert_eq!(t.linear_speed(), 0.0);
        assert_eq!((t.theta_x, t.theta_y, t.theta_z), (0.0, 0.0, -15.0));
        let d = turn_twist([1, 1, 0], 15.0);
        assert!((d.angular_speed() - 15.0).abs() < 1e-4);
        assert!(d.theta_x > 0.0 && (d.theta_x - d.theta_y).abs() < 1e-6);
    }

    #[test]
    fn polar_steps_keep_the_distance() {
        let pose = Pose {
            x: 0.4,
            y: 0.0,
            z: 0.3,
            theta_x: 90.0,
            theta_y: 0.0,
            theta_z: 90.0,
        };
        let t = StepMove::Polar {
            azimuth: 90,
            altitude: 0,
        }
        .target(pose);
        assert!(t.x.abs() < 1e-6 && (t.y - 0.4).abs() < 1e-6 && (t.z - 0.3).abs() < 1e-6);
        assert!((t.theta_z - 180.0).abs() < 1e-6);
        let up = StepMove::Polar {
            azimuth: 0,
            altitude: 10,
        }
        .target(pose);
        let d = |p: Pose| (p.x * p.x + p.y * p.y + p.z * p.z).sqrt();
        assert!((d(up) - d(pose)).abs() < 1e-5 && up.z > pose.z);
        let c = StepMove::Cartesian {
            dx: 100,
            dy: -50,
            dz: 0,
        }
        .target(pose);
        assert!((c.x - 0.41).abs() < 1e-6 && (c.y + 0.005).abs() < 1e-6);
    }
}
