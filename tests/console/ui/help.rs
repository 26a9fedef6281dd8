//! The footer and the `?` help from any keymap, and what the console does not offer where it
//! cannot work (saving on an ack-dialect link without telemetry).

use armjog::console::app::QUESTION_QUIET;
use std::time::{Duration, Instant};

use armjog::console::action::Action;
use armjog::console::app::{App, AppConfig, Effect, Input, Overlay, Severity};
use armjog::console::jog::{KeyKind, ReleaseMode};
use armjog::console::keymap::Keymap;
use armjog::console::positions::PositionBook;
use armjog::console::ui::{self, Theme};
use armjog::console::view::View;
use armjog::link::interface::{ArmEvent, LinkStatus, TelemetrySource};
use ratatui::Terminal;
use ratatui::backend::TestBackend;

use crate::app_support::{key, press, release};

/// A custom keymap with keys a footer could run together: named keys, a slash, modifiers.
const CUSTOM: &str = r#"{ "name": "custom", "bindings": {
    "i": "jog_x_plus", "space": "jog_x_minus", "-": "jog_y_plus", "kp/": "jog_y_minus",
    "pageup": "jog_z_plus", "ctrl+down": "jog_z_minus",
    "h": "pan_azimuth_plus", "l": "pan_azimuth_minus",
    "esc": "stop", "f10": "quit", "f1": "help", "s": "save_position" } }"#;

/// An ICD-dialect operator's telemetry.
const TALOS_HW: TelemetrySource = TelemetrySource::TalosHardware;

fn keymap(name: &str) -> Keymap {
    match name {
        "custom" => Keymap::from_json("custom.json", CUSTOM).expect("custom keymap"),
        builtin => Keymap::builtin(builtin).expect("built-in keymap"),
    }
}

/// A console on `keymap` with its link up; `telemetry` is what the driver says to expect.
fn app_with(
    keymap: Keymap,
    on_operator: bool,
    telemetry: TelemetrySource,
    size: (u16, u16),
) -> (App, Instant) {
    let config = AppConfig {
        keymap: keymap.into(),
        release_mode: ReleaseMode::Reported,
        refresh: Duration::from_millis(100),
        positions_on_operator: on_operator,
        max_jog_speed: 0.25,
        joint_jog_speed: armjog::link::driver::JOINT_JOG_SPEED,
        frames: !on_operator,
        simulated: false,
        arm_name: None,
        home_action: None,
        fence: None,

        config_file: None,

        new_profile: Vec::new(),

        recording_off: false,
    };
    let mut app = App::new(config, PositionBook::new());
    let t0 = Instant::now();
    for event in [
        ArmEvent::TelemetrySource(telemetry),
        ArmEvent::Status(LinkStatus::Up {
            description: "talos 127.0.0.1:61616 (icd, crc16), operator 1.0".into(),
        }),
        ArmEvent::Speed(50),
    ] {
        app.handle(Input::Arm(event), t0);
    }
    app.handle(
        Input::Resize {
            width: size.0,
            height: size.1,
        },
        t0,
    );
    (app, t0)
}

fn screen(app: &App) -> Terminal<TestBackend> {
    let (width, height) = app.size();
    let mut terminal = Terminal::new(TestBackend::new(width, height)).expect("terminal");
    terminal
        .draw(|f| ui::draw(f, &View::new(app), &Theme { color: false }))
        .expect("draw");
    terminal
}

fn text(terminal: &Terminal<TestBackend>) -> Vec<String> {
    let buffer = terminal.backend().buffer();
    let width = usize::from(buffer.area.width);
    buffer
        .content()
        .chunks(width)
        .map(|row| row.iter().map(|cell| cell.symbol()).collect())
        .collect()
}

fn footer(app: &App) -> String {
    let width = app.size().0;
    let mut terminal = Terminal::new(TestBackend::new(width, 1)).expect("terminal");
    terminal
        .draw(|f| ui::hints::draw(f, f.area(), &View::new(app), &Theme { color: false }))
        .expect("draw");
    text(&terminal).concat()
}

// ---- The footer ----

#[test]
fn footers_of_every_keymap_at_several_widths() {
    let mut shown = String::new();
    for name in ["default", "numpad", "custom"] {
        for width in [40, 62, 80, 120, 200] {
            let (app, _) = app_with(keymap(name), true, TALOS_HW, (width, 24));
            let line = footer(&app);
            shown.push_str(&format!("{name:>7} {width:>3} |{}|\n", line.trim_end()));
        }
    }
    insta::assert_snapshot!(shown);
}

#[test]
fn a_footer_never_cuts_a_key_name_and_keeps_stop_help_and_quit() {
    for name in ["default", "numpad", "custom"] {
        let keymap = keymap(name);
        let full = ui::hints::footer(&keymap, armjog::console::app::LinkActions::ALL, 1000);
        let key_names: Vec<String> = keymap.bindings().keys().map(|k| k.to_string()).collect();
        for width in 40..=full.len() {
            let line = ui::hints::footer(&keymap, armjog::console::app::LinkActions::ALL, width);
            assert!(line.chars().count() <= width, "{name} {width}: {line}");
            for group in line.split("  ") {
                assert!(full.contains(group), "{name} {width}: {group:?} was cut");
                let (keys, _) = group.split_once(' ').expect("keys and a label");
                let whole_names =
                    |sep: char| keys.split(sep).all(|k| key_names.contains(&k.into()));
                assert!(
                    keys == "arrows" || ['/', ',', ' '].into_iter().any(whole_names),
                    "{name} {width}: {keys:?} is not a list of key names"
                );
            }
            for action in [Action::Stop, Action::Help, Action::Quit] {
                let Some(first) = keymap.keys_for(action).first().map(|k| k.to_string()) else {
                    continue;
                };
                assert!(line.contains(&first), "{name} {width}: {first} missing");
            }
        }
    }
}

// ---- The help ----

#[test]
fn help_at_120x40_and_80x24() {
    for (width, height) in [(120, 40), (80, 24)] {
        let (mut app, t0) = app_with(keymap("default"), true, TALOS_HW, (width, height));
        press(&mut app, "?", t0);
        assert_eq!(*app.overlay(), Overlay::Help);
        insta::assert_snapshot!(format!("help_{width}x{height}"), screen(&app).backend());
    }
}

#[test]
fn help_that_fits_on_one_page() {
    let (mut app, t0) = app_with(keymap("default"), true, TALOS_HW, (100, 68));
    press(&mut app, "?", t0);
    press(&mut app, "pagedown", t0);
    assert_eq!(app.help_scroll(), 0, "nothing to scroll");
    insta::assert_snapshot!(screen(&app).backend());
}

#[test]
fn help_of_the_numpad_keymap_at_80x24_scrolled_to_its_end() {
    let (mut app, t0) = app_with(keymap("numpad"), true, TALOS_HW, (80, 24));
    press(&mut app, "?", t0);
    press(&mut app, "end", t0);
    insta::assert_snapshot!(screen(&app).backend());
}

#[test]
fn the_help_scrolls_to_every_action_and_closes_on_any_other_key() {
    for name in ["default", "numpad", "custom"] {
        let keymap = keymap(name);
        let help_key = keymap.keys_for(Action::Help)[0].to_string();
        let (mut app, t0) = app_with(keymap, true, TALOS_HW, (80, 24));
        press(&mut app, &help_key, t0);
        assert_eq!(
            *app.overlay(),
            Overlay::Help,
            "{name}: {help_key} opens the help"
        );
        let mut seen = String::new();
        let mut last_scroll = None;
        // Page down until the offset stops growing; the page overlaps by a line.
        while last_scroll != Some(app.help_scroll()) {
            last_scroll = Some(app.help_scroll());
            seen.push_str(&text(&screen(&app)).join("\n"));
            let effects = press(&mut app, "pagedown", t0);
            assert!(effects.is_empty(), "{name}: paging moved: {effects:?}");
            assert_eq!(*app.overlay(), Overlay::Help, "{name}: pagedown closed it");
        }
        assert!(
            app.help_scroll() > 0,
            "{name}: the help did not scroll at 80x24"
        );
        for action in Action::ALL {
            assert!(
                seen.contains(&action.name()),
                "{name}: {action:?} never shown"
            );
        }
        // Up a line, then back to the top.
        let end = app.help_scroll();
        press(&mut app, "up", t0);
        assert_eq!(app.help_scroll(), end - 1);
        press(&mut app, "pageup", t0);
        press(&mut app, "home", t0);
        assert_eq!(app.help_scroll(), 0);
        press(&mut app, "up", t0);
        assert_eq!(app.help_scroll(), 0, "no scrolling above the top");
        // Another key closes it and does nothing else; opening it again starts at the top.
        let effects = press(&mut app, "x", t0);
        assert!(
            effects.is_empty(),
            "{name}: closing the help did {effects:?}"
        );
        assert_eq!(*app.overlay(), Overlay::None);
    }
}

#[test]
fn scrolling_the_help_with_a_jog_key_never_moves_the_arm() {
    // Down is pan_altitude_minus in the default keymap: in the help it scrolls, and once the
    // help is closed the key still down moves nothing until it is pressed anew. (An ack
    // link: idle, it never goes stale, so the clock can run.)
    let (mut app, t0) = app_with(keymap("default"), true, TelemetrySource::None, (80, 24));
    press(&mut app, "?", t0);
    let effects = press(&mut app, "down", t0);
    assert!(effects.is_empty(), "{effects:?}");
    assert_eq!(app.help_scroll(), 1);
    let effects = app.handle(
        key("down", KeyKind::Repeat),
        t0 + Duration::from_millis(500),
    );
    assert!(effects.is_empty(), "a repeat in the help: {effects:?}");
    press(&mut app, "esc", t0 + Duration::from_millis(600));
    assert_eq!(*app.overlay(), Overlay::None);
    let effects = app.handle(
        key("down", KeyKind::Repeat),
        t0 + Duration::from_millis(640),
    );
    assert!(
        !app.jog().is_jogging(),
        "the held down key jogs after the help closed: {effects:?}"
    );
    release(&mut app, "down", t0 + Duration::from_millis(700));
    press(&mut app, "down", t0 + Duration::from_millis(800));
    assert!(app.jog().is_jogging(), "a fresh press pans");
}

// ---- Turns: only a Modbus link carries them ----

#[test]
fn the_turn_keys_are_offered_only_where_a_modbus_link_carries_them() {
    for (on_operator, telemetry, offered) in [
        (false, TelemetrySource::Modbus, true),
        (true, TelemetrySource::Modbus, true),
        (true, TelemetrySource::TalosHardware, false),
        (false, TelemetrySource::None, false),
    ] {
        let (app, _) = app_with(keymap("default"), on_operator, telemetry, (160, 40));
        assert_eq!(app.can_turn(), offered, "{telemetry:?}");
        let line = footer(&app);
        assert_eq!(
            line.contains("i/m/l/b/e/z turn"),
            offered,
            "{on_operator} {telemetry:?}: {line}"
        );
        assert!(line.contains("arrows pan"), "{telemetry:?}: {line}");
    }
}

// ---- Joint jogs: only a Talos operator in the ICD dialect carries them ----

#[test]
fn the_joint_keys_are_offered_only_where_a_talos_operator_carries_them() {
    for (on_operator, telemetry, offered) in [
        // Modbus alone, and an ack operator: no joint jog.
        (false, TelemetrySource::Modbus, false),
        (false, TelemetrySource::None, false),
        // An ICD operator, with or without Modbus beside it.
        (true, TelemetrySource::Modbus, true),
        (true, TALOS_HW, true),
    ] {
        let (app, _) = app_with(keymap("default"), on_operator, telemetry, (200, 40));
        assert_eq!(app.can_jog_joints(), offered, "{telemetry:?}");
        assert_eq!(app.link_actions().carries(Action::JointPlus), offered);
        let line = footer(&app);
        assert_eq!(
            line.contains("k/j joint"),
            offered,
            "{on_operator} {telemetry:?}: {line}"
        );
        assert!(line.contains("w/s/a/d/r/f jog"), "{telemetry:?}: {line}");
    }
}

#[test]
fn the_turn_keys_are_offered_until_the_driver_says_which_link_it_has() {
    let config = AppConfig {
        keymap: keymap("default").into(),
        release_mode: ReleaseMode::Reported,
        refresh: Duration::from_millis(100),
        positions_on_operator: false,
        max_jog_speed: 0.25,
        joint_jog_speed: armjog::link::driver::JOINT_JOG_SPEED,
        frames: true,
        simulated: false,
        arm_name: None,
        home_action: None,
        fence: None,

        config_file: None,

        new_profile: Vec::new(),

        recording_off: false,
    };
    let mut app = App::new(config, PositionBook::new());
    app.handle(
        Input::Resize {
            width: 160,
            height: 40,
        },
        Instant::now(),
    );
    assert!(app.can_turn());
    let line = footer(&app);
    assert!(line.contains("i/m/l/b/e/z turn"), "{line}");
}

// ---- The console's own book: no anchor toggle ----

#[test]
fn the_save_form_offers_an_anchor_only_where_an_operator_keeps_the_positions() {
    for (on_operator, telemetry) in [
        (true, TelemetrySource::TalosHardware),
        (false, TelemetrySource::Modbus),
    ] {
        let (mut app, t0) = app_with(keymap("default"), on_operator, telemetry, (120, 40));
        press(&mut app, "p", t0);
        let Overlay::Form(form) = app.overlay() else {
            panic!("{telemetry:?}: the form did not open")
        };
        let has_anchor = form.fields.iter().any(|f| f.label == "anchor");
        assert_eq!(has_anchor, on_operator, "{telemetry:?}: {form:?}");
        let shown = screen(&app);
        let text = text(&shown).join("\n");
        assert_eq!(text.contains("anchor: ["), on_operator, "{text}");
        assert_eq!(
            text.contains("anchors need Talos"),
            !on_operator,
            "the form says why: {text}"
        );
    }
}

#[test]
fn a_pose_saved_to_the_consoles_own_book_keeps_its_parent() {
    let (mut app, t0) = app_with(keymap("default"), false, TelemetrySource::Modbus, (120, 40));
    app.handle(
        Input::Arm(ArmEvent::Telemetry(Box::new(
            armjog::kortex::Telemetry::decode(&armjog::kortex::RegisterImage::default()),
        ))),
        t0,
    );
    press(&mut app, "p", t0);
    for c in "pick".chars() {
        press(&mut app, &c.to_string(), t0);
    }
    press(&mut app, "tab", t0);
    for c in "table".chars() {
        press(&mut app, &c.to_string(), t0);
    }
    let effects = press(&mut app, "enter", t0);
    assert!(
        effects
            .iter()
            .any(|e| matches!(e, Effect::SavePositions(_))),
        "{effects:?}"
    );
    let entry = app.positions().get("pick").expect("saved");
    assert_eq!(entry.parent.as_deref(), Some("table"));
    assert!(!entry.anchor);
    let (message, severity) = app.message().expect("said");
    assert_eq!(severity, Severity::Info, "{message}");
}

// ---- Ack dialect: no go-to to the console's own positions ----

/// The footer's keys as the view offers them, at 200 columns, whatever message is shown.
fn offered_footer(app: &App) -> String {
    let view = View::new(app);
    ui::hints::footer(&view.session.keymap, view.session.link_actions, 200)
}

/// Defines `name` at (x, y, z) mm with the set-cartesian form (`C`).
fn define_cartesian(app: &mut App, name: &str, at: [&str; 3], t0: Instant) {
    press(app, "C", t0);
    assert!(matches!(app.overlay(), Overlay::Form(_)), "the form opens");
    for field in std::iter::once(name).chain(at) {
        for c in field.chars() {
            press(app, &c.to_string(), t0);
        }
        press(app, "tab", t0);
    }
    press(app, "enter", t0);
    assert_eq!(*app.overlay(), Overlay::None, "{:?}", app.message());
}

#[test]
fn an_ack_link_says_why_it_cannot_go_to_a_position_the_console_keeps() {
    let (mut app, t0) = app_with(keymap("default"), false, TelemetrySource::None, (200, 40));
    define_cartesian(&mut app, "bench", ["400", "0", "300"], t0);
    assert_eq!(
        app.positions().get("bench").and_then(|e| e.cartesian),
        Some([4000, 0, 3000]),
        "stored locally, with its coordinates"
    );
    assert!(!app.can_go_to());
    let line = offered_footer(&app);
    assert!(!line.contains("go to"), "{line}");
    assert!(line.contains("h home"), "{line}");
    let effects = press(&mut app, "o", t0);
    assert!(effects.is_empty(), "{effects:?}");
    assert_eq!(*app.overlay(), Overlay::None, "nothing to confirm");
    let (message, severity) = app.message().expect("a message says why");
    assert_eq!(severity, Severity::Warning);
    assert!(!message.contains("no coordinates"), "{message}");
    assert!(message.contains("'bench'"), "{message}");
    assert!(message.contains("Modbus"), "{message}");
    assert!(message.contains("ack dialect"), "{message}");
}

#[test]
fn over_modbus_a_position_the_console_keeps_is_gone_to() {
    let (mut app, t0) = app_with(keymap("default"), false, TelemetrySource::Modbus, (200, 40));
    let mut ready = armjog::kortex::Telemetry::decode(&armjog::kortex::RegisterImage::default());
    ready.robot_state = armjog::kortex::Coded::Known(armjog::kortex::RobotState::Ready);
    app.handle(Input::Arm(ArmEvent::Telemetry(Box::new(ready))), t0);
    define_cartesian(&mut app, "bench", ["400", "0", "300"], t0);
    assert!(app.can_go_to());
    let line = offered_footer(&app);
    assert!(line.contains("o go to"), "{line}");
    press(&mut app, "o", t0);
    assert!(matches!(app.overlay(), Overlay::Confirm(_)), "asked first");
    let effects = press(&mut app, "y", t0 + QUESTION_QUIET);
    assert!(
        effects.iter().any(|e| matches!(
            e,
            Effect::Arm(armjog::link::interface::ArmCommand::MoveToPose(_))
        )),
        "{effects:?}"
    );
}

#[test]
fn over_modbus_without_telemetry_a_position_without_orientation_says_so() {
    let (mut app, t0) = app_with(keymap("default"), false, TelemetrySource::Modbus, (120, 40));
    define_cartesian(&mut app, "bench", ["400", "0", "300"], t0);
    let effects = press(&mut app, "o", t0);
    assert!(effects.is_empty(), "{effects:?}");
    assert_eq!(*app.overlay(), Overlay::None, "nothing to confirm");
    let (message, _) = app.message().expect("a message says why");
    assert!(message.contains("no orientation stored"), "{message}");
    assert!(message.contains("telemetry"), "{message}");
}

// ---- Ack dialect: no saving where it cannot work ----

#[test]
fn an_ack_link_without_telemetry_does_not_offer_saving() {
    let (mut app, t0) = app_with(keymap("default"), false, TelemetrySource::None, (120, 40));
    assert!(!app.can_save_position());
    let line = footer(&app);
    assert!(!line.contains("save"), "{line}");
    assert!(line.contains("h home"), "{line}");
    let effects = press(&mut app, "p", t0);
    assert!(effects.is_empty(), "{effects:?}");
    assert_eq!(*app.overlay(), Overlay::None, "no form opens");
    let (message, severity) = app.message().expect("a message says why");
    assert_eq!(severity, Severity::Warning);
    assert!(message.contains("cannot save"), "{message}");
    assert!(message.contains("ack dialect"), "{message}");
    assert!(message.contains("telemetry"), "{message}");
}

#[test]
fn saving_is_offered_where_it_can_work() {
    // An ICD operator saves the pose itself; a Modbus link beside an ack operator gives the
    // console the pose.
    for (on_operator, telemetry) in [
        (true, TelemetrySource::None),
        (true, TelemetrySource::TalosHardware),
        (false, TelemetrySource::Modbus),
    ] {
        let (mut app, t0) = app_with(keymap("default"), on_operator, telemetry, (120, 40));
        assert!(app.can_save_position(), "{on_operator} {telemetry:?}");
        let line = footer(&app);
        assert!(
            line.contains("p save"),
            "{on_operator} {telemetry:?}: {line}"
        );
        let effects: Vec<Effect> = press(&mut app, "p", t0);
        assert!(effects.is_empty(), "{effects:?}");
        assert!(matches!(app.overlay(), Overlay::Form(_)), "the form opens");
    }
}
