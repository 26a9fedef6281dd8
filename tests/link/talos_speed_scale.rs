//! Set Speed over Talos in the operator's own percentage, through the arm driver against the
//! simulator over real sockets (Talos jogs, Modbus telemetry). An operator whose 100 % is
//! faster than the console's cap is asked for the share of it that keeps the tool under the
//! cap; asked one-to-one (what the driver did before it knew the operator's full speed), it
//! runs over. An operator found over the cap at attach is brought under it before any motion.
//!
//! Speeds are the tool twist the Modbus telemetry reports; the driver alone (no state machine,
//! so no watch) shows what the command does.

use std::time::Duration;

use tokio::sync::mpsc::UnboundedReceiver;

use armjog::console::jog::JogMotion;
use armjog::link::driver::{Driver, DriverConfig, INITIAL_SPEED};
use armjog::link::interface::{ArmCommand, ArmEvent, LinkStatus};
use armjog::link::{ModbusConfig, TalosConfig};
use armjog::sim::{SimConfig, Simulator};

/// The console's cap, m/s.
const CAP: f64 = 0.05;

struct Rig {
    sim: Simulator,
    driver: Driver,
    events: UnboundedReceiver<ArmEvent>,
    /// The events before the link came up.
    before_up: Vec<ArmEvent>,
}

/// A driver with a 50 mm/s cap on a simulator whose operator runs `operator_full` m/s at its
/// 100 %, told it is `told` m/s.
async fn rig(operator_full: f64, told: f64) -> Rig {
    let sim = Simulator::start(SimConfig {
        max_jog_speed: operator_full,
        ..SimConfig::ephemeral()
    })
    .await
    .expect("simulator");
    let talos = TalosConfig::new(sim.talos_addr.to_string());
    let modbus = ModbusConfig::new(sim.modbus_addr.expect("modbus").to_string());
    let mut config = DriverConfig::new(Some(talos), Some(modbus));
    config.max_jog_speed = CAP;
    config.operator_full_speed = told;
    let (driver, mut events) = Driver::spawn(config);
    let mut before_up = Vec::new();
    let up = async {
        while let Some(e) = events.recv().await {
            if let ArmEvent::Status(LinkStatus::Up { .. }) = e {
                return;
            }
            before_up.push(e);
        }
    };
    tokio::time::timeout(Duration::from_secs(10), up)
        .await
        .expect("link up within 10 s");
    Rig {
        sim,
        driver,
        events,
        before_up,
    }
}

fn twist_mm_s(e: &ArmEvent) -> Option<f64> {
    let ArmEvent::Telemetry(t) = e else {
        return None;
    };
    let v = &t.tcp.twist;
    Some(f64::from(v.x.hypot(v.y).hypot(v.z)) * 1000.0)
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

    async fn operator_speed(&self) -> u8 {
        self.sim
            .arm
            .with(|_, op| op.speed())
            .await
            .expect("sim alive")
    }

    /// Holds `motion` for `seconds` (re-sent every 100 ms, as a held key is); the top tool
    /// speed the telemetry reported.
    async fn hold(&mut self, motion: JogMotion, seconds: f64) -> f64 {
        let mut top = 0.0f64;
        let until = tokio::time::Instant::now() + Duration::from_secs_f64(seconds);
        let mut resend = tokio::time::Instant::now();
        while tokio::time::Instant::now() < until {
            if tokio::time::Instant::now() >= resend {
                assert!(self.driver.send(ArmCommand::Jog(motion)));
                resend += Duration::from_millis(100);
            }
            if let Ok(Some(e)) =
                tokio::time::timeout(Duration::from_millis(20), self.events.recv()).await
                && let Some(mm_s) = twist_mm_s(&e)
                && mm_s.is_finite()
            {
                top = top.max(mm_s);
            }
        }
        assert!(self.driver.send(ArmCommand::Stop));
        self.wait_event(|e| matches!(e, ArmEvent::StopConfirmed))
            .await;
        top
    }
}

const CARTESIAN: JogMotion = JogMotion::Cartesian { x: 1, y: 0, z: 0 };
const POLAR: JogMotion = JogMotion::Polar {
    azimuth: 1,
    altitude: 0,
};

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_operator_over_the_cap_at_attach_is_brought_under_it_and_told() {
    // The simulated operator starts at 50 %: 250 mm/s of its 500, five times the cap.
    let rig = rig(0.5, 0.5).await;
    assert!(
        rig.before_up.contains(&ArmEvent::Speed(INITIAL_SPEED)),
        "{:?}",
        rig.before_up
    );
    let notice = rig.before_up.iter().find_map(|e| match e {
        ArmEvent::Notice(text) => Some(text.clone()),
        _ => None,
    });
    assert_eq!(
        notice.as_deref(),
        Some(
            "the operator was at 50% (250 mm/s), over the 50 mm/s cap: set to 25 mm/s (50% of the cap)"
        )
    );
    // 25 mm/s of 500 is 5 %.
    assert_eq!(rig.operator_speed().await, 5);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn set_speed_in_the_operators_percentage_keeps_the_tool_under_the_cap() {
    // The case too: a polar pan on an operator at its default 250 mm/s.
    for (full, motion, what) in [
        (0.5, CARTESIAN, "cartesian"),
        (0.5, POLAR, "polar"),
        (0.25, POLAR, "polar"),
    ] {
        let mut rig = rig(full, full).await;
        assert!(rig.driver.send(ArmCommand::SetSpeed(100)));
        // The console's 100 % stays 100 % of its cap, whatever the operator was asked.
        assert_eq!(
            rig.wait_event(|e| matches!(e, ArmEvent::Speed(_))).await,
            ArmEvent::Speed(100)
        );
        let share = (100.0 * CAP / full).round() as u8;
        assert_eq!(rig.operator_speed().await, share, "50 mm/s of {full} m/s");
        let top = rig.hold(motion, 2.0).await;
        let full = full * 1000.0;
        eprintln!("{what}: cap 50, operator {full} told {full}: top {top:.1} mm/s");
        assert!(top < 55.0, "{what}: {top:.1} mm/s over the 50 mm/s cap");
        assert!(top > 10.0, "{what}: only {top:.1} mm/s");
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn asked_one_to_one_a_faster_operator_runs_over_the_cap() {
    // What the driver did before it knew the operator's full speed: Set Speed 100 went out as
    // 100. Told the operator's full speed is the cap, it does so still.
    for (full, motion, what) in [(0.5, CARTESIAN, "cartesian"), (0.25, POLAR, "polar")] {
        let mut rig = rig(full, CAP).await;
        assert!(rig.driver.send(ArmCommand::SetSpeed(100)));
        rig.wait_event(|e| matches!(e, ArmEvent::Speed(100))).await;
        assert_eq!(rig.operator_speed().await, 100);
        let top = rig.hold(motion, 2.5).await;
        let full = full * 1000.0;
        eprintln!("{what}: cap 50, operator {full} asked one-to-one: top {top:.1} mm/s");
        assert!(top > 100.0, "{what}: {top:.1} mm/s");
    }
}
