//! The built-in simulated arm is named on the status bar at every width; a real link is not.

use std::time::Instant;

use ratatui::Terminal;
use ratatui::backend::TestBackend;

use armjog::console::app::{App, AppConfig, Input};
use armjog::console::jog::KeyKind;
use armjog::console::positions::PositionBook;
use armjog::console::ui::{self, Theme};
use armjog::console::view::View;
use armjog::link::interface::{ArmEvent, LinkStatus};

use crate::app_support::{buffer_text, config, key};

/// A console jogging +X over both links of an arm at loopback addresses, as the built-in
/// simulator gives them, or as a real arm's would read.
fn jogging(simulated: bool) -> (App, Instant) {
    let config = AppConfig {
        simulated,
        ..config()
    };
    let mut app = App::new(config, PositionBook::new());
    let t0 = Instant::now();
    let up = LinkStatus::Up {
        description:
            "talos 127.0.0.1:61616 (icd, crc16), operator 1.0 + modbus 127.0.0.1:5020 unit 1".into(),
    };
    app.handle(Input::Arm(ArmEvent::Status(up)), t0);
    app.handle(Input::Arm(ArmEvent::Speed(50)), t0);
    app.handle(key("w", KeyKind::Press), t0);
    (app, t0)
}

fn status(app: &App, width: u16) -> Terminal<TestBackend> {
    let mut terminal = Terminal::new(TestBackend::new(width, 2)).expect("terminal");
    let view = View::new(app);
    terminal
        .draw(|f| ui::status::draw(f, f.area(), &view, &Theme { color: false }))
        .expect("draw");
    terminal
}

#[test]
fn the_simulated_arm_is_named_at_40_80_and_160_columns() {
    let (app, _) = jogging(true);
    for width in [40, 80, 160] {
        let terminal = status(&app, width);
        let text = buffer_text(terminal.backend().buffer());
        assert!(
            text.starts_with(" SIMULATED ARM "),
            "{width} columns: {text:?}"
        );
        assert!(text.contains("JOG"), "{width} columns: {text:?}");
    }
    insta::assert_snapshot!("simulated_arm_status_40", status(&app, 40).backend());
    insta::assert_snapshot!("simulated_arm_status_80", status(&app, 80).backend());
    insta::assert_snapshot!("simulated_arm_status_160", status(&app, 160).backend());
}

#[test]
fn a_real_link_shows_its_address_and_no_simulator_badge() {
    let (app, _) = jogging(false);
    for width in [40, 80, 160] {
        let text = buffer_text(status(&app, width).backend().buffer());
        assert!(!text.contains("SIMULATED"), "{width} columns: {text:?}");
        assert!(text.starts_with(" LINK UP "), "{width} columns: {text:?}");
    }
    let wide = buffer_text(status(&app, 160).backend().buffer());
    assert!(wide.contains("talos 127.0.0.1:61616"), "{wide:?}");
}

#[test]
fn a_screen_too_small_still_names_the_simulated_arm() {
    let (mut app, t0) = jogging(true);
    app.handle(
        Input::Resize {
            width: 30,
            height: 8,
        },
        t0,
    );
    let mut terminal = Terminal::new(TestBackend::new(30, 8)).expect("terminal");
    let view = View::new(&app);
    terminal
        .draw(|f| ui::draw(f, &view, &Theme { color: false }))
        .expect("draw");
    let text = buffer_text(terminal.backend().buffer());
    assert!(text.starts_with("SIMULATED ARM: terminal too"), "{text:?}");
}
