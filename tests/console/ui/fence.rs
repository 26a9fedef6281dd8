//! The fence on screen: the arm view draws the box (blue), the zones (red) and the tool's
//! sphere in both projections; the tool panel's title names the nearest face or zone; the status
//! bar says what the fence does. On a fake clock, the arm at home.

use std::sync::Arc;
use std::time::Instant;

use armjog::console::app::{App, AppConfig, Input};
use armjog::console::positions::PositionBook;
use armjog::console::ui::{Theme, arm_view, tcp};
use armjog::console::view::View;
use armjog::kortex::{Coded, RegisterImage, RobotState, Telemetry, gen3};
use armjog::link::fence::{Aabb, Fence, KeepOut};
use armjog::link::interface::{ArmEvent, LinkStatus, TelemetrySource};
use ratatui::Terminal;
use ratatui::backend::TestBackend;

use crate::app_support::config;

/// The cell of the example, the table's top 110 mm under the sphere at home.
fn cell() -> Fence {
    Fence {
        inside: Some(Aabb {
            min: [-600.0, -600.0, 0.0],
            max: [800.0, 600.0, 900.0],
        }),
        tool_radius: 40.0,
        keep_out: vec![KeepOut {
            name: "table".into(),
            zone: Aabb {
                min: [250.0, -400.0, -100.0],
                max: [900.0, 400.0, 284.0],
            },
            enabled: true,
        }],
        ..Fence::default()
    }
}

/// A console with the cell's fence, its arm at home reporting its tool point.
fn at_home() -> App {
    let config = AppConfig {
        fence: Some(Arc::new(cell())),
        ..config()
    };
    let mut app = App::new(config, PositionBook::new());
    let mut t = Telemetry::decode(&RegisterImage::default());
    t.robot_state = Coded::Known(RobotState::Ready);
    for (joint, q) in t.joints.iter_mut().zip(gen3::HOME_DEG) {
        joint.position = q as f32;
    }
    let tool = gen3::tool_position(&gen3::HOME_DEG.map(f64::to_radians));
    (t.tcp.pose.x, t.tcp.pose.y, t.tcp.pose.z) = (tool.x as f32, tool.y as f32, tool.z as f32);
    let t0 = Instant::now();
    let up = LinkStatus::Up {
        description: "test".into(),
    };
    for event in [
        ArmEvent::Status(up),
        ArmEvent::TelemetrySource(TelemetrySource::Modbus),
        ArmEvent::Telemetry(Box::new(t)),
    ] {
        app.handle(Input::Arm(event), t0);
    }
    app
}

#[test]
fn the_arm_view_draws_the_box_the_table_and_the_tool_sphere() {
    let app = at_home();
    let mut terminal = Terminal::new(TestBackend::new(86, 19)).expect("terminal");
    terminal
        .draw(|f| arm_view::draw(f, f.area(), &View::new(&app), &Theme { color: true }))
        .expect("draw");
    insta::assert_snapshot!("arm_view_fence", terminal.backend());
}

#[test]
fn the_tool_panel_names_the_nearest_face_or_zone() {
    let app = at_home();
    // Home's tool point is 433.8 mm up: the sphere 109.8 mm over the table's top at 284.
    let view = View::new(&app);
    let (name, mm) = view.arm.fence_nearest.clone().expect("a nearest barrier");
    assert_eq!(name, "table");
    assert!((mm - 109.8).abs() < 0.1, "{mm}");
    let mut terminal = Terminal::new(TestBackend::new(60, 10)).expect("terminal");
    terminal
        .draw(|f| tcp::draw(f, f.area(), &view, &Theme { color: false }))
        .expect("draw");
    let top: String = (0..60)
        .map(|x| terminal.backend().buffer()[(x, 0)].symbol().to_string())
        .collect();
    assert!(top.contains("Tool (TCP), table 110 mm"), "{top}");
}
