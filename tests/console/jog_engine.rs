//! The hold-to-jog engine on a fake clock: press / repeat / release sequences, combined axes,
//! the auto-repeat fallback timing and the 10 Hz refresh.

use std::time::{Duration, Instant};

use armjog::console::action::Action;
use armjog::console::jog::{
    JogEffect, JogEngine, JogMotion, JogNotice, KEY_EVENT_TIMEOUT, KeyKind, MAX_ONSET,
    REPEAT_GAP_MAX, ReleaseMode,
};

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
fn a_repeat_without_a_press_never_starts_motion_in_either_mode() {
    for (mut jog, t0) in [reported(), fallback()] {
        // Repeats of a key that went down before the console looked (focus came back).
        let effects = repeats(&mut jog, t0, ms(2000), KeyKind::Repeat);
        assert!(effects.is_empty(), "{:?}: {effects:?}", jog.mode());
        assert!(!jog.is_jogging());
    }
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
    assert!(
        jog.key(Action::JogYPlus, KeyKind::Press, t0).is_empty(),
        "a press alone does not start continuous motion"
    );
    assert_eq!(
        jog.tick(t0 + ms(125)),
        [JogEffect::Step(JogMotion::Cartesian { x: 0, y: 1, z: 0 })],
        "no repeat within 125 ms: the press steps"
    );
    assert!(
        jog.key(Action::JogYPlus, KeyKind::Press, t0 + ms(500))
            .is_empty()
    );
    assert!(
        jog.key(Action::JogYPlus, KeyKind::Press, t0 + ms(530))
            .is_empty()
    );
    assert_eq!(
        jog.key(Action::JogYPlus, KeyKind::Press, t0 + ms(560)),
        [cart(0, 1, 0)],
        "two regular repeats after the onset confirm the hold"
    );
    let mut t = ms(590);
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
    // Released 3 × 30 ms after the last repeat.
    assert!(jog.next_deadline() <= Some(t0 + ms(980 + 90)));
    assert!(!jog.tick(t0 + ms(1069)).contains(&JogEffect::Stop));
    assert_eq!(jog.tick(t0 + ms(1070)), [JogEffect::Stop]);
}

/// Every effect from `tick` every 5 ms from `from` to `to`.
fn ticks(jog: &mut JogEngine, from: Instant, to: Instant) -> Vec<JogEffect> {
    let mut effects = Vec::new();
    let mut now = from;
    while now <= to {
        effects.extend(jog.tick(now));
        now += ms(5);
    }
    effects
}

fn starts(effects: &[JogEffect]) -> usize {
    effects
        .iter()
        .filter(|e| matches!(e, JogEffect::Start(_)))
        .count()
}

fn steps(effects: &[JogEffect]) -> usize {
    effects
        .iter()
        .filter(|e| matches!(e, JogEffect::Step(_)))
        .count()
}

#[test]
fn fallback_a_tap_is_one_step_and_never_continuous_motion() {
    let (mut jog, t0) = fallback();
    assert!(jog.key(Action::JogXMinus, KeyKind::Press, t0).is_empty());
    assert_eq!(jog.next_deadline(), Some(t0 + REPEAT_GAP_MAX));
    assert!(jog.tick(t0 + ms(124)).is_empty());
    assert_eq!(
        jog.tick(t0 + ms(125)),
        [JogEffect::Step(JogMotion::Cartesian { x: -1, y: 0, z: 0 })]
    );
    assert!(ticks(&mut jog, t0 + ms(130), t0 + MAX_ONSET + ms(500)).is_empty());
    assert!(!jog.is_jogging());
    assert_eq!(jog.next_deadline(), None);
}

/// Taps of `w` every `period` for `taps` taps; all effects, ticks included.
fn tap(jog: &mut JogEngine, start: Instant, period: Duration, taps: u32) -> Vec<JogEffect> {
    let mut effects = Vec::new();
    for i in 0..taps {
        let at = start + period * i;
        effects.extend(ticks(jog, at - period + ms(5), at - ms(1)));
        effects.extend(jog.key(Action::JogXPlus, KeyKind::Press, at));
    }
    let end = start + period * taps;
    effects.extend(ticks(jog, end - period + ms(5), end + ms(1000)));
    effects
}

#[test]
fn rapid_deliberate_taps_are_steps_never_a_jog() {
    for period in [150, 200, 250, 300, 400] {
        let (mut jog, t0) = fallback();
        let effects = tap(&mut jog, t0 + ms(1000), ms(period), 12);
        assert_eq!(starts(&effects), 0, "taps every {period} ms: {effects:?}");
        assert_eq!(steps(&effects), 12, "one step per tap every {period} ms");
        assert_eq!(jog.timing().interval, None, "taps are no repeat timing");
    }
}

#[test]
fn rapid_taps_stay_steps_once_the_keyboard_is_measured() {
    let (mut jog, t0) = fallback();
    // One hold teaches a 500 ms onset and 30 ms interval.
    for t in [0, 500, 530, 560, 590] {
        jog.key(Action::JogXPlus, KeyKind::Press, t0 + ms(t));
    }
    assert!(jog.is_jogging());
    jog.tick(t0 + ms(2000));
    assert!(!jog.is_jogging());
    for period in [150, 250, 400, 500] {
        let start = t0 + ms(10_000 * period);
        let effects = tap(&mut jog, start, ms(period), 10);
        assert_eq!(starts(&effects), 0, "taps every {period} ms: {effects:?}");
        assert_eq!(steps(&effects), 10, "one step per tap every {period} ms");
    }
}

#[test]
fn once_measured_a_hold_is_confirmed_by_its_first_two_repeats() {
    let (mut jog, t0) = fallback();
    for t in [0, 500, 530, 560, 590] {
        jog.key(Action::JogXPlus, KeyKind::Press, t0 + ms(t));
    }
    jog.tick(t0 + ms(2000));
    let t1 = t0 + ms(3000);
    jog.key(Action::JogXPlus, KeyKind::Press, t1);
    assert_eq!(steps(&jog.tick(t1 + ms(125))), 1);
    assert!(
        jog.key(Action::JogXPlus, KeyKind::Press, t1 + ms(505))
            .is_empty()
    );
    assert_eq!(
        jog.key(Action::JogXPlus, KeyKind::Press, t1 + ms(537)),
        [cart(1, 0, 0)]
    );
}

#[test]
fn a_double_tap_is_no_hold() {
    let (mut jog, t0) = fallback();
    let mut effects = jog.key(Action::JogXPlus, KeyKind::Press, t0);
    effects.extend(ticks(&mut jog, t0, t0 + ms(395)));
    effects.extend(jog.key(Action::JogXPlus, KeyKind::Press, t0 + ms(400)));
    effects.extend(jog.key(Action::JogXPlus, KeyKind::Press, t0 + ms(480)));
    effects.extend(ticks(&mut jog, t0 + ms(485), t0 + ms(2000)));
    assert_eq!(starts(&effects), 0, "{effects:?}");
}

#[test]
fn fallback_arrow_and_joint_taps_move_nothing_but_a_hold_does() {
    for (action, motion) in [
        (
            Action::PanAzimuthPlus,
            JogMotion::Polar {
                azimuth: 1,
                altitude: 0,
            },
        ),
        (
            Action::JointMinus,
            JogMotion::Joint {
                joint: 1,
                direction: -1,
            },
        ),
    ] {
        let (mut jog, t0) = fallback();
        jog.key(action, KeyKind::Press, t0);
        let effects = ticks(&mut jog, t0, t0 + ms(1500));
        assert_eq!(
            effects,
            [JogEffect::Notice(JogNotice::TapNeedsHold)],
            "{action:?}: a tap moves nothing and says why"
        );
        let t1 = t0 + ms(3000);
        let mut effects = Vec::new();
        for t in [0, 500, 530, 560] {
            effects.extend(jog.key(action, KeyKind::Press, t1 + ms(t)));
        }
        assert_eq!(effects, [JogEffect::Start(motion)], "{action:?} held");
    }
}

#[test]
fn a_release_event_in_the_fallback_makes_the_press_a_tap_at_once() {
    let (mut jog, t0) = fallback();
    jog.key(Action::JogZPlus, KeyKind::Press, t0);
    assert_eq!(
        jog.key(Action::JogZPlus, KeyKind::Release, t0 + ms(40)),
        [JogEffect::Step(JogMotion::Cartesian { x: 0, y: 0, z: 1 })]
    );
    assert!(ticks(&mut jog, t0 + ms(40), t0 + ms(1000)).is_empty());
}

/// A confirmed fallback hold of `w` from `t0`: press, 500 ms onset, repeats every 30 ms to 650 ms.
fn fallback_hold(jog: &mut JogEngine, t0: Instant) -> Instant {
    for t in [0, 500, 530, 560, 590, 620, 650] {
        jog.key(Action::JogXPlus, KeyKind::Press, t0 + ms(t));
    }
    assert!(jog.is_jogging());
    t0 + ms(650)
}

/// Repeats of `w` (as presses, or as repeats) every 30 ms from `from` for `span`, with ticks.
fn repeats(jog: &mut JogEngine, from: Instant, span: Duration, kind: KeyKind) -> Vec<JogEffect> {
    let mut effects = Vec::new();
    let mut now = from;
    while now <= from + span {
        effects.extend(jog.key(Action::JogXPlus, kind, now));
        effects.extend(jog.tick(now + ms(15)));
        now += ms(30);
    }
    effects
}

#[test]
fn fallback_a_held_key_never_restarts_after_a_stop_until_its_repeats_pause() {
    let (mut jog, t0) = fallback();
    let t = fallback_hold(&mut jog, t0);
    assert_eq!(jog.stop_all(t + ms(10)), [JogEffect::Stop]);
    assert!(jog.is_latched(Action::JogXPlus));
    let effects = repeats(&mut jog, t + ms(30), ms(3000), KeyKind::Press);
    assert!(effects.is_empty(), "latched: {effects:?}");
    // The repeats pause (the key is up); a new press steps, a new hold jogs.
    let t1 = t + ms(4000);
    jog.tick(t1);
    assert!(!jog.is_latched(Action::JogXPlus));
    jog.key(Action::JogXPlus, KeyKind::Press, t1);
    assert_eq!(
        jog.tick(t1 + ms(125)),
        [JogEffect::Step(JogMotion::Cartesian { x: 1, y: 0, z: 0 })]
    );
    let effects = repeats(&mut jog, t1 + ms(500), ms(200), KeyKind::Press);
    assert_eq!(effects.first(), Some(&cart(1, 0, 0)), "a new hold jogs");
}

#[test]
fn fallback_a_stall_in_the_repeats_stops_and_the_resumed_stream_moves_nothing() {
    let (mut jog, t0) = fallback();
    let t = fallback_hold(&mut jog, t0);
    // No repeat for 150 ms (a stalled terminal; 3 intervals are 90 ms): stopped.
    assert!(ticks(&mut jog, t, t + ms(150)).contains(&JogEffect::Stop));
    // The repeats come back before a second timeout: no step, no jog, as long as they come.
    let effects = repeats(&mut jog, t + ms(150), ms(3000), KeyKind::Press);
    assert!(effects.is_empty(), "{effects:?}");
}

#[test]
fn fallback_a_burst_with_no_onset_is_a_hold_only_once_longer_than_any_onset() {
    let (mut jog, t0) = fallback();
    let effects = repeats(&mut jog, t0, ms(690), KeyKind::Press);
    assert!(effects.is_empty(), "no step, no jog yet: {effects:?}");
    let effects = repeats(&mut jog, t0 + ms(720), ms(100), KeyKind::Press);
    assert_eq!(effects.first(), Some(&cart(1, 0, 0)), "{effects:?}");
    // A burst as slow as fast tapping (10 Hz) never is.
    let (mut jog, t0) = fallback();
    let mut effects = Vec::new();
    for i in 0..30 {
        effects.extend(jog.key(Action::JogXPlus, KeyKind::Press, t0 + ms(100 * i)));
        effects.extend(jog.tick(t0 + ms(100 * i + 50)));
    }
    assert_eq!(starts(&effects), 0, "{effects:?}");
}

#[test]
fn latched_keys_stay_still_while_motion_is_not_allowed_and_after() {
    for mode in [ReleaseMode::Reported, ReleaseMode::AutoRepeat] {
        let mut jog = JogEngine::new(mode, REFRESH);
        let t0 = Instant::now();
        // Pressed while motion is not allowed (link down, overlay open): tracked, latched.
        assert!(jog.latch(Action::JogXPlus, KeyKind::Press, t0).is_empty());
        assert!(jog.is_latched(Action::JogXPlus));
        let kind = match mode {
            ReleaseMode::Reported => KeyKind::Repeat,
            ReleaseMode::AutoRepeat => KeyKind::Press,
        };
        // Its auto-repeat starts at 500 ms and goes on once motion is allowed again.
        let mut effects = Vec::new();
        for t in [500, 530, 560] {
            effects.extend(jog.latch(Action::JogXPlus, kind, t0 + ms(t)));
        }
        effects.extend(repeats(&mut jog, t0 + ms(590), ms(2000), kind));
        assert!(effects.is_empty(), "{mode:?}: {effects:?}");
    }
}

#[test]
fn a_repeat_without_a_press_latches_the_key() {
    let (mut jog, t0) = reported();
    assert!(jog.key(Action::JogXPlus, KeyKind::Repeat, t0).is_empty());
    assert!(jog.is_latched(Action::JogXPlus));
    assert!(
        jog.key(Action::JogXPlus, KeyKind::Release, t0 + ms(30))
            .is_empty()
    );
    assert_eq!(
        jog.key(Action::JogXPlus, KeyKind::Press, t0 + ms(200)),
        [cart(1, 0, 0)]
    );
}

#[test]
fn reported_mode_guards_against_a_lost_release() {
    let (mut jog, t0) = reported();
    jog.key(Action::JogXPlus, KeyKind::Press, t0);
    jog.key(Action::JogXPlus, KeyKind::Repeat, t0 + ms(500));
    jog.key(Action::JogXPlus, KeyKind::Repeat, t0 + ms(530));
    // Repeats seen at 30 ms; none for max(6 × 30 ms, 500 ms) = 500 ms: stopped.
    assert_eq!(jog.tick(t0 + ms(1029)).len(), 1, "just a refresh");
    assert_eq!(
        jog.tick(t0 + ms(1030)),
        [
            JogEffect::Stop,
            JogEffect::Notice(JogNotice::NoKeyEvents(ms(500)))
        ]
    );
}

#[test]
fn reported_mode_stops_a_hold_with_no_key_event_for_a_second() {
    let (mut jog, t0) = reported();
    jog.key(Action::JogXPlus, KeyKind::Press, t0);
    let effects = ticks(&mut jog, t0 + ms(5), t0 + KEY_EVENT_TIMEOUT - ms(5));
    assert!(effects.iter().all(|e| *e == cart(1, 0, 0)), "{effects:?}");
    assert_eq!(
        jog.tick(t0 + KEY_EVENT_TIMEOUT),
        [
            JogEffect::Stop,
            JogEffect::Notice(JogNotice::NoKeyEvents(KEY_EVENT_TIMEOUT))
        ]
    );
    assert!(!jog.is_jogging());
    // A late repeat of the same hold does not restart it; a release and a new press do.
    assert!(
        jog.key(Action::JogXPlus, KeyKind::Repeat, t0 + ms(1200))
            .is_empty()
    );
    jog.key(Action::JogXPlus, KeyKind::Release, t0 + ms(1300));
    assert_eq!(
        jog.key(Action::JogXPlus, KeyKind::Press, t0 + ms(1400)),
        [cart(1, 0, 0)]
    );
}

#[test]
fn reported_mode_repeats_keep_a_long_hold_moving() {
    let (mut jog, t0) = reported();
    jog.key(Action::JogXPlus, KeyKind::Press, t0);
    let effects = repeats(&mut jog, t0 + ms(500), ms(5000), KeyKind::Repeat);
    assert!(!effects.contains(&JogEffect::Stop), "{effects:?}");
    assert!(jog.is_jogging());
}

#[test]
fn a_second_press_without_a_release_switches_to_the_auto_repeat_fallback() {
    let (mut jog, t0) = reported();
    jog.key(Action::JogXPlus, KeyKind::Press, t0);
    // The terminal's auto-repeat arrives as presses, and no release ever comes.
    assert_eq!(
        jog.key(Action::JogXPlus, KeyKind::Press, t0 + ms(500)),
        [
            JogEffect::Stop,
            JogEffect::Notice(JogNotice::ReleasesMissing)
        ]
    );
    assert_eq!(jog.mode(), ReleaseMode::AutoRepeat);
    // The hold goes on: nothing moves until its repeats pause.
    let effects = repeats(&mut jog, t0 + ms(530), ms(3000), KeyKind::Press);
    assert!(effects.is_empty(), "{effects:?}");
    let t1 = t0 + ms(5000);
    jog.key(Action::JogXPlus, KeyKind::Press, t1);
    assert_eq!(
        jog.tick(t1 + ms(125)),
        [JogEffect::Step(JogMotion::Cartesian { x: 1, y: 0, z: 0 })],
        "a fresh tap is a step now"
    );
}

#[test]
fn a_press_of_a_latched_key_without_release_is_evidence_too() {
    let (mut jog, t0) = reported();
    jog.key(Action::JogXPlus, KeyKind::Press, t0);
    jog.stop_all(t0 + ms(10));
    assert_eq!(
        jog.key(Action::JogXPlus, KeyKind::Press, t0 + ms(500)),
        [JogEffect::Notice(JogNotice::ReleasesMissing)]
    );
    assert_eq!(jog.mode(), ReleaseMode::AutoRepeat);
    assert!(!jog.is_jogging());
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
fn implausible_gaps_are_not_taken_as_repeat_timing() {
    let (mut jog, t0) = fallback();
    // A 5 ms bounce, then taps: neither an onset nor an interval.
    for t in [0, 5, 400, 800] {
        jog.key(Action::JogXPlus, KeyKind::Press, t0 + ms(t));
    }
    assert_eq!(jog.timing(), Default::default());
}

#[test]
fn a_stop_cancels_a_pending_tap() {
    let (mut jog, t0) = fallback();
    jog.key(Action::JogXPlus, KeyKind::Press, t0);
    assert_eq!(jog.stop_all(t0 + ms(50)), [JogEffect::Stop]);
    assert!(ticks(&mut jog, t0 + ms(50), t0 + ms(1000)).is_empty());
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

#[test]
fn refresh_due_says_exactly_when_a_tick_would_resend_start() {
    let (mut jog, t0) = reported();
    assert!(!jog.refresh_due(t0), "nothing held");
    jog.key(Action::JogXPlus, KeyKind::Press, t0);
    assert!(!jog.refresh_due(t0 + ms(99)));
    assert!(jog.refresh_due(t0 + REFRESH));
    // What refresh_due said is what the tick does.
    assert_eq!(jog.tick(t0 + REFRESH), [cart(1, 0, 0)]);
    assert!(!jog.refresh_due(t0 + REFRESH + ms(1)));
    jog.key(Action::JogXPlus, KeyKind::Release, t0 + REFRESH + ms(50));
    assert!(!jog.refresh_due(t0 + 3 * REFRESH), "released: no refresh");
    assert!(jog.tick(t0 + 3 * REFRESH).is_empty());
}
