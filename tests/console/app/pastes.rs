//! Pastes and bursts in the state machine, on a fake clock: a paste is text, never keys; a
//! question is answered only by a key a person typed.

use std::time::Instant;

use armjog::console::app::{App, BURST_KEY_GAP, Effect, Input, Overlay, Pasted, QUESTION_QUIET};
use armjog::console::form::Confirm;
use armjog::console::jog::{KeyKind, ReleaseMode};
use armjog::link::interface::ArmCommand;
use armjog::talos::name::MAX_NAME_LEN;

use crate::app_support::*;

fn paste(app: &mut App, text: &str, now: Instant) -> Vec<Effect> {
    app.handle(Input::Paste(Pasted::Text(text.into())), now)
}

fn moves(effects: &[Effect]) -> bool {
    effects
        .iter()
        .any(|e| matches!(e, Effect::Arm(command) if *command != ArmCommand::Stop))
}

#[test]
fn a_pasted_why_goes_nowhere_and_says_so_once() {
    for mode in [ReleaseMode::Reported, ReleaseMode::AutoRepeat] {
        let (mut app, t0) = app(mode, true);
        assert!(paste(&mut app, "why", t0).is_empty());
        assert_eq!(app.overlay(), &Overlay::None, "no question opened");
        assert_eq!(message(&app), "paste ignored: pasted text is never keys");
        // Even a paste that holds every key of the keymap.
        let everything: String = ('!'..='~').chain([' ', '\r']).collect();
        assert!(paste(&mut app, &everything, t0 + ms(500)).is_empty());
        assert_eq!(app.overlay(), &Overlay::None);
    }
}

#[test]
fn without_bracketed_paste_a_typed_burst_why_never_goes_home() {
    let (mut app, t0) = app(ReleaseMode::AutoRepeat, true);
    // What a terminal without bracketed paste sends for a pasted "why": three keys at once.
    let mut effects = Vec::new();
    for (i, c) in ["w", "h", "y"].into_iter().enumerate() {
        effects.extend(press(
            &mut app,
            c,
            t0 + ms(0) + BURST_KEY_GAP / 10 * i as u32,
        ));
    }
    assert!(
        !effects.contains(&Effect::Arm(ArmCommand::Home)),
        "{effects:?}"
    );
    assert_eq!(
        app.overlay(),
        &Overlay::Confirm(Confirm::Home),
        "still asking"
    );
    assert_eq!(
        message(&app),
        "key ignored: the question has only just opened"
    );
}

#[test]
fn a_question_ignores_keys_for_150_ms_and_keys_of_a_burst_after_that() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    press(&mut app, "h", t0);
    assert!(press(&mut app, "y", t0 + ms(100)).is_empty());
    assert!(press(&mut app, "enter", t0 + QUESTION_QUIET - ms(1)).is_empty());
    assert_eq!(app.overlay(), &Overlay::Confirm(Confirm::Home));
    // Past the quiet time, a key within a few ms of the one before is a burst, not typing.
    let burst = t0 + QUESTION_QUIET + ms(1);
    assert!(press(&mut app, "y", burst).is_empty());
    assert_eq!(app.overlay(), &Overlay::Confirm(Confirm::Home));
    assert_eq!(message(&app), "key ignored: keys came too fast to be typed");
    for i in 1..10 {
        assert!(press(&mut app, "y", burst + BURST_KEY_GAP / 2 * i).is_empty());
    }
    // Releases are not keys of a burst.
    let later = t0 + ms(400);
    release(&mut app, "y", later);
    assert_eq!(
        press(&mut app, "y", later + ms(1)),
        [Effect::Arm(ArmCommand::Home)],
        "a typed answer still answers"
    );
}

#[test]
fn an_answer_typed_after_150_ms_works_and_no_still_cancels() {
    let (mut app, t0) = app(ReleaseMode::AutoRepeat, true);
    press(&mut app, "h", t0);
    assert_eq!(
        press(&mut app, "y", t0 + QUESTION_QUIET),
        [Effect::Arm(ArmCommand::Home)]
    );
    let t1 = t0 + ms(2000);
    press(&mut app, "h", t1);
    assert!(press(&mut app, "n", t1 + ms(300)).is_empty());
    assert_eq!(app.overlay(), &Overlay::None, "cancelled");
    // A second question is timed from its own opening.
    let t2 = t1 + ms(1000);
    press(&mut app, "h", t2);
    assert!(press(&mut app, "y", t2 + ms(100)).is_empty());
    assert_eq!(
        press(&mut app, "y", t2 + ms(200)),
        [Effect::Arm(ArmCommand::Home)]
    );
}

#[test]
fn a_paste_into_the_save_form_is_inserted_without_control_characters_and_cut() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    press(&mut app, "p", t0);
    assert!(paste(&mut app, "pick\r\n", t0 + ms(300)).is_empty());
    let Overlay::Form(form) = app.overlay() else {
        panic!("no form: {:?}", app.overlay())
    };
    assert_eq!(form.fields[0].value, "pick");
    assert_eq!(message(&app), "", "nothing to say about a paste that fits");
    // A paste over the name limit is cut there, with a message; nothing is sent.
    let long = "x".repeat(MAX_NAME_LEN);
    assert!(paste(&mut app, &long, t0 + ms(600)).is_empty());
    let Overlay::Form(form) = app.overlay() else {
        panic!("no form: {:?}", app.overlay())
    };
    let value = form.fields[0].value.clone();
    assert_eq!(value, format!("pick{}", "x".repeat(MAX_NAME_LEN - 4)));
    assert_eq!(
        message(&app),
        format!("pasted text cut to the field's {MAX_NAME_LEN}-byte limit")
    );
    // Enter after it saves what is in the field.
    let effects = press(&mut app, "enter", t0 + ms(900));
    let error = match app.overlay() {
        Overlay::Form(form) => form.error.clone(),
        _ => None,
    };
    assert!(
        matches!(effects.as_slice(), [Effect::Arm(ArmCommand::SavePosition { name, .. })] if *name == value),
        "{effects:?} {error:?}"
    );
}

#[test]
fn input_the_reader_refused_stops_a_jog_and_says_why() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    assert_eq!(press(&mut app, "w", t0), [jog(1, 0, 0)]);
    let refused = "keys ignored: over 4096 bytes came faster than anyone types";
    let effects = app.handle(Input::Paste(Pasted::Refused(refused.into())), t0 + ms(10));
    assert!(effects.contains(&STOP), "{effects:?}");
    assert!(!moves(&effects));
    assert_eq!(message(&app), format!("{refused}; stopped"));
    // The held key is latched: its repeats do not restart the jog.
    let repeat = app.handle(key("w", KeyKind::Repeat), t0 + ms(50));
    assert!(!moves(&repeat), "{repeat:?}");
}
