//! The stop guard's stop names what it stopped: a go-to (`go to 'bench' stopped: the stop guard
//! stopped the arm: ...`), home, a stored action, a jog; it is one line, never "jog failed" for
//! what was not a jog, and the arm's abort that follows is not said again as a failure. Fake
//! clock.

use armjog::console::app::{Effect, MotionShown, QUESTION_QUIET};
use armjog::kortex::ActionStatus;
use armjog::link::interface::{ArmCommand, ArmError, ArmEvent, CommandKind};

use crate::app::tours::Bench;
use crate::app_support::{STOP, no_motion};

const REASON: &str = "the stop guard stopped the arm: no heartbeat for 500 ms";

/// The guard's report, as the driver passes it on: a failed jog, whatever ran.
fn guard_stopped(b: &mut Bench) -> Vec<Effect> {
    b.event(ArmEvent::Failed {
        command: CommandKind::Jog,
        error: ArmError::GuardStoppedArm("no heartbeat for 500 ms".into()),
    })
}

/// `key`, then yes to its question: the command sent, which the link then reports taken, and
/// the arm seen moving.
fn start(b: &mut Bench, key: &str) -> ArmCommand {
    b.press(key);
    b.at(QUESTION_QUIET);
    let effects = b.press("y");
    let started: Vec<&ArmCommand> = effects
        .iter()
        .filter_map(|e| match e {
            Effect::Arm(c) if c.starts_motion() => Some(c),
            _ => None,
        })
        .collect();
    let [command] = started.as_slice() else {
        panic!("one motion expected: {effects:?}");
    };
    let command = (*command).clone();
    b.event(ArmEvent::Done {
        command: command.clone(),
    });
    b.feed(12.0, ActionStatus::Started);
    command
}

/// The guard stops what `key` started: the line says `<what> stopped: <the guard's words>`,
/// a STOP goes out, nothing moves, and the arm's abort and rest that follow say nothing more.
fn stopped_by_the_guard(b: &mut Bench, key: &str, what: &str) {
    start(b, key);
    assert!(matches!(b.app.motion_shown(), MotionShown::Action { .. }));
    let effects = guard_stopped(b);
    assert!(effects.contains(&STOP), "{effects:?}");
    assert!(no_motion(&effects), "{effects:?}");
    assert_eq!(b.message(), format!("{what} stopped: {REASON}"));
    assert!(!matches!(b.app.motion_shown(), MotionShown::Action { .. }));
    for velocity in [0.0, 0.0] {
        assert!(no_motion(&b.feed(velocity, ActionStatus::Aborted)));
        assert_eq!(b.message(), format!("{what} stopped: {REASON}"));
    }
}

#[test]
fn a_guard_stop_of_a_single_go_to_names_the_go_to_in_one_line() {
    let mut b = Bench::new(false);
    assert_eq!(b.app.selected_name(), Some("bench"));
    stopped_by_the_guard(&mut b, "o", "go to 'bench'");
}

#[test]
fn a_guard_stop_of_home_names_home() {
    stopped_by_the_guard(&mut Bench::new(false), "h", "home");
}

#[test]
fn a_guard_stop_of_a_stored_action_names_the_action() {
    let mut b = Bench::new(false);
    b.press("A");
    // The kind is prefilled `action`; the id, then enter asks the question `start` answers.
    b.press("5");
    stopped_by_the_guard(&mut b, "enter", "action 5");
}

#[test]
fn a_guard_stop_of_a_jog_says_the_jog_stopped_not_failed() {
    let mut b = Bench::new(false);
    let effects = b.press("w");
    assert!(!no_motion(&effects), "{effects:?}");
    let effects = guard_stopped(&mut b);
    assert_eq!(effects, [STOP]);
    assert_eq!(b.message(), format!("jog stopped: {REASON}"));
}

#[test]
fn a_guard_stop_with_nothing_running_says_the_guard_stopped_the_arm() {
    let mut b = Bench::new(false);
    guard_stopped(&mut b);
    assert_eq!(b.message(), REASON);
}

#[test]
fn a_guard_stop_that_failed_is_never_said_as_a_stop_and_our_stop_goes_out() {
    let mut b = Bench::new(false);
    start(&mut b, "o");
    let effects = b.event(ArmEvent::Failed {
        command: CommandKind::Jog,
        error: ArmError::GuardStopFailed("the operator did not answer".into()),
    });
    assert!(effects.contains(&STOP), "{effects:?}");
    assert!(no_motion(&effects), "{effects:?}");
    assert_eq!(
        b.message(),
        "go to 'bench': the stop guard could NOT stop the arm, it may still be moving: the \
         operator did not answer; STOP sent"
    );
    assert!(!b.message().contains("stopped"), "{}", b.message());
}
