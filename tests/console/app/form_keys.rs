//! Keystrokes into forms on a fake clock, with reported key events and in the auto-repeat
//! fallback: every keystroke is text; only the auto-repeat of a key already repeating when it
//! opened the form is not.

use std::time::Instant;

use armjog::console::app::{App, Effect, Input, Overlay};
use armjog::console::jog::{KeyKind, ReleaseMode};
use armjog::link::interface::ArmCommand;

use crate::app_support;

use app_support::*;

const MODES: [ReleaseMode; 2] = [ReleaseMode::Reported, ReleaseMode::AutoRepeat];

/// The focused field's text of the open form.
fn typed(app: &App) -> String {
    match app.overlay() {
        Overlay::Form(form) => form.fields[form.focus].value.clone(),
        other => panic!("no form open: {other:?}"),
    }
}

fn save(name: &str) -> Effect {
    Effect::Arm(ArmCommand::SavePosition {
        name: name.into(),
        anchor: false,
        parent: None,
    })
}

/// `p` held while the screen is too small to act on it (its auto-repeat arrives every 33 ms
/// from 500 ms), then the screen grows and the next repeat opens the form. Returns the time
/// of that repeat.
fn form_opened_by_a_repeating_p(app: &mut App, t0: Instant) -> Instant {
    app.handle(
        Input::Resize {
            width: 30,
            height: 8,
        },
        t0,
    );
    for t in [0, 500, 533, 566] {
        press(app, "p", t0 + ms(t));
    }
    app.handle(
        Input::Resize {
            width: 80,
            height: 24,
        },
        t0 + ms(580),
    );
    let opened = t0 + ms(599);
    press(app, "p", opened);
    assert!(
        matches!(app.overlay(), Overlay::Form(_)),
        "p opened the form"
    );
    opened
}

#[test]
fn p_then_pick_typed_at_once_saves_pick_in_both_modes() {
    for mode in MODES {
        // All at one instant, and at a fast typist's 30 ms per key (faster than any repeat
        // onset, as fast as a repeat).
        for gap in [0, 30] {
            let (mut app, t0) = app(mode, true);
            press(&mut app, "p", t0);
            for (i, c) in ["p", "i", "c", "k"].into_iter().enumerate() {
                press(&mut app, c, t0 + ms(gap * (i as u64 + 1)));
            }
            assert_eq!(typed(&app), "pick", "{mode:?}, {gap} ms apart");
            let effects = press(&mut app, "enter", t0 + ms(200));
            assert_eq!(effects, [save("pick")], "{mode:?}, {gap} ms apart");
        }
    }
}

#[test]
fn a_p_held_before_the_form_opened_is_ignored_until_it_pauses() {
    let (mut app, t0) = app(ReleaseMode::AutoRepeat, true);
    let opened = form_opened_by_a_repeating_p(&mut app, t0);
    // Its run goes on: no interval measured yet, so 1.5 x the default 91 ms continue it.
    for t in [33, 66, 99, 132] {
        press(&mut app, "p", opened + ms(t));
    }
    assert_eq!(typed(&app), "", "the held p's repeats are not text");
    // Released; typed again after a pause longer than 1.5 intervals: text.
    press(&mut app, "p", opened + ms(132 + 140));
    assert_eq!(typed(&app), "p");
    // From now on every p is text, however fast.
    press(&mut app, "p", opened + ms(132 + 150));
    assert_eq!(typed(&app), "pp");
}

#[test]
fn the_run_window_follows_the_measured_repeat_interval() {
    let (mut app, t0) = app(ReleaseMode::AutoRepeat, true);
    // A hold of w measures this keyboard's repeat: 40 ms.
    for t in [0, 500, 540, 580, 620, 660, 700] {
        press(&mut app, "w", t0 + ms(t));
    }
    press(&mut app, "space", t0 + ms(710));
    let interval = app.jog().timing().interval.expect("interval measured");
    assert!(interval.abs_diff(ms(40)) <= ms(2), "{interval:?}");
    let t1 = t0 + ms(2000);
    let opened = form_opened_by_a_repeating_p(&mut app, t1);
    // 33 ms continues the run; 70 ms (more than 1.5 x 40) does not, though it would with the
    // default interval.
    press(&mut app, "p", opened + ms(33));
    assert_eq!(typed(&app), "");
    press(&mut app, "p", opened + ms(33 + 70));
    assert_eq!(
        typed(&app),
        "p",
        "a pause of 1.5 measured intervals ends the run"
    );
}

#[test]
fn a_different_key_right_after_opening_is_text_and_ends_the_run() {
    let (mut app, t0) = app(ReleaseMode::AutoRepeat, true);
    let opened = form_opened_by_a_repeating_p(&mut app, t0);
    press(&mut app, "i", opened + ms(5));
    assert_eq!(typed(&app), "i", "a fresh key 5 ms after opening");
    press(&mut app, "p", opened + ms(15));
    assert_eq!(
        typed(&app),
        "ip",
        "after another key, p is a keystroke again"
    );
}

#[test]
fn with_reported_events_the_opening_keys_repeats_are_ignored_until_it_is_pressed_again() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    press(&mut app, "p", t0);
    for t in [500, 533, 566] {
        app.handle(key("p", KeyKind::Repeat), t0 + ms(t));
    }
    assert_eq!(typed(&app), "", "the held p's repeats are not text");
    release(&mut app, "p", t0 + ms(580));
    press(&mut app, "p", t0 + ms(600));
    app.handle(key("p", KeyKind::Repeat), t0 + ms(1100));
    assert_eq!(typed(&app), "pp", "a new press and its own repeat are text");
}

#[test]
fn holding_backspace_deletes_repeatedly_in_both_modes() {
    for mode in MODES {
        let (mut app, t0) = app(mode, true);
        press(&mut app, "p", t0);
        for (i, c) in "position".chars().enumerate() {
            press(&mut app, &c.to_string(), t0 + ms(10 * i as u64 + 10));
        }
        let hold = t0 + ms(1000);
        press(&mut app, "backspace", hold);
        let repeat = match mode {
            ReleaseMode::Reported => KeyKind::Repeat,
            ReleaseMode::AutoRepeat => KeyKind::Press,
        };
        for t in [500, 533, 566, 599] {
            app.handle(key("backspace", repeat), hold + ms(t));
        }
        assert_eq!(typed(&app), "pos", "{mode:?}: five deletes");
    }
}

#[test]
fn a_form_keeps_no_motion_for_after_it_closes() {
    // The jog keys typed as text stay latched: closing the form starts nothing.
    for mode in MODES {
        let (mut app, t0) = app(mode, true);
        press(&mut app, "p", t0);
        let mut effects = Vec::new();
        for (i, c) in ["w", "a", "r", "d"].into_iter().enumerate() {
            effects.extend(press(&mut app, c, t0 + ms(20 * i as u64 + 20)));
        }
        effects.extend(press(&mut app, "esc", t0 + ms(100)));
        for t in [150, 300, 600, 900] {
            effects.extend(app.handle(Input::Tick, t0 + ms(t)));
        }
        assert!(
            !effects
                .iter()
                .any(|e| matches!(e, Effect::Arm(ArmCommand::Jog(_) | ArmCommand::Step(_)))),
            "{mode:?}: {effects:?}"
        );
        assert_eq!(*app.overlay(), Overlay::None);
    }
}

#[test]
fn the_key_that_closed_an_earlier_overlay_is_a_keystroke_in_a_form() {
    // Fallback: enter closes the help, and its auto-repeat is kept from acting for a while.
    // In a form opened meanwhile, enter pressed again is a keystroke: it submits.
    let (mut app, t0) = app(ReleaseMode::AutoRepeat, true);
    press(&mut app, "?", t0);
    press(&mut app, "enter", t0 + ms(100));
    assert_eq!(*app.overlay(), Overlay::None, "enter closed the help");
    press(&mut app, "p", t0 + ms(200));
    press(&mut app, "a", t0 + ms(250));
    assert_eq!(press(&mut app, "enter", t0 + ms(300)), [save("a")]);
}
