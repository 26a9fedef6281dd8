//! Reading a stored run's progress from hand-built register images (addresses from the ICD:
//! holding 100 status, 101 id, 102 move type; input 0 robot state, 2-3 faults, 48.. joint
//! velocities).

use super::*;
use crate::kortex::image::RegisterImage;

/// status 0 started, 1 completed, 3 aborted; move type 0 action, 1 sequence.
fn poll(status: u16, id: u16, move_type: u16, moving: bool) -> Telemetry {
    let mut image = RegisterImage::default();
    image.input_registers[0] = 7; // ready
    image.holding_registers[100] = status;
    image.holding_registers[101] = id;
    image.holding_registers[102] = move_type;
    if moving {
        // J1 at 10 deg/s = 0x41200000, low word first.
        image.input_registers[48] = 0x0000;
        image.input_registers[49] = 0x4120;
    }
    Telemetry::decode(&image)
}

fn sequence(id: u16) -> StoredRun {
    StoredRun::new(Stored {
        motion: StoredMotion::Sequence,
        id,
    })
}

const MS: fn(u64) -> Duration = Duration::from_millis;

#[test]
fn names_say_kind_and_id() {
    let stored = Stored {
        motion: StoredMotion::Action,
        id: 5,
    };
    assert_eq!(stored.to_string(), "action 5");
    assert_eq!(
        sequence(1).stored.to_string(),
        "sequence 1",
        "and a sequence"
    );
}

#[test]
fn started_running_completed() {
    let mut run = sequence(1);
    // An earlier action 2 completed: not ours, not yet past the start limit.
    assert_eq!(
        run.observe(&poll(1, 2, 0, false), MS(100)),
        Progress::Pending
    );
    assert_eq!(
        run.observe(&poll(0, 1, 1, true), MS(200)),
        Progress::Started
    );
    assert!(run.seen_started());
    assert_eq!(
        run.observe(&poll(0, 1, 1, true), MS(300)),
        Progress::Running
    );
    // Completed while still moving is not the end yet.
    assert_eq!(
        run.observe(&poll(1, 1, 1, true), MS(400)),
        Progress::Running
    );
    let end = run.observe(&poll(1, 1, 1, false), MS(500));
    assert_eq!(end, Progress::Completed);
    assert!(end.ended());
}

#[test]
fn an_earlier_completed_run_of_the_same_id_is_not_taken_for_this_one() {
    let mut run = sequence(1);
    assert_eq!(
        run.observe(&poll(1, 1, 1, false), MS(100)),
        Progress::Pending
    );
    assert_eq!(
        run.observe(&poll(1, 1, 1, false), MS(499)),
        Progress::Pending
    );
    // Past the grace the status is this run's: it ended at once.
    assert_eq!(
        run.observe(&poll(1, 1, 1, false), MS(500)),
        Progress::Completed
    );
}

#[test]
fn the_same_id_as_an_action_is_not_the_sequence() {
    let mut run = sequence(2);
    assert_eq!(
        run.observe(&poll(0, 2, 0, true), MS(100)),
        Progress::Pending
    );
    match run.observe(&poll(0, 2, 0, true), MS(2000)) {
        Progress::NotTaken(why) => assert_eq!(
            why,
            "the arm did not take sequence 2 within 2 s: it reports action 2 (is it on the \
             arm's Web App, Actions page?)"
        ),
        other => panic!("{other:?}"),
    }
}

#[test]
fn aborted_after_running_is_an_abort() {
    let mut run = sequence(1);
    run.observe(&poll(0, 1, 1, true), MS(100));
    assert_eq!(
        run.observe(&poll(3, 1, 1, false), MS(900)),
        Progress::Aborted("aborted".into())
    );
}

#[test]
fn aborted_without_having_run_is_not_taken() {
    let mut run = sequence(9);
    assert_eq!(
        run.observe(&poll(3, 9, 1, false), MS(100)),
        Progress::Pending
    );
    assert_eq!(
        run.observe(&poll(3, 9, 1, false), MS(600)),
        Progress::NotTaken(
            "the arm did not take sequence 9: aborted at once (is it on the arm's Web App, \
             Actions page?)"
                .into()
        )
    );
}

#[test]
fn a_fault_ends_the_run_at_any_time() {
    let mut run = sequence(1);
    run.observe(&poll(0, 1, 1, true), MS(100));
    let mut t = poll(0, 1, 1, true);
    t.faults = crate::kortex::FlagSet::from_bits(1 << 4);
    match run.observe(&t, MS(200)) {
        Progress::Fault(why) => assert!(why.starts_with("the arm is in fault"), "{why}"),
        other => panic!("{other:?}"),
    }
}

#[test]
fn another_move_after_ours_started_is_another_clients_whenever_it_comes() {
    let mut run = sequence(1);
    assert_eq!(
        run.observe(&poll(0, 1, 1, true), MS(100)),
        Progress::Started
    );
    // Seconds into the run, well past the start limit: still not "did not take".
    assert_eq!(
        run.observe(&poll(0, 5, 0, true), Duration::from_secs(30)),
        Progress::OtherMove("the arm runs action 5, not our sequence 1".into())
    );
    // Within the first moments too, once ours was seen: a twist (move type 3) from elsewhere.
    let mut run = sequence(1);
    run.observe(&poll(0, 1, 1, true), MS(100));
    assert_eq!(
        run.observe(&poll(0, 0, 3, true), MS(200)),
        Progress::OtherMove("the arm runs twist, not our sequence 1".into())
    );
    // Before ours was seen the status may still be an earlier run's: not another client's.
    let mut run = sequence(1);
    assert_eq!(
        run.observe(&poll(0, 5, 0, true), MS(600)),
        Progress::Pending
    );
}
