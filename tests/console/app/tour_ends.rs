//! What ends a tour, on a fake clock: any key mid-leg, a failed leg, a stale or lost link, a
//! guard stop; each stops the arm and names the leg, and nothing resumes after (a reconnect,
//! the arm heard again, its report at rest).

use armjog::console::app::{Input, STALE_AFTER};
use armjog::kortex::ActionStatus;
use armjog::link::interface::{ArmCommand, ArmEvent, LinkStatus};

use super::tours::{Bench, leg};
use crate::app_support::{STOP, no_motion};

#[test]
fn any_key_mid_leg_stops_the_arm_and_ends_the_tour_naming_the_leg() {
    for key in ["v", "space", "w"] {
        let mut b = Bench::new(false);
        let first = leg(&b.play("O"));
        let second = leg(&b.finish_leg(first));
        b.leg_started(second);
        let effects = b.press(key);
        assert_eq!(effects, [STOP], "{key}");
        assert_eq!(b.tour_label(), None, "{key}");
        assert_eq!(
            b.message(),
            "tour 'rounds' leg 2/3 → pick: stopped by a key; play it again to go on",
            "{key}"
        );
        // The arm stops at rest: no third leg.
        assert!(no_motion(&b.feed(0.0, ActionStatus::Completed)), "{key}");
        assert!(no_motion(&b.feed(0.0, ActionStatus::Completed)), "{key}");
    }
}

#[test]
fn a_failed_leg_ends_the_tour_with_its_reason_and_the_leg() {
    let mut b = Bench::new(false);
    let first = leg(&b.play("O"));
    b.leg_started(first);
    let effects = b.feed(0.0, ActionStatus::Aborted);
    assert!(effects.contains(&STOP), "{effects:?}");
    assert!(no_motion(&effects), "{effects:?}");
    assert_eq!(b.tour_label(), None);
    let said = b.message();
    assert!(
        said.starts_with("tour 'rounds' leg 1/3 → bench ended the tour: go to 'bench' failed"),
        "{said}"
    );
}

#[test]
fn a_stale_link_mid_tour_stops_it_and_nothing_resumes_when_the_arm_is_heard_again() {
    let mut b = Bench::new(false);
    let first = leg(&b.play("O"));
    b.leg_started(first);
    // Three of its (slow, here) poll intervals, at least STALE_AFTER.
    let now = b.at(STALE_AFTER * 4);
    let effects = b.app.handle(Input::Tick, now);
    assert_eq!(effects, [STOP]);
    assert_eq!(b.tour_label(), None);
    assert!(b.message().contains("leg 1/3 → bench"), "{}", b.message());
    assert!(no_motion(&b.feed(0.0, ActionStatus::Completed)));
    assert!(no_motion(&b.feed(0.0, ActionStatus::Completed)));
}

#[test]
fn a_link_lost_mid_leg_ends_the_tour_and_a_reconnect_resumes_nothing() {
    let mut b = Bench::new(true);
    let first = leg(&b.play("O"));
    assert_eq!(
        first,
        ArmCommand::GoToPosition {
            name: "bench".into()
        },
        "over Talos a leg is a Go To"
    );
    b.leg_started(first);
    b.event(ArmEvent::Status(LinkStatus::Down {
        reason: "reset".into(),
    }));
    assert_eq!(b.tour_label(), None);
    let back = b.event(ArmEvent::Status(LinkStatus::Up {
        description: "test".into(),
    }));
    assert!(no_motion(&back), "{back:?}");
    assert!(no_motion(&b.feed(0.0, ActionStatus::Completed)));
    assert!(no_motion(&b.feed(0.0, ActionStatus::Completed)));
}

#[test]
fn a_guard_stop_mid_leg_ends_the_tour_naming_the_leg_and_the_tour() {
    let mut b = Bench::new(false);
    let first = leg(&b.play("O"));
    let second = leg(&b.finish_leg(first));
    b.leg_started(second);
    // The guard reports its stop as a failed jog, though no jog is held.
    let effects = b.event(ArmEvent::Failed {
        command: armjog::link::interface::CommandKind::Jog,
        error: armjog::link::interface::ArmError::GuardStoppedArm("no heartbeat for 500 ms".into()),
    });
    assert!(effects.contains(&STOP), "{effects:?}");
    assert!(no_motion(&effects), "{effects:?}");
    assert_eq!(b.tour_label(), None);
    assert_eq!(
        b.message(),
        "tour 'rounds' leg 2/3 → pick stopped: the stop guard stopped the arm: no heartbeat \
         for 500 ms"
    );
    // The arm reports the leg aborted and then at rest: the tour's words stay, nothing moves.
    assert!(no_motion(&b.feed(0.0, ActionStatus::Aborted)));
    assert!(no_motion(&b.feed(0.0, ActionStatus::Aborted)));
    assert!(
        b.message()
            .starts_with("tour 'rounds' leg 2/3 → pick stopped"),
        "{}",
        b.message()
    );
}
