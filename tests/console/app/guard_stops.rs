//! The stop guard's stop names what it stopped: a go-to (`go to 'bench' stopped: the stop guard
//! stopped the arm: ...`), home, a stored action, a jog; it is one line, never "jog failed" for
//! what was not a jog, and the arm's abort that follows is not said again as a failure. Fake
//! clock.

use std::time::Duration;

use armjog::console::app::{Effect, Input, MotionShown, QUESTION_QUIET};
use armjog::kortex::{ActionState, ActionStatus, Coded};
use armjog::link::interface::{ArmCommand, ArmError, ArmEvent, CommandKind};

use crate::app::tours::{Bench, leg};
use crate::app_support::{STOP, ms, no_motion};

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

/// The console frozen (SIGSTOP) for 3 s while `key` (then yes) or the tour ran; the guard
/// stopped the arm meanwhile. On resume the first input handled is `first` (what the run loop
/// takes first is a race: its overdue timer, finding the link stale, or the arm's telemetry,
/// the arm at rest and the move aborted, or the guard's report itself), then the guard's
/// report; the line names what ran.
fn resumed_after_a_freeze(b: &mut Bench, first: &str) {
    b.at(Duration::from_secs(3));
    let now = b.at(ms(1));
    let input = match first {
        "tick" | "guard" => Input::Tick,
        _ => {
            let action = ActionState {
                status: Coded::Known(ActionStatus::Aborted),
                id: 0,
                move_type: Coded::Known(b.move_type),
            };
            let mut t =
                crate::app_support::arm_telemetry(crate::app_support::HOME_JOINTS, 0.0, action);
            t.tcp.pose = b.tool;
            Input::Arm(ArmEvent::Telemetry(Box::new(t)))
        }
    };
    if first != "guard" {
        let effects = b.app.handle(input, now);
        assert!(no_motion(&effects), "{effects:?}");
    }
    let effects = guard_stopped(b);
    assert!(no_motion(&effects), "{effects:?}");
}

#[test]
fn a_guard_stop_of_a_frozen_console_names_the_tour_and_the_leg_whatever_came_first() {
    for (talos, first) in [false, true]
        .into_iter()
        .flat_map(|talos| ["tick", "telemetry", "guard"].map(|first| (talos, first)))
    {
        let mut b = Bench::new(talos);
        let first_leg = leg(&b.play("O"));
        b.leg_started(first_leg);
        assert_eq!(b.tour_label().as_deref(), Some("TOUR 1/3 → bench"));
        resumed_after_a_freeze(&mut b, first);
        assert_eq!(b.tour_label(), None, "{first}");
        assert_eq!(
            b.message(),
            format!("tour 'rounds' leg 1/3 → bench stopped: {REASON}"),
            "talos {talos}, {first} first"
        );
    }
}

#[test]
fn a_guard_stop_of_a_frozen_console_names_the_go_to_or_home_whatever_came_first() {
    for (key, what) in [("o", "go to 'bench'"), ("h", "home")] {
        for first in ["tick", "telemetry", "guard"] {
            let mut b = Bench::new(false);
            start(&mut b, key);
            resumed_after_a_freeze(&mut b, first);
            assert_eq!(
                b.message(),
                format!("{what} stopped: {REASON}"),
                "{key} {first}"
            );
        }
    }
}

#[test]
fn a_guard_stop_long_after_a_freeze_with_nothing_running_names_nothing() {
    let mut b = Bench::new(false);
    start(&mut b, "o");
    b.at(Duration::from_secs(3));
    let now = b.at(ms(1));
    b.app.handle(Input::Tick, now);
    // The go-to ended there; a guard stop well after is not its.
    b.at(Duration::from_secs(2));
    guard_stopped(&mut b);
    assert_eq!(b.message(), REASON);
}
