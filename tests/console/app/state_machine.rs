//! The console's state machine on a fake clock: jogging, every stop path, overlays, forms and
//! named positions. No terminal, no sockets.

use armjog::console::app::QUESTION_QUIET;
use std::time::{Duration, Instant};

use armjog::console::app::{App, Effect, Input, Overlay};
use armjog::console::jog::{JogMotion, KeyKind, ReleaseMode};
use armjog::console::positions::PositionBook;
use armjog::link::interface::{
    ArmCommand, ArmError, ArmEvent, CommandKind, LinkStatus, PositionCoordinates, StepMove,
};

use crate::app_support;

use app_support::*;

#[test]
fn holding_w_jogs_plus_x_and_releasing_stops() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    assert_eq!(press(&mut app, "w", t0), [jog(1, 0, 0)]);
    assert_eq!(
        app.handle(Input::Tick, t0 + ms(100)),
        [jog(1, 0, 0)],
        "10 Hz refresh"
    );
    assert_eq!(release(&mut app, "w", t0 + ms(150)), [STOP]);
}

#[test]
fn w_and_a_together_jog_diagonally() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    press(&mut app, "w", t0);
    assert_eq!(press(&mut app, "a", t0 + ms(20)), [jog(1, 1, 0)]);
    assert_eq!(release(&mut app, "w", t0 + ms(40)), [jog(0, 1, 0)]);
}

#[test]
fn arrows_pan_with_right_and_up_positive() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    let polar =
        |azimuth, altitude| Effect::Arm(ArmCommand::Jog(JogMotion::Polar { azimuth, altitude }));
    assert_eq!(press(&mut app, "right", t0), [polar(1, 0)]);
    assert_eq!(press(&mut app, "up", t0), [polar(1, 1)]);
}

#[test]
fn a_release_with_shift_added_still_releases_the_key() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    press(&mut app, "w", t0);
    assert_eq!(release(&mut app, "W", t0 + ms(30)), [STOP]);
}

#[test]
fn any_other_key_stops_the_motion() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    press(&mut app, "w", t0);
    let effects = press(&mut app, "h", t0 + ms(10));
    assert_eq!(effects, [STOP]);
    assert!(
        matches!(app.overlay(), Overlay::Confirm(_)),
        "home asks first"
    );
    press(&mut app, "n", t0 + ms(10) + QUESTION_QUIET);
    press(&mut app, "d", t0 + ms(200));
    assert_eq!(
        press(&mut app, "F", t0 + ms(210)),
        [STOP],
        "an unbound key stops too"
    );
}

#[test]
fn space_always_sends_stop() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    assert_eq!(
        press(&mut app, "space", t0),
        [STOP],
        "even when idle: stops discrete moves"
    );
    press(&mut app, "r", t0);
    assert_eq!(press(&mut app, "space", t0 + ms(5)), [STOP]);
    assert!(app.jog().active().is_none());
}

#[test]
fn focus_loss_stops() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    press(&mut app, "s", t0);
    assert_eq!(app.handle(Input::FocusLost, t0 + ms(5)), [STOP]);
}

#[test]
fn a_terminal_too_small_for_the_status_stops() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    press(&mut app, "s", t0);
    assert_eq!(
        app.handle(
            Input::Resize {
                width: 30,
                height: 8
            },
            t0 + ms(5)
        ),
        [STOP]
    );
    assert!(
        press(&mut app, "s", t0 + ms(10)).is_empty(),
        "no jog while too small"
    );
}

#[test]
fn link_loss_stops_and_nothing_restarts_after_reconnect() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    press(&mut app, "w", t0);
    let down = Input::Arm(ArmEvent::Status(LinkStatus::Down {
        reason: "gone".into(),
    }));
    assert_eq!(app.handle(down, t0 + ms(10)), [STOP]);
    let up = Input::Arm(ArmEvent::Status(LinkStatus::Up {
        description: "back".into(),
    }));
    // Back up: only a STOP (motion was unaccounted for), never a start.
    assert_eq!(app.handle(up, t0 + ms(20)), [STOP]);
    assert!(
        app.handle(key("w", KeyKind::Repeat), t0 + ms(30))
            .is_empty(),
        "a repeat is no press"
    );
    assert!(app.handle(Input::Tick, t0 + ms(200)).is_empty());
    release(&mut app, "w", t0 + ms(250));
    assert!(
        press(&mut app, "w", t0 + ms(300)).contains(&jog(1, 0, 0)),
        "a new press moves"
    );
}

#[test]
fn no_jog_while_the_link_is_down() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    let down = Input::Arm(ArmEvent::Status(LinkStatus::Down {
        reason: "gone".into(),
    }));
    app.handle(down, t0);
    assert!(press(&mut app, "w", t0 + ms(1)).is_empty());
}

#[test]
fn a_failed_jog_stops_and_forgets_the_held_keys() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    press(&mut app, "w", t0);
    let failed = Input::Arm(ArmEvent::Failed {
        command: CommandKind::Jog,
        error: ArmError::Talos(
            armjog::link::TalosError::Timeout {
                command: armjog::talos::CommandValue::CartesianMoveStart,
                id: 7,
                after: Duration::from_millis(500),
            }
            .into(),
        ),
    });
    assert_eq!(app.handle(failed, t0 + ms(10)), [STOP]);
    assert!(app.handle(Input::Tick, t0 + ms(200)).is_empty());
}

#[test]
fn the_guard_stopping_the_arm_stops_the_jog_as_a_failed_jog_does() {
    let (mut app, t0) = app(ReleaseMode::Reported, false);
    press(&mut app, "w", t0);
    let stopped = Input::Arm(ArmEvent::Failed {
        command: CommandKind::Jog,
        error: ArmError::GuardStoppedArm("no heartbeat for 500 ms".into()),
    });
    assert_eq!(app.handle(stopped, t0 + ms(10)), [STOP]);
    assert!(
        app.handle(Input::Tick, t0 + ms(200)).is_empty(),
        "held keys latched"
    );
    let said = app.message().map(|m| m.0);
    assert_eq!(
        said,
        Some("jog stopped: the stop guard stopped the arm: no heartbeat for 500 ms")
    );
}

#[test]
fn a_failure_of_another_command_leaves_the_held_jog_alone() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    press(&mut app, "w", t0);
    let failed = Input::Arm(ArmEvent::Failed {
        command: CommandKind::SetSpeed,
        error: ArmError::SpeedOutOfRange {
            requested: 0,
            in_force: 40,
        },
    });
    assert!(app.handle(failed, t0 + ms(10)).is_empty());
    assert_eq!(
        app.handle(Input::Tick, t0 + ms(100)),
        [jog(1, 0, 0)],
        "still refreshed"
    );
    let said = app.message().map(|m| m.0);
    assert_eq!(
        said,
        Some("set speed failed: speed 0 % is outside 1-100: 40 % stays in force")
    );
}

#[test]
fn quit_signal_and_ctrl_c_stop_then_quit() {
    for input in [
        key("q", KeyKind::Press),
        key("ctrl+c", KeyKind::Press),
        Input::Signal("SIGTERM"),
    ] {
        let (mut app, t0) = app(ReleaseMode::Reported, true);
        press(&mut app, "w", t0);
        let effects = app.handle(input, t0 + ms(5));
        assert_eq!(effects.first(), Some(&STOP));
        assert_eq!(effects.last(), Some(&Effect::Quit));
        assert!(app.quitting());
    }
}

#[test]
fn fallback_mode_stops_when_the_repeats_stop() {
    let (mut app, t0) = app(ReleaseMode::AutoRepeat, true);
    press(&mut app, "a", t0);
    let mut t = 500;
    while t <= 800 {
        press(&mut app, "a", t0 + ms(t));
        t += 40;
    }
    let last = t - 40;
    let deadline = app.next_deadline().expect("a deadline while held");
    assert!(deadline <= t0 + ms(last + 3 * 40));
    let mut stopped = false;
    let mut now = t0 + ms(last);
    while now <= t0 + ms(last + 3 * 40) {
        stopped |= app.handle(Input::Tick, now).contains(&STOP);
        now += ms(5);
    }
    assert!(
        stopped,
        "stopped within 3 repeat intervals of the last repeat"
    );
}

#[test]
fn overlays_take_keys_and_never_jog() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    press(&mut app, "?", t0);
    assert_eq!(*app.overlay(), Overlay::Help);
    assert!(
        press(&mut app, "w", t0 + ms(5)).is_empty(),
        "w closes help, does not jog"
    );
    assert_eq!(*app.overlay(), Overlay::None);
}

#[test]
fn home_asks_for_confirmation() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    press(&mut app, "h", t0);
    assert_eq!(
        press(&mut app, "y", t0 + QUESTION_QUIET),
        [Effect::Arm(ArmCommand::Home)]
    );
    press(&mut app, "h", t0);
    assert!(
        press(&mut app, "esc", t0).is_empty(),
        "anything but yes cancels"
    );
}

#[test]
fn step_mode_sends_one_discrete_move_per_press() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    press(&mut app, "t", t0);
    let effects = press(&mut app, "d", t0 + ms(5));
    assert_eq!(
        effects,
        [Effect::Arm(ArmCommand::Step(StepMove::Cartesian {
            dx: 0,
            dy: -50,
            dz: 0
        }))]
    );
    assert!(
        app.handle(key("d", KeyKind::Repeat), t0 + ms(600))
            .is_empty()
    );
    press(&mut app, ".", t0);
    let effects = press(&mut app, "right", t0 + ms(700));
    assert_eq!(
        effects,
        [Effect::Arm(ArmCommand::Step(StepMove::Polar {
            azimuth: 10,
            altitude: 0
        }))]
    );
}

#[test]
fn speed_keys_walk_the_speed_steps() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    app.handle(Input::Arm(ArmEvent::Speed(50)), t0);
    assert_eq!(
        press(&mut app, "+", t0),
        [Effect::Arm(ArmCommand::SetSpeed(75))]
    );
    assert_eq!(
        press(&mut app, "-", t0),
        [Effect::Arm(ArmCommand::SetSpeed(25))]
    );
    // The speed changes only once the arm says so: from 10 % the steps are fine.
    app.handle(Input::Arm(ArmEvent::Speed(10)), t0);
    assert_eq!(
        press(&mut app, "-", t0),
        [Effect::Arm(ArmCommand::SetSpeed(5))]
    );
    // A speed between steps (another client set it) goes to the next step each way.
    app.handle(Input::Arm(ArmEvent::Speed(33)), t0);
    assert_eq!(
        press(&mut app, "+", t0),
        [Effect::Arm(ArmCommand::SetSpeed(50))]
    );
    assert_eq!(
        press(&mut app, "-", t0),
        [Effect::Arm(ArmCommand::SetSpeed(25))]
    );
}

fn type_text(app: &mut App, text: &str, now: Instant) {
    for c in text.chars() {
        let name = if c == ' ' {
            "space".to_string()
        } else {
            c.to_string()
        };
        app.handle(key(&name, KeyKind::Press), now);
    }
}

#[test]
fn saving_a_position_on_the_operator_goes_through_a_form() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    press(&mut app, "p", t0);
    assert!(matches!(app.overlay(), Overlay::Form(_)));
    type_text(&mut app, "pick", t0);
    let effects = press(&mut app, "enter", t0);
    let save = ArmCommand::SavePosition {
        name: "pick".into(),
        anchor: false,
        parent: None,
    };
    assert_eq!(effects, [Effect::Arm(save.clone())]);
    let effects = app.handle(Input::Arm(ArmEvent::Done { command: save }), t0);
    assert!(
        matches!(effects.as_slice(), [Effect::SavePositions(book)] if book.get("pick").is_some())
    );
    assert_eq!(app.selected_name(), Some("pick"));
}

#[test]
fn an_invalid_name_keeps_the_form_open_and_sends_nothing() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    press(&mut app, "p", t0);
    assert!(press(&mut app, "enter", t0).is_empty());
    let Overlay::Form(form) = &app.overlay() else {
        panic!("form closed")
    };
    assert!(form.error.as_deref().unwrap_or("").contains("empty"));
}

#[test]
fn go_to_and_delete_ask_first_and_unknown_names_are_marked() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    let mut book = PositionBook::new();
    book.get_or_insert("bench");
    app.handle(Input::PositionsLoaded(Ok(book)), t0);
    press(&mut app, "o", t0);
    assert_eq!(
        press(&mut app, "y", t0 + QUESTION_QUIET),
        [Effect::Arm(ArmCommand::GoToPosition {
            name: "bench".into()
        })]
    );
    app.handle(
        Input::Arm(ArmEvent::UnknownPosition {
            name: "bench".into(),
        }),
        t0,
    );
    assert!(
        app.positions()
            .get("bench")
            .is_some_and(|e| e.unknown_to_operator)
    );
    press(&mut app, "delete", t0);
    assert_eq!(
        press(&mut app, "y", t0 + QUESTION_QUIET),
        [Effect::Arm(ArmCommand::DeletePosition {
            name: "bench".into()
        })]
    );
}

#[test]
fn over_modbus_the_console_keeps_positions_and_go_to_moves_to_the_stored_pose() {
    let (mut app, t0) = app(ReleaseMode::Reported, false);
    press(&mut app, "C", t0);
    type_text(&mut app, "spot", t0);
    for (field, value) in [(1, "400"), (2, "-100"), (3, "300")] {
        press(&mut app, "tab", t0);
        let _ = field;
        type_text(&mut app, value, t0);
    }
    let effects = press(&mut app, "enter", t0);
    assert!(matches!(effects.as_slice(), [Effect::SavePositions(_)]));
    assert_eq!(
        app.positions().get("spot").and_then(|e| e.cartesian),
        Some([4000, -1000, 3000])
    );
    // With no telemetry there is no orientation to keep: go-to refuses rather than guess.
    press(&mut app, "o", t0);
    assert!(press(&mut app, "y", t0).is_empty());
}

#[test]
fn remembered_names_are_checked_with_the_operator_when_the_link_comes_up() {
    let config = app_support::config();
    let mut book = PositionBook::new();
    book.get_or_insert("ghost");
    let mut app = App::new(config, book);
    let t0 = Instant::now();
    let up = Input::Arm(ArmEvent::Status(LinkStatus::Up {
        description: "t".into(),
    }));
    assert_eq!(
        app.handle(up.clone(), t0),
        [Effect::Arm(ArmCommand::GetPosition {
            name: "ghost".into()
        })]
    );
    assert!(app.handle(up, t0).is_empty(), "only when the link comes up");
    app.handle(
        Input::Arm(ArmEvent::UnknownPosition {
            name: "ghost".into(),
        }),
        t0,
    );
    assert!(
        app.positions()
            .get("ghost")
            .is_some_and(|e| e.unknown_to_operator)
    );
    assert!(app.message().is_none(), "marked in the panel, not shouted");
}

#[test]
fn an_answer_about_a_name_not_in_the_book_adds_nothing_and_leaves_the_selection() {
    let config = app_support::config();
    let mut book = PositionBook::new();
    book.get_or_insert("bench");
    book.get_or_insert("table");
    let mut app = App::new(config, book);
    let t0 = Instant::now();
    press(&mut app, "pagedown", t0);
    assert_eq!(app.selected_name(), Some("table"));
    // Replies about a name deleted meanwhile; "apple" would sort before the selection.
    app.handle(
        Input::Arm(ArmEvent::Position {
            name: "apple".into(),
            coordinates: PositionCoordinates {
                cartesian: Some([1, 2, 3]),
                polar: None,
            },
        }),
        t0,
    );
    app.handle(
        Input::Arm(ArmEvent::UnknownPosition {
            name: "apple".into(),
        }),
        t0,
    );
    let names: Vec<&str> = app.positions().names().collect();
    assert_eq!(names, ["bench", "table"], "nothing added");
    assert_eq!(app.selected_name(), Some("table"), "the selection stays");
    // A name in the book is still updated.
    app.handle(
        Input::Arm(ArmEvent::Position {
            name: "bench".into(),
            coordinates: PositionCoordinates {
                cartesian: Some([4, 5, 6]),
                polar: None,
            },
        }),
        t0,
    );
    assert_eq!(
        app.positions().get("bench").and_then(|e| e.cartesian),
        Some([4, 5, 6])
    );
    assert_eq!(app.selected_name(), Some("table"));
}

#[test]
fn holding_the_key_that_closed_an_overlay_does_not_start_a_jog() {
    let (mut app, t0) = app(ReleaseMode::AutoRepeat, true);
    press(&mut app, "?", t0);
    assert!(
        press(&mut app, "w", t0 + ms(100)).is_empty(),
        "w closes help"
    );
    // Its auto-repeat arrives as presses in the fallback mode.
    for t in [600, 633, 666, 700] {
        assert!(
            press(&mut app, "w", t0 + ms(t)).is_empty(),
            "repeat at {t} ms"
        );
    }
    // Released, then pressed again after a pause: that moves (a tap is a step).
    assert!(press(&mut app, "w", t0 + ms(1600)).is_empty());
    assert_eq!(app.handle(Input::Tick, t0 + ms(1725)), [step(50, 0, 0)]);
}

#[test]
fn holding_the_key_that_opened_a_question_does_not_answer_it() {
    let (mut app, t0) = app(ReleaseMode::AutoRepeat, true);
    press(&mut app, "h", t0);
    for t in [500, 533, 566] {
        press(&mut app, "h", t0 + ms(t));
    }
    assert!(matches!(app.overlay(), Overlay::Confirm(_)), "still asking");
    assert_eq!(
        press(&mut app, "y", t0 + ms(900)),
        [Effect::Arm(ArmCommand::Home)]
    );
}

#[test]
fn with_reported_events_a_repeat_never_answers_an_overlay() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    press(&mut app, "h", t0);
    assert!(
        app.handle(key("h", KeyKind::Repeat), t0 + ms(500))
            .is_empty()
    );
    assert!(matches!(app.overlay(), Overlay::Confirm(_)));
}

#[test]
fn telemetry_polls_share_one_counted_log_line() {
    use armjog::link::interface::LogEntry;
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    let poll = |id| LogEntry {
        id: Some(id),
        name: "hw_op".into(),
        outcome: "OK".into(),
        ok: true,
        poll: true,
        count: 1,
        ..LogEntry::default()
    };
    for id in [2, 4, 6] {
        app.handle(Input::Arm(ArmEvent::Log(poll(id))), t0);
    }
    let command = LogEntry {
        id: Some(8),
        name: "cart_start".into(),
        outcome: "OK".into(),
        ok: true,
        count: 1,
        ..LogEntry::default()
    };
    app.handle(Input::Arm(ArmEvent::Log(command)), t0);
    app.handle(Input::Arm(ArmEvent::Log(poll(10))), t0);
    let lines: Vec<(Option<u32>, u32)> = app.log().iter().map(|e| (e.id, e.count)).collect();
    assert_eq!(lines, [(Some(6), 3), (Some(8), 1), (Some(10), 1)]);
}
