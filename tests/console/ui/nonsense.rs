//! Nonsense telemetry is shown as nonsense: a value out of physical range (1e9 deg, 1e30, NaN)
//! shows as `?` in the joints, tool, history and arm view panels, the arm panel names the field
//! and its registers, and a robot state the ICD does not list shows its number.

use std::time::Duration;

use armjog::console::app::Input;
use armjog::console::ui::arm_view;
use armjog::kortex::{Coded, RegisterImage, RobotState, Telemetry};
use armjog::link::interface::ArmEvent;

use armjog::console::app::App;
use armjog::console::ui::{self, Theme};
use armjog::console::view::View;

use crate::app_support::{buffer_text, row, screen, with_telemetry};

/// The history panel alone, 70 x 11.
fn history_panel(app: &App) -> ratatui::Terminal<ratatui::backend::TestBackend> {
    let mut terminal =
        ratatui::Terminal::new(ratatui::backend::TestBackend::new(70, 11)).expect("terminal");
    let view = View::new(app);
    terminal
        .draw(|f| ui::history::draw(f, f.area(), &view, &Theme { color: false }))
        .expect("draw");
    terminal
}

/// A sane snapshot at home, at rest.
fn sane() -> Telemetry {
    let mut t = Telemetry::decode(&RegisterImage::default());
    t.robot_state = Coded::Known(RobotState::Ready);
    t.arm.voltage = 24.0;
    let home = [0.0, 15.0, 180.0, 230.0, 0.0, 55.0, 90.0];
    for (j, angle) in t.joints.iter_mut().zip(home) {
        j.position = angle;
        j.temperature = 30.0;
    }
    t.tcp.pose.x = 0.4566;
    t.tcp.pose.z = 0.4338;
    t
}

fn nonsense() -> Telemetry {
    let mut t = sane();
    t.robot_state = Coded::Unknown(65535);
    t.joints[0].position = 1e9;
    t.joints[1].position = 1e30;
    t.joints[2].torque = 1e30;
    t.tcp.twist.x = f32::NAN;
    t
}

fn rows_with(
    terminal: &ratatui::Terminal<ratatui::backend::TestBackend>,
    part: &str,
) -> Vec<String> {
    let height = terminal.backend().buffer().area.height;
    (0..height)
        .map(|y| row(terminal, y))
        .filter(|r| r.contains(part))
        .collect()
}

#[test]
fn joints_out_of_range_show_a_question_mark_never_another_angle() {
    let (app, _) = with_telemetry(nonsense());
    let terminal = screen(&app, 160, 50);
    let text = buffer_text(terminal.backend().buffer());
    assert!(!text.contains("-80.00"), "1e9 deg is not shown as -80.00");
    assert!(!text.contains("120.00"), "1e30 deg is not shown as 120.00");
    let j1 = rows_with(&terminal, "J1 ");
    assert!(j1.iter().any(|r| r.contains(" ? ")), "{j1:#?}");
    // The arm panel names the field and its registers, and the state its number.
    assert!(text.contains("NONSENSE"), "{text}");
    assert!(
        text.contains("J1 position 1e9 (input registers 34-35)"),
        "{text}"
    );
    assert!(text.contains("unknown (65535)"), "{text}");
    assert!(!text.contains("unspecified (0)"));
    // The arm view does not draw an arm from nonsense angles.
    assert!(text.contains(&arm_view::NOT_FINITE[..30]), "{text}");
}

#[test]
fn a_nan_twist_is_not_a_speed_of_zero() {
    let (app, _) = with_telemetry(nonsense());
    let terminal = screen(&app, 160, 50);
    let text = buffer_text(terminal.backend().buffer());
    assert!(
        !text.contains("0.0 mm/s"),
        "a NaN twist reads ?, not 0.0 mm/s"
    );
    let vel = rows_with(&terminal, "vel");
    assert!(vel.iter().any(|r| r.contains('?')), "{vel:#?}");
    let history = history_panel(&app);
    let tcp = rows_with(&history, "TCP ");
    assert!(tcp.iter().any(|r| r.contains("? mm/s")), "{tcp:#?}");
}

#[test]
fn a_1e30_torque_in_the_history_is_a_question_mark_not_a_number_cut_at_the_edge() {
    let (mut app, t0) = with_telemetry(sane());
    for i in 1..=8u64 {
        let t = if i % 2 == 0 { nonsense() } else { sane() };
        app.handle(
            Input::Arm(ArmEvent::Telemetry(Box::new(t))),
            t0 + Duration::from_millis(100 * i),
        );
    }
    let history = history_panel(&app);
    let text = buffer_text(history.backend().buffer());
    assert!(!text.contains("1000000000"), "no 1e30 written out: {text}");
    let j3 = rows_with(&history, "J3 ");
    assert_eq!(j3.len(), 1, "{text}");
    // Its latest value, and its buckets with a nonsense sample, read `?`.
    assert!(j3[0].trim_end_matches([' ', '│']).ends_with('?'), "{j3:#?}");
    assert!(j3[0].contains("?"), "{j3:#?}");
    let j4 = rows_with(&history, "J4 ");
    assert!(
        !j4[0].contains('?'),
        "the other joints read numbers: {j4:#?}"
    );
}

#[test]
fn sane_telemetry_shows_numbers_and_no_warning() {
    let (app, _) = with_telemetry(sane());
    let terminal = screen(&app, 160, 50);
    let text = buffer_text(terminal.backend().buffer());
    assert!(!text.contains("NONSENSE"));
    assert!(text.contains("ready (7)"), "{text}");
    assert!(
        text.contains("-130.00"),
        "J4 at 230 deg reads -130.00: {text}"
    );
}
