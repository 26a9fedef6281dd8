//! What the app's state machine costs a jog key, warm and cold (a bench binary, not criterion).
//!
//! `App::handle` for a jog key's press (the START it decides) and its release (the STOP), on an
//! app with its link up and telemetry in, as the console's event loop calls it:
//! - warm: keys one after another, everything the key touches in the caches;
//! - cold: before each key a 64 MB buffer is written, so the key's code and data come from
//!   memory again, as they do for a technician's key after a pause.
//!
//! Warm, the call takes some 0.3 us; cold, twenty to forty times that (5-13 us on a 2-core
//! virtual machine): the key path's cost is what it touches, not what it computes. A change that
//! makes a key touch less (fewer hooks, fewer allocations, state kept together) shows here first, with
//! far less noise than a pty's end-to-end figures.
//!
//! Run with `cargo bench --bench app_key` (`ROUNDS=N` keys of each kind, 300 by default).

use std::time::{Duration, Instant};

// The tests' app helpers, shared by path as the test binaries share them.
#[path = "../tests/app_support/mod.rs"]
mod app_support;
#[path = "../tests/common/mod.rs"]
mod common;

use armjog::console::app::{App, AppConfig, Effect, Input};
use armjog::console::jog::KeyKind;
use armjog::console::positions::PositionBook;
use armjog::link::driver::hw_telemetry;
use armjog::link::interface::{ArmCommand, ArmEvent, LinkStatus};
use armjog::sim::arm_model::Arm;
use armjog::sim::telemetry::{actuator_feedback, arm_state};

/// Larger than any last-level cache this runs on: writing it evicts the key's lines.
const EVICT_BYTES: usize = 64 << 20;
/// The telemetry period at 30 Hz: the app hears a report between keys, as it does live.
const REPORT: Duration = Duration::from_millis(33);

/// What the simulated arm at home reports.
fn report() -> Input {
    let snapshot = Arm::default().snapshot();
    let feedback: Vec<_> = (1..=7).map(|j| actuator_feedback(&snapshot, j)).collect();
    let telemetry = hw_telemetry::telemetry(&arm_state(&snapshot), &feedback);
    Input::Arm(ArmEvent::Telemetry(Box::new(telemetry)))
}

/// An app with its Talos link up, telemetry in, key releases reported: the tests' session
/// (`tests/app_support`), on the simulated arm.
fn app(now: Instant) -> App {
    let config = AppConfig {
        simulated: true,
        ..app_support::config()
    };
    let mut app = App::new(config, PositionBook::new());
    let events = [
        ArmEvent::Status(LinkStatus::Up {
            description: "talos 127.0.0.1:61616 (icd, crc16), operator 1.0".into(),
        }),
        ArmEvent::Speed(50),
    ];
    for event in events {
        app.handle(Input::Arm(event), now);
    }
    app.handle(report(), now);
    app
}

fn is_jog(effects: &[Effect]) -> bool {
    effects
        .iter()
        .any(|e| matches!(e, Effect::Arm(ArmCommand::Jog(_))))
}

fn is_stop(effects: &[Effect]) -> bool {
    effects
        .iter()
        .any(|e| matches!(e, Effect::Arm(command) if command.is_stop()))
}

/// Press and release times of `rounds` keys, each key after a telemetry report and `before`.
fn measure(rounds: usize, mut before: impl FnMut()) -> (Vec<Duration>, Vec<Duration>) {
    let mut now = Instant::now();
    let mut app = app(now);
    let mut timed_key = |kind: KeyKind, now: Instant| {
        app.handle(report(), now);
        before();
        let started = Instant::now();
        let effects = app.handle(app_support::key("w", kind), now);
        (started.elapsed(), effects)
    };
    let (mut presses, mut releases) = (Vec::new(), Vec::new());
    for _ in 0..rounds {
        now += REPORT;
        let (took, effects) = timed_key(KeyKind::Press, now);
        presses.push(took);
        assert!(is_jog(&effects), "the press starts a jog: {effects:?}");
        now += REPORT;
        let (took, effects) = timed_key(KeyKind::Release, now);
        releases.push(took);
        assert!(is_stop(&effects), "the release stops: {effects:?}");
    }
    presses.sort();
    releases.sort();
    (presses, releases)
}

fn percentile(sorted: &[Duration], p: f64) -> Duration {
    let i = ((sorted.len() as f64 - 1.0) * p).round() as usize;
    sorted[i.min(sorted.len() - 1)]
}

fn line(name: &str, sorted: &[Duration]) {
    let us = |p| percentile(sorted, p).as_secs_f64() * 1e6;
    println!(
        "  {name:<14} p50 {:>7.2} us   p90 {:>7.2} us   max {:>7.2} us",
        us(0.5),
        us(0.9),
        us(1.0)
    );
}

fn main() {
    let rounds = std::env::var("ROUNDS")
        .ok()
        .and_then(|r| r.parse().ok())
        .unwrap_or(300);
    let mut evict = vec![0u8; EVICT_BYTES];
    let mut pass = 0u8;
    let (warm_press, warm_release) = measure(rounds, || {});
    let (cold_press, cold_release) = measure(rounds, || {
        pass = pass.wrapping_add(1);
        for byte in evict.iter_mut().step_by(64) {
            *byte = pass;
        }
        std::hint::black_box(&evict);
    });
    println!("App::handle for a jog key, {rounds} of each:");
    line("press, warm", &warm_press);
    line("release, warm", &warm_release);
    line("press, cold", &cold_press);
    line("release, cold", &cold_release);
}
