//! What the fence costs a telemetry sample, with a box, soft limits on J2, J4, J6 and 100 zones.
//!
//! - judge: `Fence::judge` of a held cartesian jog on a sample whose κ is known (the geometry);
//! - sample_and_judge: κ now and a step ahead (`kappa_ahead`, the Jacobian's SVDs) and the judge,
//!   what the app does per sample for a held jog;
//! - app_sample: `App::handle` of one telemetry report while a jog key is held, with that fence
//!   and without one: the whole per-sample cost in the state machine, and what the fence adds.
//!
//! Run: `cargo bench --bench fence_check -- --warm-up-time 1 --measurement-time 3`

use std::hint::black_box;
use std::sync::Arc;
use std::time::{Duration, Instant};

use armjog::console::app::{App, AppConfig, Input};
use armjog::console::jog::KeyKind;
use armjog::console::positions::PositionBook;
use armjog::kortex::gen3::HOME_DEG;
use armjog::link::driver::hw_telemetry;
use armjog::link::fence::{Aabb, Fence, Heading, KeepOut, Pace, Sample, kappa_ahead};
use armjog::link::interface::{ArmEvent, LinkStatus};
use armjog::sim::arm_model::Arm;
use armjog::sim::telemetry::{actuator_feedback, arm_state};
use criterion::{Criterion, criterion_group, criterion_main};

#[path = "../tests/app_support/mod.rs"]
mod app_support;
#[path = "../tests/common/mod.rs"]
mod common;

/// A box, three soft limits and `zones` 50 mm cubes spread over the floor, clear of the tool.
fn fence(zones: usize) -> Fence {
    let mut joints = [None; 7];
    joints[1] = Some([-120.0, 120.0]);
    joints[3] = Some([-140.0, 140.0]);
    joints[5] = Some([-115.0, 115.0]);
    let keep_out = (0..zones)
        .map(|i| {
            let (x, y) = (
                (i % 10) as f64 * 80.0 - 400.0,
                (i / 10) as f64 * 80.0 - 400.0,
            );
            KeepOut {
                name: format!("zone {i}"),
                zone: Aabb {
                    min: [x, y, -100.0],
                    max: [x + 50.0, y + 50.0, -50.0],
                },
                enabled: true,
            }
        })
        .collect();
    Fence {
        inside: Some(Aabb {
            min: [-800.0, -800.0, -200.0],
            max: [1000.0, 800.0, 1200.0],
        }),
        tool_radius: 40.0,
        joints,
        keep_out,
        ..Fence::default()
    }
}

const PACE: Pace = Pace {
    speed_mm_s: 125.0,
    joint_rate: 10.0,
    lookahead_s: 0.08,
};

fn report() -> Input {
    let snapshot = Arm::default().snapshot();
    let feedback: Vec<_> = (1..=7).map(|j| actuator_feedback(&snapshot, j)).collect();
    let telemetry = hw_telemetry::telemetry(&arm_state(&snapshot), &feedback);
    Input::Arm(ArmEvent::Telemetry(Box::new(telemetry)))
}

/// An app with its link up, telemetry in and `w` (+X) held.
fn jogging(fence: Option<Fence>) -> (App, Instant) {
    let config = AppConfig {
        fence: fence.map(Arc::new),
        ..app_support::config()
    };
    let mut app = App::new(config, PositionBook::new());
    let now = Instant::now();
    let up = LinkStatus::Up {
        description: "talos 127.0.0.1:61616 (icd, crc16), operator 1.0".into(),
    };
    for input in [
        Input::Arm(ArmEvent::Status(up)),
        Input::Arm(ArmEvent::Speed(50)),
        report(),
        app_support::key("w", KeyKind::Press),
    ] {
        app.handle(input, now);
    }
    assert!(app.jog().is_jogging(), "w held jogs");
    (app, now)
}

fn bench(c: &mut Criterion) {
    let fence = fence(100);
    let q = HOME_DEG.map(|a| if a > 180.0 { a - 360.0 } else { a });
    let heading = Heading::Axes([1, 0, 0]);
    let tool_mm = [450.0, 0.0, 300.0];
    let sample = Sample {
        tool_mm,
        joints_deg: q,
        joint_rates: [0.0; 7],
        kappa: kappa_ahead(&q, &heading),
    };
    c.bench_function("judge (100 zones)", |b| {
        b.iter(|| black_box(&fence).judge(black_box(&sample), heading, PACE))
    });
    c.bench_function("sample_and_judge (100 zones)", |b| {
        b.iter(|| {
            let sample = Sample {
                kappa: kappa_ahead(black_box(&q), &heading),
                ..sample
            };
            fence.judge(&sample, heading, PACE)
        })
    });
    for (name, fence) in [
        ("app_sample (no fence)", None),
        ("app_sample (100 zones)", Some(fence)),
    ] {
        let (mut app, mut now) = jogging(fence);
        let input = report();
        c.bench_function(name, |b| {
            b.iter(|| {
                // Telemetry at 30 Hz; a key repeat now and then keeps the jog held.
                now += Duration::from_millis(33);
                app.handle(input.clone(), now);
                app.handle(app_support::key("w", KeyKind::Repeat), now)
            })
        });
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
