//! The history store (30 s of TCP speed and joint torque/current in 250 ms buckets) and the
//! limit warning, on a fake clock: the store and the app take `now`, so nothing here waits.

use std::time::{Duration, Instant};

use armjog::console::app::{
    BUCKETS, History, Input, JointQuantity, LIMIT_WARNING_DEG, near_limits,
};
use armjog::console::jog::{KeyKind, ReleaseMode};
use armjog::console::view::View;
use armjog::kortex::{RegisterImage, Telemetry};
use armjog::link::interface::ArmEvent;
use ratatui::style::Color;

use crate::app_support::{app, key, ms};
use crate::app_support::{row, screen, with_telemetry};

/// Telemetry at home with the given torques and currents, the tool at `x` m moving at `vx`
/// m/s.
fn sample(torque: [f32; 7], current: [f32; 7], x: f32, vx: f32) -> Telemetry {
    let mut t = Telemetry::decode(&RegisterImage::default());
    let home = [0.0, 15.0, 180.0, 230.0, 0.0, 55.0, 90.0];
    for (i, joint) in t.joints.iter_mut().enumerate() {
        joint.position = home[i];
        joint.torque = torque[i];
        joint.current = current[i];
    }
    t.tcp.pose.x = x;
    t.tcp.twist.x = vx;
    t
}

fn at_home(positions: [f32; 7]) -> Telemetry {
    let mut t = sample([0.0; 7], [0.0; 7], 0.4566, 0.0);
    for (joint, p) in t.joints.iter_mut().zip(positions) {
        joint.position = p;
    }
    t
}

#[test]
fn the_store_stays_bounded_and_ages_out_after_30_s() {
    let mut h = History::default();
    let t0 = Instant::now();
    let t = sample([1.0; 7], [0.5; 7], 0.4, 0.1);
    // 100 Hz for a minute: 6000 samples, never more than the window's buckets held.
    for i in 0..6000u64 {
        h.record(&t, t0 + ms(10 * i));
        assert!(h.len() <= BUCKETS + 1, "{} buckets at sample {i}", h.len());
    }
    let end = t0 + ms(60_000);
    let series = h.series(end);
    assert_eq!(series.speed.len(), BUCKETS);
    assert!(series.speed.iter().rev().skip(1).all(Option::is_some));
    // Silence: 31 s later every bucket has aged out of the window.
    let later = end + Duration::from_secs(31);
    let series = h.series(later);
    assert_eq!(series.speed.len(), BUCKETS);
    assert!(series.speed.iter().all(Option::is_none), "{series:?}");
    assert_eq!(series.hardest, None);
    // A sample after the silence drops the old buckets from memory too.
    h.record(&t, later);
    assert_eq!(h.len(), 1);
}

#[test]
fn a_bucket_joins_the_window_with_its_first_sample_so_a_still_arm_shows_the_same_series() {
    let mut h = History::default();
    let t0 = Instant::now();
    let t = sample([2.5; 7], [0.75; 7], 0.4, 0.0);
    // 30 Hz for 40 s, every sample alike: an arm at rest.
    let period = ms(33);
    let mut at = t0;
    while at < t0 + Duration::from_secs(40) {
        h.record(&t, at);
        at += period;
    }
    let last_sample = at - period;
    let shown = h.series(last_sample);
    assert!(shown.speed.iter().all(Option::is_some), "{shown:?}");
    // The next bucket begins before the next sample: the window waits for that sample rather
    // than showing an empty newest column.
    let next_bucket = t0 + ms(250 * ((last_sample - t0).as_millis() as u64 / 250 + 1));
    assert!(next_bucket < at, "a bucket begins between two samples");
    assert_eq!(h.series(next_bucket), shown);
    // Its first sample moves the window on, and a still arm's series reads the same.
    h.record(&t, at);
    assert_eq!(h.series(at), shown);
    assert_eq!(h.series(at).joints[3].last(), Some(&Some(2.5)));
    // Telemetry that stops ages out all the same, a bucket behind.
    let silent = h.series(at + ms(250 * 3));
    assert_eq!(
        silent.speed.iter().rev().take(2).collect::<Vec<_>>(),
        [&None, &None]
    );
}

#[test]
fn a_sample_from_before_the_newest_bucket_joins_it() {
    let t0 = Instant::now();
    let mut h = History::default();
    h.record(&sample([0.0; 7], [0.0; 7], 0.4, 0.0), t0);
    h.record(&sample([1.0; 7], [0.0; 7], 0.4, 0.1), t0 + ms(1000));
    // A clock that went back half a second.
    h.record(&sample([3.0; 7], [0.0; 7], 0.4, 0.3), t0 + ms(500));
    assert_eq!(h.len(), 2);
    let series = h.series(t0 + ms(1000));
    let newest = |v: &Vec<Option<f64>>| v.last().copied().flatten().unwrap();
    assert!((newest(&series.speed) - 300.0).abs() < 1e-3);
    assert!((newest(&series.joints[6]) - 2.0).abs() < 1e-6);
}

#[test]
fn the_speed_is_the_twists_or_else_from_successive_positions() {
    let t0 = Instant::now();
    let mut h = History::default();
    h.record(&sample([0.0; 7], [0.0; 7], 0.40, 0.2), t0);
    let series = h.series(t0);
    assert!((series.speed_now.unwrap() - 200.0).abs() < 1e-3);
    assert!((series.speed.last().unwrap().unwrap() - 200.0).abs() < 1e-3);

    // No twist: 10 mm in 100 ms is 100 mm/s.
    let mut h = History::default();
    h.record(&sample([0.0; 7], [0.0; 7], 0.40, 0.0), t0);
    h.record(&sample([0.0; 7], [0.0; 7], 0.41, 0.0), t0 + ms(100));
    let now = h.series(t0 + ms(100)).speed_now.unwrap();
    assert!((now - 100.0).abs() < 0.5, "{now}");
}

#[test]
fn a_bucket_keeps_the_peak_speed_and_the_mean_magnitude() {
    let t0 = Instant::now();
    let mut h = History::default();
    h.record(&sample([-2.0; 7], [1.0; 7], 0.4, 0.05), t0);
    h.record(&sample([4.0; 7], [3.0; 7], 0.4, 0.30), t0 + ms(50));
    h.record(&sample([0.0; 7], [2.0; 7], 0.4, 0.10), t0 + ms(100));
    let series = h.series(t0 + ms(100));
    let last = |v: &Vec<Option<f64>>| v.last().copied().flatten().unwrap();
    assert!((last(&series.speed) - 300.0).abs() < 1e-3);
    assert!(
        (last(&series.joints[0]) - 2.0).abs() < 1e-6,
        "mean |torque|"
    );
    assert!((series.speed_now.unwrap() - 100.0).abs() < 1e-3, "latest");
}

#[test]
fn a_key_cycles_torque_and_current() {
    let (mut app, t0) = app(ReleaseMode::Reported, false);
    let t = sample(
        [0.0, 12.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [3.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        0.4,
        0.0,
    );
    app.handle(Input::Arm(ArmEvent::Telemetry(Box::new(t))), t0);
    assert_eq!(app.history().quantity(), JointQuantity::Torque);
    assert_eq!(View::new(&app).arm.history.hardest.map(|h| h.0), Some(2));
    app.handle(key("T", KeyKind::Press), t0 + ms(10));
    assert_eq!(app.history().quantity(), JointQuantity::Current);
    let view = View::new(&app);
    assert_eq!(view.arm.history.quantity, JointQuantity::Current);
    assert_eq!(view.arm.history.hardest.map(|h| h.0), Some(1));
    app.handle(key("T", KeyKind::Press), t0 + ms(20));
    assert_eq!(app.history().quantity(), JointQuantity::Torque);
}

#[test]
fn the_hardest_joint_has_the_largest_mean_over_the_window() {
    let t0 = Instant::now();
    let mut h = History::default();
    // J3 peaks high once; J5 works steadily harder on average.
    for i in 0..40u64 {
        let mut torque = [0.0; 7];
        torque[2] = if i == 0 { 30.0 } else { 0.0 };
        torque[4] = 2.0;
        h.record(&sample(torque, [0.0; 7], 0.4, 0.0), t0 + ms(100 * i));
    }
    let (joint, mean) = h.series(t0 + ms(4000)).hardest.unwrap();
    assert_eq!(joint, 5);
    assert!((mean - 2.0).abs() < 1e-6, "{mean}");
}

#[test]
fn joints_within_5_degrees_of_a_limit_are_named_nearest_first() {
    // J4 at 145.9 (limit 147.8): 1.9 deg; J2 at -125 (reported 235): 3.9 deg; J6 at 110: 10.3.
    let t = at_home([0.0, 235.0, 180.0, 145.9, 0.0, 110.0, 90.0]);
    let near = near_limits(&t);
    let named: Vec<String> = near.iter().map(|n| n.text()).collect();
    assert_eq!(named, ["J4 1.9° from limit", "J2 3.9° from limit"]);
    // Continuous joints are never near a limit, wherever they are.
    let t = at_home([179.9, 15.0, 359.0, 230.0, 180.0, 55.0, 181.0]);
    assert!(near_limits(&t).is_empty());
    // Just outside the warning distance.
    let t = at_home([
        0.0,
        15.0,
        180.0,
        147.8 - LIMIT_WARNING_DEG - 0.01,
        0.0,
        55.0,
        90.0,
    ]);
    assert!(near_limits(&t).is_empty());
}

#[test]
fn the_status_bar_names_the_joint_and_its_gauge_turns_to_the_warning_colour() {
    let (app, _) = with_telemetry(at_home([0.0, 15.0, 180.0, 145.8, 0.0, 55.0, 90.0]));
    let terminal = screen(&app, 120, 30);
    let status = row(&terminal, 1);
    assert!(status.contains("J4 2.0° from limit"), "{status}");
    let buffer = terminal.backend().buffer();
    // The joints panel: J4's row is the fourth after the border and the header.
    let j4 = row(&terminal, 2 + 5);
    assert!(j4.contains("J4"), "{j4}");
    let gauge_x = j4
        .find("-|")
        .or_else(|| j4.find("|"))
        .map(|b| j4[..b].chars().count());
    let gauge_x = u16::try_from(gauge_x.expect("gauge on J4's row")).unwrap();
    assert_eq!(buffer[(gauge_x, 7)].fg, Color::Yellow, "{j4}");
    // J2 is far from its limit: its gauge keeps the default colour.
    let j2 = row(&terminal, 2 + 3);
    let x = u16::try_from(j2[..j2.find("-").unwrap()].chars().count()).unwrap();
    assert_eq!(buffer[(x, 5)].fg, Color::Reset, "{j2}");
    // The screen, then where the warning colour is (`W`) on the joints rows.
    let text: Vec<String> = (0..12).map(|y| row(&terminal, y)).collect();
    let warned: Vec<String> = (4..11)
        .map(|y| {
            (0..70)
                .map(|x| {
                    if buffer[(x, y)].fg == Color::Yellow {
                        'W'
                    } else {
                        '.'
                    }
                })
                .collect()
        })
        .collect();
    insta::assert_snapshot!(
        "status_and_joints_near_a_limit",
        format!(
            "{}\n\nwarning colour, joints rows:\n{}",
            text.join("\n"),
            warned.join("\n")
        )
    );
}

#[test]
fn the_history_panel_at_160x48_marks_the_hardest_joint() {
    let (mut app, t0) = with_telemetry(sample([0.0; 7], [0.0; 7], 0.4, 0.0));
    app.handle(
        armjog::console::app::Input::Resize {
            width: 160,
            height: 48,
        },
        t0,
    );
    for i in 1..=40u64 {
        let ramp = i as f32 / 40.0;
        let torque = [0.5, 12.0 * ramp, 0.3, 6.0, 0.2, 1.5, 0.1];
        let current = [0.1, 1.2, 0.3, 0.9, 0.1, 0.4, 0.05];
        let t = sample(torque, current, 0.4, 0.25 * ramp);
        app.handle(
            Input::Arm(ArmEvent::Telemetry(Box::new(t))),
            t0 + ms(250 * i),
        );
    }
    let terminal = screen(&app, 160, 48);
    // Wherever the layout put it: the rows from its top border, the columns of its box.
    let (top, left, width) = (0..48)
        .find_map(|y| {
            let line: Vec<char> = row(&terminal, y).chars().collect();
            let text: String = line.iter().collect();
            let start = text.find("┌ History")?;
            let left = text[..start].chars().count();
            let right = (left + 1..line.len()).find(|&x| line[x] == '┐')?;
            Some((y, left, right + 1 - left))
        })
        .expect("the history panel at 160x48");
    let panel: Vec<String> = (top..top + 11)
        .map(|y| row(&terminal, y).chars().skip(left).take(width).collect())
        .collect();
    let panel = panel.join("\n");
    assert!(panel.contains("hardest J2"), "{panel}");
    assert!(panel.contains("250.0 mm/s"), "{panel}");
    insta::assert_snapshot!("history_panel_160x48", panel);
}
