//! The hold-to-jog engine on a fake clock: press / repeat / release sequences, combined axes,
//! the auto-repeat fallback timing and the 10 Hz refresh.

use std::time::{Duration, Instant};

use armjog::console::action::Action;
use armjog::console::jog::{JogEffect, JogEngine, JogMotion, KeyKind, MAX_ONSET, ReleaseMode};

const REFRESH: Duration = Duration::from_millis(100);

fn ms(n: u64) -> Duration {
    Duration::from_millis(n)
}

fn cart(x: i8, y: i8, z: i8) -> JogEffect {
    JogEffect::Start(JogMotion::Cartesian { x, y, z })
}

fn reported() -> (JogEngine, Instant) {
    (
        JogEngine::new(ReleaseMode::Reported, REFRESH),
        Instant::now(),
    )
}

fn fallback() -> (JogEngine, Instant) {
    (
        JogEngine::new(ReleaseMode::AutoRepeat, REFRESH),
        Instant::now(),
    )
}

#[test]
fn press_starts_and_release_stops() {
    let (mut jog, t0) = reported();
    assert_eq!(
        jog.key(Action::JogXPlus, KeyKind::Press, t0),
        [cart(1, 0, 0)]
    );
    assert_eq!(
        jog.key(Action::JogXPlus, KeyKind::Release, t0 + ms(30)),
        [JogEffect::Stop]
    );
    assert!(!jog.is_jogging());
}

#[test]
fn held_keys_combine_into_one_direction_and_a_change_updates_at_once() {
    let (mut jog, t0) = reported();
    jog.key(Action::JogXPlus, KeyKind::Press, t0);
    assert_eq!(
        jog.key(Action::JogYMinus, KeyKind::Press, t0 + ms(10)),
        [cart(1, -1, 0)]
    );
    assert_eq!(
        jog.key(Action::JogZPlus, KeyKind::Press, t0 + ms(20)),
        [cart(1, -1, 1)]
    );
    assert_eq!(
        jog.key(Action::JogXPlus, KeyKind::Release, t0 + ms(30)),
        [cart(0, -1, 1)]
    );
    assert_eq!(
        jog.key(Action::JogYMinus, KeyKind::Release, t0 + ms(40)),
        [cart(0, 0, 1)]
    );
    assert_eq!(
        jog.key(Action::JogZPlus, KeyKind::Release, t0 + ms(50)),
        [JogEffect::Stop]
    );
}

#[test]
fn opposite_keys_cancel_to_a_stop() {
    let (mut jog, t0) = reported();
    jog.key(Action::JogXPlus, KeyKind::Press, t0);
    assert_eq!(
        jog.key(Action::JogXMinus, KeyKind::Press, t0 + ms(5)),
        [JogEffect::Stop]
    );
    assert_eq!(
        jog.key(Action::JogXPlus, KeyKind::Release, t0 + ms(9)),
        [cart(-1, 0, 0)]
    );
}

#[test]
fn polar_keys_make_a_polar_motion_and_switching_family_stops_first() {
    let (mut jog, t0) = reported();
    jog.key(Action::JogXPlus, KeyKind::Press, t0);
    let effects = jog.key(Action::PanAzimuthPlus, KeyKind::Press, t0 + ms(10));
    assert_eq!(
        effects,
        [
            JogEffect::Stop,
            JogEffect::Start(JogMotion::Polar {
                azimuth: 1,
                altitude: 0
            })
        ]
    );
    let effects = jog.key(Action::PanAltitudeMinus, KeyKind::Press, t0 + ms(20));
    assert_eq!(
        effects,
        [JogEffect::Start(JogMotion::Polar {
            azimuth: 1,
            altitude: -1
        })]
    );
}

#[test]
fn start_is_re_sent_every_refresh_period_while_held() {
    let (mut jog, t0) = reported();
    jog.key(Action::JogZMinus, KeyKind::Press, t0);
    assert_eq!(jog.next_deadline(), Some(t0 + REFRESH));
    assert!(jog.tick(t0 + ms(60)).is_empty());
    assert_eq!(jog.tick(t0 + ms(100)), [cart(0, 0, -1)]);
    assert!(jog.tick(t0 + ms(150)).is_empty());
    assert_eq!(jog.tick(t0 + ms(200)), [cart(0, 0, -1)]);
    assert_eq!(jog.next_deadline(), Some(t0 + ms(300)));
    jog.key(Action::JogZMinus, KeyKind::Release, t0 + ms(250));
    assert_eq!(jog.next_deadline(), None);
    assert!(
        jog.tick(t0 + ms(300)).is_empty(),
        "nothing after the release"
    );
}

#[test]
fn duplicated_releases_are_harmless() {
    let (mut jog, t0) = reported();
    jog.key(Action::JogXPlus, KeyKind::Press, t0);
    assert_eq!(
        jog.key(Action::JogXPlus, KeyKind::Release, t0 + ms(10)),
        [JogEffect::Stop]
    );
    assert!(
        jog.key(Action::JogXPlus, KeyKind::Release, t0 + ms(11))
            .is_empty()
    );
}

#[test]
fn a_repeat_without_a_press_never_starts_motion() {
    let (mut jog, t0) = reported();
    assert!(jog.key(Action::JogXPlus, KeyKind::Repeat, t0).is_empty());
    assert!(!jog.is_jogging());
}

#[test]
fn nothing_ever_starts_by_itself() {
    let (mut jog, t0) = fallback();
    for i in 0..50 {
        assert!(jog.tick(t0 + ms(i * 37)).is_empty());
    }
    assert_eq!(jog.next_deadline(), None);
}

#[test]
fn fallback_holds_while_repeats_arrive_and_stops_three_intervals_after_the_last() {
    let (mut jog, t0) = fallback();
    // GNOME-like keyboard: 500 ms onset, then a repeat every 30 ms until the key goes up at
    // 1010 ms (last repeat at 980 ms).
    assert_eq!(
        jog.key(Action::JogYPlus, KeyKind::Press, t0),
        [cart(0, 1, 0)]
    );
    let mut t = ms(500);
    while t <= ms(980) {
        assert!(jog.key(Action::JogYPlus, KeyKind::Press, t0 + t).is_empty());
        assert!(
            jog.tick(t0 + t).iter().all(|e| *e != JogEffect::Stop),
            "at {t:?}"
        );
        t += ms(30);
    }
    let timing = jog.timing();
    assert_eq!(timing.onset, Some(ms(500)));
    assert_eq!(timing.interval, Some(ms(30)));
    // Refreshes went out at 500, 620, ..., 980 ms; the release deadline (980 + 3 × 30 ms)
    // comes before the next one.
    assert_eq!(jog.next_deadline(), Some(t0 + ms(980 + 90)));
    assert!(jog.tick(t0 + ms(1069)).is_empty());
    assert_eq!(jog.tick(t0 + ms(1070)), [JogEffect::Stop]);
}

#[test]
fn fallback_single_tap_stops_no_later_than_the_slowest_onset() {
    let (mut jog, t0) = fallback();
    jog.key(Action::JogXMinus, KeyKind::Press, t0);
    for t in (100..700).step_by(100) {
        assert_eq!(jog.tick(t0 + ms(t)), [cart(-1, 0, 0)], "refresh at {t} ms");
    }
    assert_eq!(jog.tick(t0 + MAX_ONSET), [JogEffect::Stop]);
}

#[test]
fn once_the_onset_is_measured_a_tap_stops_sooner() {
    let (mut jog, t0) = fallback();
    // Learn a 250 ms onset (Linux console) from one hold.
    jog.key(Action::JogXPlus, KeyKind::Press, t0);
    jog.key(Action::JogXPlus, KeyKind::Press, t0 + ms(250));
    jog.tick(t0 + ms(2000));
    assert!(!jog.is_jogging());
    // A tap: released after 250 × 1.25 + 40 = 352 ms (well before 700 ms).
    let t1 = t0 + ms(3000);
    jog.key(Action::JogXPlus, KeyKind::Press, t1);
    assert!(!jog.tick(t1 + ms(351)).contains(&JogEffect::Stop));
    assert_eq!(jog.tick(t1 + ms(353)), [JogEffect::Stop]);
}

#[test]
fn implausible_gaps_are_not_taken_as_repeat_timing() {
    let (mut jog, t0) = fallback();
    jog.key(Action::JogXPlus, KeyKind::Press, t0);
    jog.key(Action::JogXPlus, KeyKind::Press, t0 + ms(5)); // 5 ms: a bounce, not an onset
    assert_eq!(jog.timing().onset, None);
}

#[test]
fn reported_mode_guards_against_a_lost_release() {
    let (mut jog, t0) = reported();
    jog.key(Action::JogXPlus, KeyKind::Press, t0);
    jog.key(Action::JogXPlus, KeyKind::Repeat, t0 + ms(500));
    jog.key(Action::JogXPlus, KeyKind::Repeat, t0 + ms(530));
    // Repeats seen at 30 ms; none for max(6 × 30 ms, 500 ms) = 500 ms: released.
    assert_eq!(jog.tick(t0 + ms(1029)).len(), 1, "just a refresh");
    assert_eq!(jog.tick(t0 + ms(1030)), [JogEffect::Stop]);
}

#[test]
fn reported_mode_without_repeats_holds_until_release() {
    let (mut jog, t0) = reported();
    jog.key(Action::JogXPlus, KeyKind::Press, t0);
    assert_eq!(jog.tick(t0 + ms(5000)), [cart(1, 0, 0)]);
    assert!(jog.is_jogging());
}

#[test]
fn stop_all_stops_a_jog_and_is_quiet_when_idle() {
    let (mut jog, t0) = reported();
    assert!(jog.stop_all(t0).is_empty());
    jog.key(Action::PanAzimuthMinus, KeyKind::Press, t0);
    assert_eq!(jog.stop_all(t0 + ms(1)), [JogEffect::Stop]);
    assert!(!jog.is_jogging());
    assert_eq!(jog.next_deadline(), None);
    // The key is still physically down: its next repeat does not restart motion.
    assert!(
        jog.key(Action::PanAzimuthMinus, KeyKind::Repeat, t0 + ms(40))
            .is_empty()
    );
}

#[test]
fn joint_jog_drives_the_selected_joint_and_reselecting_stops_it() {
    let (mut jog, t0) = reported();
    assert!(jog.select_joint(3, t0).is_empty());
    let effects = jog.key(Action::JointMinus, KeyKind::Press, t0);
    assert_eq!(
        effects,
        [JogEffect::Start(JogMotion::Joint {
            joint: 3,
            direction: -1
        })]
    );
    assert_eq!(jog.select_joint(4, t0 + ms(10)), [JogEffect::Stop]);
    assert_eq!(jog.joint(), 4);
}
