//! Positions keep the whole pose: coordinates, orientation, joint angles (when the telemetry had
//! them) and the frame; books written before these were kept still load; `v` shows all of it.

use std::time::Instant;

use ratatui::Terminal;
use ratatui::backend::TestBackend;

use armjog::console::app::{App, Effect, Input, Overlay};
use armjog::console::jog::ReleaseMode;
use armjog::console::positions::{PoseFrame, PositionBook};
use armjog::console::ui::{self, Theme};
use armjog::console::view::View;
use armjog::kortex::{RegisterImage, Telemetry};
use armjog::link::interface::{ArmCommand, ArmEvent, PositionCoordinates};

use crate::app_support::{app, press};

/// Reported joint angles of the telemetry below, degrees.
const JOINTS: [f32; 7] = [359.5, 15.0, 180.0, 230.0, 0.0, 55.0, 90.0];

/// Telemetry at a pose with a known orientation and joint angles.
fn telemetry() -> Telemetry {
    let mut t = Telemetry::decode(&RegisterImage::default());
    t.tcp.pose.x = 0.4566;
    t.tcp.pose.y = -0.0012;
    t.tcp.pose.z = 0.4338;
    t.tcp.pose.theta_x = 90.0;
    t.tcp.pose.theta_y = -0.001;
    t.tcp.pose.theta_z = 89.5;
    for (joint, angle) in t.joints.iter_mut().zip(JOINTS) {
        joint.position = angle;
    }
    t
}

fn with_telemetry(on_operator: bool) -> (App, Instant) {
    let (mut app, t0) = app(ReleaseMode::Reported, on_operator);
    app.handle(Input::Arm(ArmEvent::Telemetry(Box::new(telemetry()))), t0);
    (app, t0)
}

fn type_text(app: &mut App, text: &str, now: Instant) {
    for c in text.chars() {
        press(app, &c.to_string(), now);
    }
}

fn assert_whole_pose(app: &App, name: &str) {
    let entry = app.positions().get(name).expect("saved");
    assert_eq!(entry.cartesian, Some([4566, -12, 4338]));
    assert_eq!(entry.orientation, Some([90.0, -0.001, 89.5]));
    assert_eq!(entry.joints, Some(JOINTS));
    assert_eq!(entry.frame, PoseFrame::Base);
}

#[test]
fn a_book_in_the_old_format_loads_and_the_whole_pose_survives_a_save() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("arm.json");
    // As armjog wrote books before joint angles and the frame were kept.
    std::fs::write(
        &path,
        r#"{
  "format": 1,
  "positions": {
    "home": { "anchor": false, "cartesian": [4566, 10, 4338], "orientation": [90.0, 0.0, 90.0] },
    "pick": { "anchor": true, "parent": "home", "cartesian": [5000, -1205, 2500] },
    "ghost": {}
  }
}
"#,
    )
    .expect("write the old book");
    let mut book = PositionBook::load(&path).expect("an old book loads");
    let home = book.get("home").expect("home");
    assert_eq!(home.cartesian, Some([4566, 10, 4338]));
    assert_eq!(home.orientation, Some([90.0, 0.0, 90.0]));
    assert_eq!(home.joints, None, "no joint angles were kept then");
    assert_eq!(
        home.frame,
        PoseFrame::Base,
        "coordinates were base-frame then"
    );
    assert!(book.get("pick").is_some_and(|e| e.anchor));
    assert_eq!(book.get("ghost").and_then(|e| e.cartesian), None);

    book.get_or_insert("home").joints = Some(JOINTS);
    book.save(&path).expect("saved");
    let text = std::fs::read_to_string(&path).expect("read back");
    assert!(text.contains(r#""frame": "base""#), "{text}");
    assert!(text.contains(r#""joints": ["#), "{text}");
    assert_eq!(PositionBook::load(&path).expect("loads"), book);
}

#[test]
fn saving_over_modbus_keeps_the_whole_pose_from_the_telemetry() {
    let (mut app, t0) = with_telemetry(false);
    press(&mut app, "p", t0);
    type_text(&mut app, "pick", t0);
    let effects = press(&mut app, "enter", t0);
    assert!(
        effects
            .iter()
            .any(|e| matches!(e, Effect::SavePositions(book) if book.get("pick").is_some())),
        "{effects:?}"
    );
    assert_whole_pose(&app, "pick");
}

#[test]
fn saving_on_the_operator_keeps_the_whole_pose_from_the_telemetry() {
    let (mut app, t0) = with_telemetry(true);
    app.handle(
        Input::Arm(ArmEvent::Done {
            command: ArmCommand::SavePosition {
                name: "pick".into(),
                anchor: false,
                parent: None,
            },
        }),
        t0,
    );
    assert_whole_pose(&app, "pick");
}

#[test]
fn joint_angles_go_once_the_operator_says_the_position_moved() {
    let (mut app, t0) = with_telemetry(true);
    let saved = ArmCommand::SavePosition {
        name: "pick".into(),
        anchor: false,
        parent: None,
    };
    app.handle(Input::Arm(ArmEvent::Done { command: saved }), t0);
    let reply = |cartesian| {
        Input::Arm(ArmEvent::Position {
            name: "pick".into(),
            coordinates: PositionCoordinates {
                cartesian: Some(cartesian),
                polar: None,
            },
        })
    };
    // The operator's rounding: the same place.
    app.handle(reply([4567, -12, 4338]), t0);
    assert_eq!(
        app.positions().get("pick").and_then(|e| e.joints),
        Some(JOINTS)
    );
    // Its parent moved it (anchored): the angles describe another place.
    app.handle(reply([4600, -12, 4338]), t0);
    let entry = app.positions().get("pick").expect("kept");
    assert_eq!(entry.cartesian, Some([4600, -12, 4338]));
    assert_eq!(entry.joints, None);
}

fn render_dialog(app: &App, width: u16, height: u16) -> Terminal<TestBackend> {
    let mut terminal = Terminal::new(TestBackend::new(width, height)).expect("terminal");
    let view = View::new(app);
    terminal
        .draw(|frame| {
            let area = frame.area();
            ui::dialog::draw(frame, area, &view, &Theme { color: false })
        })
        .expect("draw");
    terminal
}

#[test]
fn v_shows_the_whole_pose_with_units() {
    let (mut app, t0) = with_telemetry(false);
    press(&mut app, "p", t0);
    type_text(&mut app, "pick", t0);
    press(&mut app, "enter", t0);
    press(&mut app, "v", t0);
    assert!(matches!(app.overlay(), Overlay::Position { .. }));
    insta::assert_snapshot!(render_dialog(&app, 80, 12).backend());
}

#[test]
fn v_on_the_operator_shows_its_coordinates_and_the_remembered_pose() {
    let (mut app, t0) = with_telemetry(true);
    let saved = ArmCommand::SavePosition {
        name: "pick".into(),
        anchor: false,
        parent: None,
    };
    app.handle(Input::Arm(ArmEvent::Done { command: saved }), t0);
    press(&mut app, "v", t0);
    app.handle(
        Input::Arm(ArmEvent::Position {
            name: "pick".into(),
            coordinates: PositionCoordinates {
                cartesian: Some([4566, -12, 4338]),
                polar: Some([436, -2, 6315]),
            },
        }),
        t0,
    );
    insta::assert_snapshot!(render_dialog(&app, 80, 12).backend());
}

#[test]
fn a_value_the_telemetry_garbled_is_not_kept_and_the_book_still_loads() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    let mut garbled = telemetry();
    garbled.tcp.pose.theta_y = f32::NAN;
    garbled.joints[3].position = f32::INFINITY;
    app.handle(Input::Arm(ArmEvent::Telemetry(Box::new(garbled))), t0);
    app.handle(
        Input::Arm(ArmEvent::Done {
            command: ArmCommand::SavePosition {
                name: "pick".into(),
                anchor: false,
                parent: None,
            },
        }),
        t0,
    );
    let entry = app.positions().get("pick").expect("saved");
    assert_eq!(entry.cartesian, Some([4566, -12, 4338]));
    assert_eq!(entry.orientation, None);
    assert_eq!(entry.joints, None);
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("arm.json");
    app.positions().save(&path).expect("saved");
    assert_eq!(&PositionBook::load(&path).expect("loads"), app.positions());
}
