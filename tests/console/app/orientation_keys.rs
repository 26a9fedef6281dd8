//! Orientation jog keys in the console's state machine on a fake clock: each key turns about its
//! axis with its sign, turns combine, and release, focus loss and a refused jog stop them; the
//! status bar names the turn, its rate and its frame.

use armjog::console::app::{App, Effect, Input};
use armjog::console::jog::{JogMotion, KeyKind, ReleaseMode};
use armjog::console::ui::{Theme, status};
use armjog::console::view::View;
use armjog::kortex::ReferenceFrame;
use armjog::link::driver::ORIENTATION_NEEDS_MODBUS;
use armjog::link::interface::{ArmCommand, ArmError, ArmEvent, CommandKind};
use ratatui::Terminal;
use ratatui::backend::TestBackend;

use crate::app_support::*;

fn turn(rx: i8, ry: i8, rz: i8) -> Effect {
    Effect::Arm(ArmCommand::Jog(JogMotion::Orientation { rx, ry, rz }))
}

/// A Modbus console (frames apply) with release events.
fn modbus_app() -> (App, std::time::Instant) {
    app(ReleaseMode::Reported, false)
}

#[test]
fn each_turn_key_turns_about_its_axis_with_its_sign() {
    let cases = [
        ("i", turn(1, 0, 0)),
        ("m", turn(-1, 0, 0)),
        ("l", turn(0, 1, 0)),
        ("b", turn(0, -1, 0)),
        ("e", turn(0, 0, 1)),
        ("z", turn(0, 0, -1)),
    ];
    for (key, expected) in cases {
        let (mut app, t0) = modbus_app();
        assert_eq!(
            press(&mut app, key, t0),
            std::slice::from_ref(&expected),
            "{key}"
        );
        // Held: the START is refreshed, as for every jog.
        assert_eq!(app.handle(Input::Tick, t0 + ms(100)), [expected], "{key}");
        assert_eq!(release(&mut app, key, t0 + ms(150)), [STOP], "{key}");
        assert!(app.handle(Input::Tick, t0 + ms(400)).is_empty(), "{key}");
    }
}

#[test]
fn turn_keys_combine_and_a_change_to_or_from_a_translation_goes_through_a_stop() {
    let (mut app, t0) = modbus_app();
    assert_eq!(press(&mut app, "i", t0), [turn(1, 0, 0)]);
    assert_eq!(press(&mut app, "b", t0 + ms(10)), [turn(1, -1, 0)]);
    assert_eq!(release(&mut app, "i", t0 + ms(20)), [turn(0, -1, 0)]);
    // Another family: the turn stops before the translation starts.
    assert_eq!(press(&mut app, "w", t0 + ms(30)), [STOP, jog(1, 0, 0)]);
    assert_eq!(release(&mut app, "w", t0 + ms(40)), [STOP, turn(0, -1, 0)]);
    assert_eq!(release(&mut app, "b", t0 + ms(50)), [STOP]);
}

#[test]
fn a_turn_stops_on_focus_loss_and_moves_again_only_after_a_fresh_press() {
    let (mut app, t0) = modbus_app();
    assert_eq!(press(&mut app, "e", t0), [turn(0, 0, 1)]);
    assert_eq!(app.handle(Input::FocusLost, t0 + ms(50)), [STOP]);
    assert!(app.handle(Input::FocusGained, t0 + ms(60)).is_empty());
    // Still down, repeating: latched, nothing moves.
    for t in [90, 120, 150] {
        assert!(
            app.handle(key("e", KeyKind::Repeat), t0 + ms(t)).is_empty(),
            "repeat at {t} ms"
        );
    }
    assert!(app.handle(Input::Tick, t0 + ms(200)).is_empty());
    assert!(release(&mut app, "e", t0 + ms(210)).is_empty());
    assert_eq!(press(&mut app, "e", t0 + ms(300)), [turn(0, 0, 1)]);
}

#[test]
fn a_turn_the_link_refuses_stops_and_says_why() {
    let (mut app, t0) = modbus_app();
    assert_eq!(press(&mut app, "l", t0), [turn(0, 1, 0)]);
    let refused = Input::Arm(ArmEvent::Failed {
        command: CommandKind::Jog,
        error: ArmError::Unsupported(ORIENTATION_NEEDS_MODBUS),
    });
    assert_eq!(app.handle(refused, t0 + ms(20)), [STOP]);
    let (message, _) = app.message().expect("a message");
    assert!(
        message.contains("orientation jog needs the Modbus link"),
        "{message}"
    );
    // The key is still down: no refresh, nothing restarts.
    assert!(app.handle(Input::Tick, t0 + ms(200)).is_empty());
}

#[test]
fn fallback_a_turn_key_tap_moves_nothing_and_says_a_hold_is_needed() {
    let (mut app, t0) = app(ReleaseMode::AutoRepeat, false);
    assert!(press(&mut app, "i", t0).is_empty());
    let later = app.handle(Input::Tick, t0 + ms(1000));
    assert!(
        !later
            .iter()
            .any(|e| matches!(e, Effect::Arm(ArmCommand::Jog(_) | ArmCommand::Step(_)))),
        "{later:?}"
    );
    let (message, _) = app.message().expect("a message");
    assert!(message.contains("only while held"), "{message}");
}

/// The status bar's text at `width` columns.
fn status_text(app: &App, width: u16) -> String {
    let mut terminal = Terminal::new(TestBackend::new(width, 2)).expect("terminal");
    let view = View::new(app);
    terminal
        .draw(|f| status::draw(f, f.area(), &view, &Theme { color: false }))
        .expect("draw");
    let buffer = terminal.backend().buffer().clone();
    buffer
        .content()
        .chunks(usize::from(width))
        .map(|row| row.iter().map(|c| c.symbol()).collect::<String>())
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn the_status_bar_shows_the_turn_its_rate_in_deg_per_s_and_the_frame() {
    let (mut app, t0) = modbus_app();
    app.handle(
        Input::Resize {
            width: 120,
            height: 40,
        },
        t0,
    );
    app.handle(Input::Arm(ArmEvent::Speed(50)), t0);
    assert_eq!(
        press(&mut app, "g", t0),
        [Effect::Arm(ArmCommand::SetFrame(ReferenceFrame::Tool))]
    );
    let start = press(&mut app, "e", t0 + ms(10));
    assert_eq!(start, [turn(0, 0, 1)]);
    let command = ArmCommand::Jog(JogMotion::Orientation {
        rx: 0,
        ry: 0,
        rz: 1,
    });
    app.handle(Input::Arm(ArmEvent::Done { command }), t0 + ms(20));
    let text = status_text(&app, 120);
    // 50 % of 30 deg/s.
    assert!(
        text.contains("JOG turning +Rz 15.0 deg/s (tool frame)"),
        "{text}"
    );
    app.handle(Input::Arm(ArmEvent::Speed(10)), t0 + ms(30));
    let text = status_text(&app, 120);
    assert!(
        text.contains("turning +Rz 3.0 deg/s (tool frame)"),
        "{text}"
    );
    // The motion never gives way: at 80 and 50 columns the turn still shows whole.
    for width in [80, 50] {
        let text = status_text(&app, width);
        assert!(
            text.contains("turning +Rz 3.0 deg/s (tool frame)"),
            "{width}: {text}"
        );
    }
}

#[test]
fn no_built_in_keymap_moves_the_arm_on_a_dialogs_yes_or_no() {
    use armjog::console::keymap::{KeyName, Keymap};
    for name in ["default", "numpad"] {
        let keymap = Keymap::builtin(name).expect("keymap");
        for answer in ["y", "n", "Y", "N"] {
            let key: KeyName = answer.parse().expect("key name");
            let action = keymap.action(&key);
            assert!(
                action.is_none_or(|a| a.jog().is_none()),
                "{name}: {answer} is {action:?}"
            );
        }
    }
}
