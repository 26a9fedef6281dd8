//! Jog keys in the console's state machine on a fake clock: nothing starts by itself after any
//! stop, in the auto-repeat fallback a tap is a bounded step and a hold a jog, and release events
//! must keep proving a hold. Both key-release modes.

use std::time::{Duration, Instant};

use armjog::console::app::{App, Effect, Input, Overlay};
use armjog::console::jog::{KeyKind, ReleaseMode};
use armjog::link::interface::{ArmCommand, ArmEvent, LinkStatus};

use crate::app_support;

use app_support::*;

// ---- Nothing starts by itself: a key down before a stop moves only after a new press ----

fn moves(effects: &[Effect]) -> bool {
    effects.iter().any(|e| {
        matches!(
            e,
            Effect::Arm(ArmCommand::Jog(_) | ArmCommand::Step(_) | ArmCommand::Home)
        )
    })
}

/// What the terminal sends while `w` stays down: repeat events, or presses in the fallback.
fn auto_repeat_kind(mode: ReleaseMode) -> KeyKind {
    match mode {
        ReleaseMode::Reported => KeyKind::Repeat,
        ReleaseMode::AutoRepeat => KeyKind::Press,
    }
}

/// A hold of `w` that jogs; returns the time of its last event.
fn start_hold(app: &mut App, mode: ReleaseMode, t0: Instant) -> Instant {
    let times: &[u64] = match mode {
        ReleaseMode::Reported => &[0],
        ReleaseMode::AutoRepeat => &[0, 500, 530, 560, 590],
    };
    for t in times {
        app.handle(key("w", KeyKind::Press), t0 + ms(*t));
    }
    assert!(app.jog().is_jogging(), "{mode:?}: w jogs");
    t0 + ms(*times.last().unwrap_or(&0))
}

/// `w` stays down for `span` from `from`: its auto-repeat every 30 ms, with ticks.
fn keep_holding(app: &mut App, mode: ReleaseMode, from: Instant, span: Duration) -> Vec<Effect> {
    let mut effects = Vec::new();
    let mut now = from;
    while now <= from + span {
        effects.extend(app.handle(key("w", auto_repeat_kind(mode)), now));
        effects.extend(app.handle(Input::Tick, now + ms(15)));
        now += ms(30);
    }
    effects
}

/// `w` goes up (a release event, or its repeats pause) and is pressed anew: it moves.
fn fresh_press_moves(app: &mut App, mode: ReleaseMode, at: Instant) {
    let mut effects = match mode {
        ReleaseMode::Reported => release(app, "w", at),
        ReleaseMode::AutoRepeat => app.handle(Input::Tick, at + ms(1000)),
    };
    let pressed = at + ms(1100);
    effects.extend(press(app, "w", pressed));
    effects.extend(app.handle(Input::Tick, pressed + ms(125)));
    assert!(moves(&effects), "{mode:?}: a new press moves: {effects:?}");
}

type Step = fn(&mut App, Instant) -> Vec<Effect>;

/// Interruptions of a hold: what stops it, then what allows motion again.
fn interruptions() -> Vec<(&'static str, Step, Step)> {
    vec![
        (
            "reconnect",
            |app, t| {
                let reason = "connection reset".into();
                app.handle(Input::Arm(ArmEvent::Status(LinkStatus::Down { reason })), t)
            },
            |app, t| {
                let description = "back".into();
                app.handle(
                    Input::Arm(ArmEvent::Status(LinkStatus::Up { description })),
                    t,
                )
            },
        ),
        (
            "focus",
            |app, t| app.handle(Input::FocusLost, t),
            |app, t| app.handle(Input::FocusGained, t),
        ),
        (
            "resize",
            |app, t| {
                let (width, height) = (30, 8);
                app.handle(Input::Resize { width, height }, t)
            },
            |app, t| {
                let (width, height) = (100, 30);
                app.handle(Input::Resize { width, height }, t)
            },
        ),
        (
            "help overlay",
            |app, t| press(app, "?", t),
            |app, t| {
                let effects = press(app, "esc", t);
                assert_eq!(*app.overlay(), Overlay::None);
                effects
            },
        ),
        (
            "fault reset",
            |app, t| press(app, "c", t),
            |app, t| app.handle(Input::Tick, t),
        ),
        (
            "other key",
            |app, t| press(app, "+", t),
            |app, t| app.handle(Input::Tick, t),
        ),
        (
            "stop",
            |app, t| press(app, "space", t),
            |app, t| app.handle(Input::Tick, t),
        ),
        (
            "step mode",
            |app, t| press(app, "t", t),
            |app, t| press(app, "t", t),
        ),
    ]
}

#[test]
fn a_key_held_through_any_stop_does_not_move_again_until_pressed_anew() {
    for mode in [ReleaseMode::Reported, ReleaseMode::AutoRepeat] {
        for (name, stop, resume) in interruptions() {
            let (mut app, t0) = app(mode, true);
            let last = start_hold(&mut app, mode, t0);
            let t = last + ms(20);
            let effects = stop(&mut app, t);
            assert!(
                effects.contains(&STOP),
                "{mode:?} {name}: stops: {effects:?}"
            );
            let during = keep_holding(&mut app, mode, t + ms(10), ms(300));
            let allowed = resume(&mut app, t + ms(320));
            let after = keep_holding(&mut app, mode, t + ms(330), ms(3000));
            // In step mode the fallback's repeats are presses, each a step (unchanged).
            if name != "step mode" {
                assert!(
                    !moves(&during),
                    "{mode:?} {name}: while stopped: {during:?}"
                );
            }
            assert!(!moves(&allowed), "{mode:?} {name}: resuming: {allowed:?}");
            assert!(!moves(&after), "{mode:?} {name}: held on: {after:?}");
            assert!(!app.jog().is_jogging());
            fresh_press_moves(&mut app, mode, t + ms(3400));
        }
    }
}

#[test]
fn a_stop_before_the_repeat_onset_still_holds_the_key_back() {
    // Stopped right after the press: the onset and repeats that follow are the same hold.
    for mode in [ReleaseMode::Reported, ReleaseMode::AutoRepeat] {
        for (name, stop, resume) in interruptions() {
            let (mut app, t0) = app(mode, true);
            press(&mut app, "w", t0);
            let effects = stop(&mut app, t0 + ms(20));
            assert!(
                effects.contains(&STOP),
                "{mode:?} {name}: stops: {effects:?}"
            );
            let allowed = resume(&mut app, t0 + ms(100));
            let after = keep_holding(&mut app, mode, t0 + ms(500), ms(3000));
            assert!(!moves(&allowed), "{mode:?} {name}: resuming: {allowed:?}");
            if name != "step mode" {
                assert!(!moves(&after), "{mode:?} {name}: held on: {after:?}");
            }
            fresh_press_moves(&mut app, mode, t0 + ms(3600));
        }
    }
}

#[test]
fn a_key_pressed_while_the_link_is_down_does_not_move_when_it_comes_back() {
    for mode in [ReleaseMode::Reported, ReleaseMode::AutoRepeat] {
        let (mut app, t0) = app(mode, true);
        let reason = "gone".into();
        app.handle(
            Input::Arm(ArmEvent::Status(LinkStatus::Down { reason })),
            t0,
        );
        assert!(press(&mut app, "w", t0 + ms(10)).is_empty());
        let mut effects = keep_holding(&mut app, mode, t0 + ms(510), ms(200));
        let description = "back".into();
        let up = Input::Arm(ArmEvent::Status(LinkStatus::Up { description }));
        effects.extend(app.handle(up, t0 + ms(720)));
        effects.extend(keep_holding(&mut app, mode, t0 + ms(730), ms(2000)));
        assert!(!moves(&effects), "{mode:?}: {effects:?}");
        fresh_press_moves(&mut app, mode, t0 + ms(2800));
    }
}

#[test]
fn holding_the_key_that_closes_an_overlay_never_jogs_in_either_mode() {
    for mode in [ReleaseMode::Reported, ReleaseMode::AutoRepeat] {
        let (mut app, t0) = app(mode, true);
        press(&mut app, "?", t0);
        let mut effects = press(&mut app, "w", t0 + ms(100));
        assert_eq!(*app.overlay(), Overlay::None, "w closed the help");
        effects.extend(keep_holding(&mut app, mode, t0 + ms(600), ms(3000)));
        assert!(!moves(&effects), "{mode:?}: {effects:?}");
        fresh_press_moves(&mut app, mode, t0 + ms(3700));
    }
}

// ---- The auto-repeat fallback: a tap is a step, a hold is a jog ----

#[test]
fn fallback_a_tap_is_a_step_of_the_step_size_at_most_5_mm() {
    use armjog::console::app::TAP_STEP_LIMIT;
    assert_eq!(TAP_STEP_LIMIT, 50, "5 mm in tenths");
    let (mut app, t0) = app(ReleaseMode::AutoRepeat, true);
    assert!(press(&mut app, "w", t0).is_empty());
    assert_eq!(
        app.next_deadline(),
        Some(t0 + ms(125)),
        "the runtime wakes for it"
    );
    assert_eq!(app.handle(Input::Tick, t0 + ms(125)), [step(50, 0, 0)]);
    // A bigger step size is bounded; a smaller one is kept.
    press(&mut app, ".", t0 + ms(1000));
    press(&mut app, "d", t0 + ms(2000));
    assert_eq!(app.handle(Input::Tick, t0 + ms(2125)), [step(0, -50, 0)]);
    for (i, _) in [0, 1].iter().enumerate() {
        press(&mut app, ",", t0 + ms(3000 + i as u64));
    }
    press(&mut app, "r", t0 + ms(4000));
    assert_eq!(app.handle(Input::Tick, t0 + ms(4125)), [step(0, 0, 10)]);
    let mut later = Vec::new();
    for t in (4130..6000).step_by(10) {
        later.extend(app.handle(Input::Tick, t0 + ms(t)));
    }
    assert!(later.is_empty(), "one step per tap: {later:?}");
}

#[test]
fn fallback_rapid_taps_step_each_time_and_never_jog() {
    let (mut app, t0) = app(ReleaseMode::AutoRepeat, true);
    let mut effects = Vec::new();
    for i in 0..10u64 {
        let at = t0 + ms(200 * i);
        effects.extend(press(&mut app, "w", at));
        effects.extend(app.handle(Input::Tick, at + ms(125)));
    }
    effects.extend(app.handle(Input::Tick, t0 + ms(3000)));
    let jogs = effects
        .iter()
        .filter(|e| matches!(e, Effect::Arm(ArmCommand::Jog(_))))
        .count();
    let steps = effects.iter().filter(|e| **e == step(50, 0, 0)).count();
    assert_eq!((jogs, steps), (0, 10), "{effects:?}");
}

#[test]
fn fallback_an_arrow_tap_moves_nothing_and_says_a_hold_is_needed() {
    let (mut app, t0) = app(ReleaseMode::AutoRepeat, true);
    let mut effects = press(&mut app, "right", t0);
    let deadline = app.next_deadline().expect("a deadline for the tap");
    effects.extend(app.handle(Input::Tick, deadline));
    assert!(!moves(&effects), "{effects:?}");
    let message = app
        .message()
        .map(|(text, _)| text.to_string())
        .unwrap_or_default();
    assert!(message.contains("only while held"), "{message}");
}

// ---- Release events need evidence ----

#[test]
fn with_release_events_a_hold_with_no_key_event_for_a_second_stops_and_says_so() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    press(&mut app, "w", t0);
    let mut stopped_at = None;
    let mut now = t0;
    while stopped_at.is_none() && now < t0 + ms(3000) {
        now = app.next_deadline().expect("a deadline while jogging");
        if app.handle(Input::Tick, now).contains(&STOP) {
            stopped_at = Some(now);
        }
    }
    assert_eq!(stopped_at, Some(t0 + ms(1000)));
    let message = app
        .message()
        .map(|(text, _)| text.to_string())
        .unwrap_or_default();
    assert!(message.contains("no key event for 1 s"), "{message}");
    assert!(message.contains("report key releases"), "{message}");
}

#[test]
fn with_release_events_a_second_press_without_release_switches_to_the_fallback() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    press(&mut app, "w", t0);
    // The terminal claimed the protocol, but its auto-repeat arrives as presses.
    assert_eq!(press(&mut app, "w", t0 + ms(500)), [STOP]);
    assert_eq!(app.jog().mode(), ReleaseMode::AutoRepeat);
    let message = app
        .message()
        .map(|(text, _)| text.to_string())
        .unwrap_or_default();
    assert!(message.contains("auto-repeat fallback"), "{message}");
    let status =
        armjog::console::ui::status::release_mode_text(&armjog::console::view::View::new(&app));
    assert!(
        status.contains("auto-repeat fallback"),
        "the status bar follows: {status}"
    );
    let effects = keep_holding(&mut app, ReleaseMode::AutoRepeat, t0 + ms(530), ms(3000));
    assert!(!moves(&effects), "no runaway: {effects:?}");
    fresh_press_moves(&mut app, ReleaseMode::AutoRepeat, t0 + ms(3600));
}

#[test]
fn fallback_step_mode_steps_once_per_press_not_once_per_auto_repeat() {
    let (mut app, t0) = app(ReleaseMode::AutoRepeat, true);
    press(&mut app, "t", t0);
    let steps = |effects: &[Effect]| {
        effects
            .iter()
            .filter(|e| matches!(e, Effect::Arm(ArmCommand::Step(_))))
            .count()
    };
    let mut total = steps(&press(&mut app, "w", t0 + ms(500)));
    assert_eq!(total, 1, "the press steps");
    // Held: the auto-repeat arrives as presses, after the onset and then every 33 ms.
    let mut at = t0 + ms(1000);
    while at < t0 + ms(2500) {
        total += steps(&press(&mut app, "w", at));
        total += steps(&app.handle(Input::Tick, at + ms(1)));
        at += ms(33);
    }
    assert_eq!(total, 1, "a held key steps once");
    // Let go (the repeats pause), then press again: one more step.
    app.handle(Input::Tick, at + ms(600));
    assert_eq!(steps(&press(&mut app, "w", at + ms(700))), 1);
}
