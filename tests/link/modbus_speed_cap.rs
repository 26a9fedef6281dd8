//! One speed cap for every motion over Modbus, measured on the simulated arm through the arm
//! driver: jogs (cartesian, polar) are twists the console bounds itself; moves (go to, step,
//! home, a stored action or sequence by id) run at the arm's limit, which the link lowers for the
//! move and puts back afterwards.
//!
//! Speeds are the simulator's own tool velocity (Jacobian times joint velocities), sampled
//! while the motion runs, so a loaded machine changes how many samples there are, not their
//! values.

use std::time::Duration;

use tokio::sync::mpsc::UnboundedReceiver;

use armjog::console::jog::JogMotion;
use armjog::kortex::Pose;
use armjog::link::ModbusConfig;
use armjog::link::driver::{Driver, DriverConfig};
use armjog::link::interface::{ArmCommand, ArmEvent, LinkStatus, StepMove};
use armjog::sim::arm_model::{ActionStatus, Arm};
use armjog::sim::kinematics;
use armjog::sim::{SimConfig, Simulator};

/// The cap of these tests, m/s.
const CAP: f64 = 0.05;
/// Slack over the cap for the simulator's damped tracking.
const TOLERANCE: f64 = 1.03;
/// The arm's own limits, as a technician configured them.
const ARM_LIMITS: (f32, f32) = (0.3, 80.0);

struct Rig {
    sim: Simulator,
    driver: Driver,
    events: UnboundedReceiver<ArmEvent>,
}

async fn rig(arm: Arm) -> Rig {
    let sim = Simulator::start(SimConfig {
        arm,
        ..SimConfig::ephemeral()
    })
    .await
    .expect("simulator");
    sim.arm
        .with(|arm, _| arm.set_speed_limits(ARM_LIMITS.0.into(), ARM_LIMITS.1.into()))
        .await
        .expect("sim alive")
        .expect("limits accepted");
    let modbus = ModbusConfig::new(sim.modbus_addr.expect("modbus").to_string());
    let mut config = DriverConfig::new(None, Some(modbus));
    config.max_jog_speed = CAP;
    let (driver, mut events) = Driver::spawn(config);
    let up = async {
        while let Some(e) = events.recv().await {
            if matches!(e, ArmEvent::Status(LinkStatus::Up { .. })) {
                return;
            }
        }
    };
    tokio::time::timeout(Duration::from_secs(10), up)
        .await
        .expect("link up within 10 s");
    let mut rig = Rig {
        sim,
        driver,
        events,
    };
    rig.command(ArmCommand::SetSpeed(100)).await;
    // Telemetry first: steps need the pose.
    rig.wait_event(|e| matches!(e, ArmEvent::Telemetry(_)))
        .await;
    rig
}

fn tool_speed(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

impl Rig {
    async fn wait_event(&mut self, wanted: impl Fn(&ArmEvent) -> bool) -> ArmEvent {
        let wait = async {
            while let Some(e) = self.events.recv().await {
                if let ArmEvent::Failed { command, error } = &e {
                    panic!("{command} failed: {error}");
                }
                if wanted(&e) {
                    return e;
                }
            }
            panic!("driver ended");
        };
        tokio::time::timeout(Duration::from_secs(10), wait)
            .await
            .expect("event within 10 s")
    }

    /// Sends a command and waits until it is done.
    async fn command(&mut self, command: ArmCommand) {
        assert!(self.driver.send(command.clone()));
        self.wait_event(|e| matches!(e, ArmEvent::Done { command: c } if *c == command))
            .await;
    }

    /// The limits in force, as the registers carry them (f32).
    async fn limits(&self) -> (f32, f32) {
        let (linear, angular) = self
            .sim
            .arm
            .with(|arm, _| arm.speed_limits())
            .await
            .expect("sim alive");
        (linear as f32, angular as f32)
    }

    /// Holds a jog for `seconds` (re-sent every 100 ms, as a held key is) and returns the top
    /// tool speed seen.
    async fn hold_jog(&mut self, motion: JogMotion, seconds: f64) -> f64 {
        let mut top = 0.0f64;
        let until = tokio::time::Instant::now() + Duration::from_secs_f64(seconds);
        let mut resend = tokio::time::Instant::now();
        while tokio::time::Instant::now() < until {
            if tokio::time::Instant::now() >= resend {
                assert!(self.driver.send(ArmCommand::Jog(motion)));
                resend += Duration::from_millis(100);
            }
            let s = self.sim.arm.snapshot().await.expect("sim alive");
            top = top.max(tool_speed(s.tcp_linear_velocity));
            tokio::time::sleep(Duration::from_millis(5)).await;
        }
        self.command(ArmCommand::Stop).await;
        top
    }

    /// Samples the tool speed until the sim's action is over (at most 30 s); returns the top
    /// speed and the lowest linear limit seen in force meanwhile.
    async fn follow_move(&mut self) -> (f64, f64) {
        let mut top = 0.0f64;
        let mut lowest_limit = f64::MAX;
        let follow = async {
            loop {
                let s = self.sim.arm.snapshot().await.expect("sim alive");
                top = top.max(tool_speed(s.tcp_linear_velocity));
                lowest_limit = lowest_limit.min(s.speed_limit_linear);
                if s.action_status != ActionStatus::Started {
                    return s.action_status;
                }
                tokio::time::sleep(Duration::from_millis(5)).await;
            }
        };
        let status = tokio::time::timeout(Duration::from_secs(30), follow)
            .await
            .expect("the move ended within 30 s");
        assert_eq!(status, ActionStatus::Completed);
        (top, lowest_limit)
    }

    /// Waits (up to 10 s) until the arm's limits are back to what the technician set.
    async fn limits_restored(&self) {
        let wait = async {
            while self.limits().await != ARM_LIMITS {
                tokio::time::sleep(Duration::from_millis(10)).await;
            }
        };
        if tokio::time::timeout(Duration::from_secs(10), wait)
            .await
            .is_err()
        {
            panic!("limits not restored: {:?}", self.limits().await);
        }
    }
}

fn assert_capped(what: &str, top: f64, cap: f64) {
    assert!(
        top <= cap * TOLERANCE,
        "{what}: {:.1} mm/s over the {:.1} mm/s cap",
        top * 1000.0,
        cap * 1000.0
    );
    assert!(top > 0.5 * cap, "{what}: hardly moved ({top} m/s)");
}

#[tokio::test]
async fn jogs_stay_under_the_cap_and_leave_the_arms_limits_alone() {
    let mut rig = rig(Arm::default()).await;
    for (what, motion) in [
        ("cartesian", JogMotion::Cartesian { x: 1, y: -1, z: 1 }),
        (
            "polar azimuth",
            JogMotion::Polar {
                azimuth: 1,
                altitude: 0,
            },
        ),
        (
            "polar diagonal",
            JogMotion::Polar {
                azimuth: -1,
                altitude: 1,
            },
        ),
    ] {
        let top = rig.hold_jog(motion, 0.8).await;
        assert_capped(what, top, CAP);
        assert_eq!(rig.limits().await, ARM_LIMITS, "{what}");
    }
    // At 40 % the cap is 20 mm/s, for polar pans too.
    rig.command(ArmCommand::SetSpeed(40)).await;
    let polar = JogMotion::Polar {
        azimuth: 1,
        altitude: 1,
    };
    let top = rig.hold_jog(polar, 0.8).await;
    assert_capped("polar at 40 %", top, 0.4 * CAP);
    rig.driver.shutdown().await;
}

#[tokio::test]
async fn go_to_and_steps_run_under_the_cap_and_restore_the_limits() {
    let mut rig = rig(Arm::default()).await;
    let home = kinematics::forward(&kinematics::to_radians(&kinematics::HOME_DEG));
    let [tx, ty, tz] = [0.40f32, 0.10, 0.50];
    let [ox, oy, oz] = home.euler_deg().map(|v| v as f32);
    let target = Pose {
        x: tx,
        y: ty,
        z: tz,
        theta_x: ox,
        theta_y: oy,
        theta_z: oz,
    };
    rig.command(ArmCommand::MoveToPose(target)).await;
    let (top, lowest) = rig.follow_move().await;
    assert_capped("go to", top, CAP);
    assert!((lowest - CAP).abs() < 1e-6, "lowered to the cap: {lowest}");
    rig.limits_restored().await;

    for step in [
        StepMove::Cartesian {
            dx: 0,
            dy: -500,
            dz: -300,
        },
        StepMove::Polar {
            azimuth: 10,
            altitude: 0,
        },
    ] {
        rig.command(ArmCommand::Step(step)).await;
        let (top, _) = rig.follow_move().await;
        assert_capped(&format!("{step:?}"), top, CAP);
        rig.limits_restored().await;
    }
    rig.driver.shutdown().await;
}

#[tokio::test]
async fn home_runs_under_the_cap_and_restores_the_limits() {
    let away = kinematics::to_radians(&[30.0, 40.0, 160.0, 250.0, 20.0, 70.0, 60.0]);
    let mut rig = rig(Arm::at(away)).await;
    rig.command(ArmCommand::Home).await;
    let (top, _) = rig.follow_move().await;
    assert_capped("home", top, CAP);
    rig.limits_restored().await;
    rig.driver.shutdown().await;
}

#[tokio::test]
async fn a_stopped_or_abandoned_capped_move_gives_the_limits_back() {
    let away = kinematics::to_radians(&[30.0, 40.0, 160.0, 250.0, 20.0, 70.0, 60.0]);
    let mut rig = rig(Arm::at(away)).await;
    rig.command(ArmCommand::Home).await;
    assert_eq!(rig.limits().await.0, CAP as f32);
    rig.command(ArmCommand::Stop).await;
    rig.limits_restored().await;

    // Quitting mid-move: the move is stopped and the limits put back.
    rig.command(ArmCommand::Home).await;
    assert_eq!(rig.limits().await.0, CAP as f32);
    let Rig { sim, driver, .. } = rig;
    driver.shutdown().await;
    let s = sim.arm.snapshot().await.expect("sim alive");
    assert!(!s.moving, "stopped on quit");
    let limits = (
        s.speed_limit_linear as f32,
        s.speed_limit_angular_deg as f32,
    );
    assert_eq!(limits, ARM_LIMITS);
}

#[tokio::test]
async fn stored_actions_and_sequences_by_id_run_under_the_cap_as_home_does() {
    use armjog::kortex::{Stored, StoredMotion};
    // Zero (action 5) from a few degrees off it; sequence 1 (Retract, then Home) from Retract.
    for (from, stored) in [
        (
            [0.0, 20.0, 10.0, 25.0, 0.0, 20.0, 0.0],
            Stored {
                motion: StoredMotion::Action,
                id: 5,
            },
        ),
        (
            armjog::sim::stored::RETRACT_DEG,
            Stored {
                motion: StoredMotion::Sequence,
                id: 1,
            },
        ),
    ] {
        let mut rig = rig(Arm::at(kinematics::to_radians(&from))).await;
        rig.command(ArmCommand::StartStored(stored)).await;
        let (top, lowest) = rig.follow_move().await;
        assert_capped(&stored.to_string(), top, CAP);
        assert!(
            (lowest - CAP).abs() < 1e-6,
            "{stored}: lowered to the cap: {lowest}"
        );
        rig.limits_restored().await;
        rig.driver.shutdown().await;
    }
}
