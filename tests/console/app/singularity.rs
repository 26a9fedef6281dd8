//! The arm near a singularity: the Jacobian's condition number at the reported joint angles
//! (Gen3 model), named on the status bar beside the joints near a limit, in the warning
//! colour, giving way like them at narrow widths; nothing without telemetry. On a fake clock:
//! telemetry goes straight into the app.

use armjog::console::app::{Input, SINGULARITY_WARNING};
use armjog::console::jog::ReleaseMode;
use armjog::console::view::View;
use armjog::kortex::gen3::HOME_DEG;
use armjog::kortex::{RegisterImage, Telemetry};
use armjog::link::interface::{ArmEvent, TelemetrySource};
use armjog::sim::kinematics::near_singularity_pose_deg;
use ratatui::style::Color;

use crate::app_support::app;
use crate::app_support::{row, screen, with_telemetry};

/// Telemetry reporting the joint angles `q_deg` (folded into 0-360 as the arm reports them).
fn reporting(q_deg: [f64; 7]) -> Telemetry {
    let mut t = Telemetry::decode(&RegisterImage::default());
    for (joint, q) in t.joints.iter_mut().zip(q_deg) {
        joint.position = q.rem_euclid(360.0) as f32;
    }
    t
}

/// Home with J4 `j4` degrees.
fn elbow(j4: f64) -> [f64; 7] {
    let mut q = HOME_DEG;
    q[3] = j4;
    q
}

#[test]
fn near_singular_telemetry_sets_the_view_and_home_does_not() {
    let (app, _) = with_telemetry(reporting(HOME_DEG));
    assert_eq!(View::new(&app).arm.near_singularity, None);
    // 11 degrees short of straight: not yet; 9: named.
    let (app, _) = with_telemetry(reporting(elbow(-11.0)));
    assert_eq!(View::new(&app).arm.near_singularity, None);
    let (mut app, t0) = with_telemetry(reporting(elbow(-9.0)));
    let kappa = View::new(&app)
        .arm
        .near_singularity
        .expect("9 deg short of straight");
    assert!(kappa > SINGULARITY_WARNING && kappa < 100.0, "{kappa}");
    // The next telemetry back at home clears it.
    app.handle(
        Input::Arm(ArmEvent::Telemetry(Box::new(reporting(HOME_DEG)))),
        t0,
    );
    assert_eq!(View::new(&app).arm.near_singularity, None);
    // Worked out when the joints move: a report with the same angles keeps the estimate, one
    // that bends the elbow again brings it back.
    let mut near = reporting(elbow(-9.0));
    app.handle(Input::Arm(ArmEvent::Telemetry(Box::new(near.clone()))), t0);
    near.arm.cpu_temperature += 1.0;
    app.handle(Input::Arm(ArmEvent::Telemetry(Box::new(near))), t0);
    assert_eq!(View::new(&app).arm.near_singularity, Some(kappa));
}

#[test]
fn the_status_bar_names_the_singularity_in_the_warning_colour() {
    let (app, _) = with_telemetry(reporting(near_singularity_pose_deg()));
    let terminal = screen(&app, 120, 30);
    let status = row(&terminal, 1);
    let text = "near singularity (κ 253)";
    let start = status.find(text).map(|b| status[..b].chars().count());
    let start = u16::try_from(start.expect("the warning on the status bar")).unwrap();
    let buffer = terminal.backend().buffer();
    let len = u16::try_from(text.chars().count()).unwrap();
    for x in start..start + len {
        assert_eq!(buffer[(x, 1)].fg, Color::Yellow, "{status}");
    }
    let rows: Vec<String> = (0..2).map(|y| row(&terminal, y)).collect();
    insta::assert_snapshot!("status_near_a_singularity", rows.join("\n"));
}

#[test]
fn with_a_joint_near_its_limit_too_both_show_and_narrow_the_limit_stays() {
    // J2 2 degrees short of its limit and the elbow 3 short of straight.
    let mut q = near_singularity_pose_deg();
    q[1] = 126.9;
    let (mut app, t0) = with_telemetry(reporting(q));
    let view = View::new(&app);
    assert_eq!(view.arm.near_limits.len(), 1, "{:?}", view.arm.near_limits);
    let kappa = view.arm.near_singularity.expect("near a singularity");
    let singular = format!("near singularity (κ {kappa:.0})");
    let both = format!("J2 2.0° from limit, {singular}");
    let wide = row(&screen(&app, 160, 30), 1);
    assert!(wide.contains(&both), "{wide}");
    // From the widest to the minimum: each warning shows whole or not at all, the limit as
    // long as any warning does, and a figure is never cut.
    let mut narrowed = false;
    for width in (40..=160u16).rev() {
        app.handle(Input::Resize { width, height: 30 }, t0);
        let status = row(&screen(&app, width, 30), 1);
        let has_singular = status.contains(&singular);
        let has_limit = status.contains("J2 2.0° from limit");
        assert_eq!(
            status.contains("singularity"),
            has_singular,
            "{width}: {status}"
        );
        assert!(
            !status.contains('…') || !status.contains('κ'),
            "{width}: {status}"
        );
        assert!(has_limit || !has_singular, "{width}: {status}");
        narrowed |= has_limit && !has_singular;
    }
    assert!(narrowed, "at some width only the limit shows");
}

#[test]
fn alone_it_shows_whole_down_to_the_minimum_width() {
    let (mut app, t0) = with_telemetry(reporting(near_singularity_pose_deg()));
    let mut shown = Vec::new();
    for width in 40..=120u16 {
        app.handle(Input::Resize { width, height: 24 }, t0);
        let status = row(&screen(&app, width, 24), 1);
        let whole = status.contains("near singularity (κ 253)");
        assert_eq!(status.contains("singularity"), whole, "{width}: {status}");
        assert!(!status.contains("κ") || whole, "{width}: {status}");
        // The key-release mode never gives way to it.
        assert!(status.contains("release"), "{width}: {status}");
        shown.push(whole);
    }
    // Idle, it fits even the minimum width: the last part to give way but the motion and the
    // key-release mode.
    assert!(shown.iter().all(|s| *s), "{shown:?}");
}

#[test]
fn without_telemetry_nothing_shows() {
    // The ack dialect carries no data back: no angles, no estimate.
    let (mut app, t0) = app(ReleaseMode::AutoRepeat, true);
    app.handle(
        Input::Arm(ArmEvent::TelemetrySource(TelemetrySource::None)),
        t0,
    );
    let view = View::new(&app);
    assert_eq!(view.arm.telemetry, None);
    assert_eq!(view.arm.near_singularity, None);
    let terminal = screen(&app, 120, 30);
    let status = row(&terminal, 1);
    assert!(!status.contains("singularity"), "{status}");
    assert!(!status.contains('κ'), "{status}");
}
