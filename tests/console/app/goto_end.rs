//! A go-to's end is ours only when the arm's action status names our move and the arm is at
//! rest where it was sent (within `ARRIVED_MM` / `ARRIVED_DEG`): another client's move that
//! starts under our go-to or tour leg, or an arm that ends elsewhere, stops the arm, ends the
//! tour and says `MOVED BY ANOTHER CLIENT`, never "done". Fake clock.

use armjog::console::app::{ARRIVED_DEG, ARRIVED_MM, Effect, MotionShown, QUESTION_QUIET};
use armjog::kortex::{ActionState, ActionStatus, Coded, MoveType, Pose};
use armjog::link::interface::{ArmCommand, ArmEvent, TelemetrySource};

use crate::app::tours::{Bench, leg};
use crate::app_support::{STOP, ms, no_motion};

/// One telemetry report 100 ms on: the tool at `tool`, the action status `status` of
/// `move_type` `id`, the joints turning at `velocity` deg/s.
fn report(
    b: &mut Bench,
    velocity: f32,
    (status, move_type, id): (ActionStatus, MoveType, u16),
    tool: Pose,
) -> Vec<Effect> {
    let now = b.at(ms(100));
    let action = ActionState {
        status: Coded::Known(status),
        id,
        move_type: Coded::Known(move_type),
    };
    let mut t =
        crate::app_support::arm_telemetry(crate::app_support::HOME_JOINTS, velocity, action);
    t.tcp.pose = tool;
    b.app.handle(
        armjog::console::app::Input::Arm(ArmEvent::Telemetry(Box::new(t))),
        now,
    )
}

const OURS_STARTED: (ActionStatus, MoveType, u16) =
    (ActionStatus::Started, MoveType::CartesianTrajectory, 0);
const OURS_COMPLETED: (ActionStatus, MoveType, u16) =
    (ActionStatus::Completed, MoveType::CartesianTrajectory, 0);

/// A single go-to to the selected position, `bench`, over Modbus: its command, taken.
fn go_to_bench(b: &mut Bench) -> (ArmCommand, Pose) {
    assert_eq!(b.app.selected_name(), Some("bench"));
    b.press("o");
    b.at(QUESTION_QUIET);
    let command = leg(&b.press("y"));
    let ArmCommand::MoveToPose(target) = command else {
        panic!("not a move to pose: {command:?}");
    };
    b.event(ArmEvent::Done {
        command: command.clone(),
    });
    (command, target)
}

/// Our move reported started, the tool still where it was.
fn ours_started(b: &mut Bench) -> Vec<Effect> {
    let tool = b.tool;
    report(b, 12.0, OURS_STARTED, tool)
}

/// The tour's leg was another client's move: the arm stopped, nothing started, the tour over
/// and `said` on the message line.
fn assert_tour_ended(b: &Bench, effects: &[Effect], said: &str) {
    assert!(effects.contains(&STOP) && no_motion(effects), "{effects:?}");
    assert_eq!(b.tour_label(), None);
    assert_eq!(b.message(), said);
}

fn offset(pose: Pose, dx_mm: f32, dtheta_z: f32) -> Pose {
    Pose {
        x: pose.x + dx_mm / 1000.0,
        theta_z: pose.theta_z + dtheta_z,
        ..pose
    }
}

#[test]
fn another_clients_action_under_our_go_to_stops_the_arm_and_is_never_our_go_to_done() {
    let mut b = Bench::new(false);
    let (_, target) = go_to_bench(&mut b);
    let home = b.tool;
    assert!(no_motion(&ours_started(&mut b)));
    // `armjog modbus action --id 5` from elsewhere: the arm runs the Zero action instead.
    let action_5 = (ActionStatus::Started, MoveType::Action, 5);
    let effects = report(&mut b, 12.0, action_5, home);
    assert!(effects.contains(&STOP), "{effects:?}");
    assert_eq!(
        b.message(),
        "go to 'bench' not done: MOVED BY ANOTHER CLIENT: the arm runs action 5, not our \
         cartesian trajectory; STOP sent"
    );
    assert!(!matches!(b.app.motion_shown(), MotionShown::Action { .. }));
    // Its end, at rest at the target even, is not ours: nothing says done.
    let said = b.message();
    let end = report(
        &mut b,
        0.0,
        (ActionStatus::Completed, MoveType::Action, 5),
        target,
    );
    assert!(no_motion(&end), "{end:?}");
    assert_eq!(b.message(), said);
}

#[test]
fn a_go_to_at_rest_away_from_its_target_is_another_clients_move_not_done() {
    let mut b = Bench::new(false);
    let (_, target) = go_to_bench(&mut b);
    ours_started(&mut b);
    // Another client's trajectory replaced ours (same move type) and ended 150 mm off.
    let effects = report(&mut b, 0.0, OURS_COMPLETED, offset(target, 150.0, 0.0));
    assert!(effects.contains(&STOP), "{effects:?}");
    assert_eq!(
        b.message(),
        "go to 'bench' not done: MOVED BY ANOTHER CLIENT: the arm is at rest 150 mm from where \
         it was sent; STOP sent"
    );
    // Turned away, the point where it was sent: not ours either.
    let mut b = Bench::new(false);
    let (_, target) = go_to_bench(&mut b);
    ours_started(&mut b);
    let effects = report(&mut b, 0.0, OURS_COMPLETED, offset(target, 0.0, 10.0));
    assert!(effects.contains(&STOP), "{effects:?}");
    assert!(
        b.message()
            .ends_with("turned 10 deg from where it was sent; STOP sent"),
        "{}",
        b.message()
    );
}

#[test]
fn a_go_to_within_the_tolerance_of_its_target_is_done() {
    let mut b = Bench::new(false);
    let (_, target) = go_to_bench(&mut b);
    // A status read within the grace may still be the home action before it: not a foreign
    // move.
    let before = (ActionStatus::Completed, MoveType::Action, 2);
    let home = b.tool;
    assert!(report(&mut b, 0.0, before, home).is_empty());
    ours_started(&mut b);
    let near = offset(target, ARRIVED_MM * 0.8, ARRIVED_DEG * 0.8);
    let effects = report(&mut b, 0.0, OURS_COMPLETED, near);
    assert!(effects.is_empty(), "{effects:?}");
    assert_eq!(b.message(), "go to 'bench' done");
}

#[test]
fn a_tour_leg_another_client_moved_elsewhere_ends_the_tour_and_no_next_leg_starts() {
    let mut b = Bench::new(false);
    let first = leg(&b.play("O"));
    let ArmCommand::MoveToPose(bench) = first else {
        panic!("{first:?}");
    };
    b.event(ArmEvent::Done { command: first });
    ours_started(&mut b);
    // A second console's leg to pick took over: the arm completes a trajectory there.
    let pick = offset(bench, 10.0, 0.0);
    let effects = report(&mut b, 0.0, OURS_COMPLETED, pick);
    assert_tour_ended(
        &b,
        &effects,
        "tour 'rounds' leg 1/3 → bench ended the tour: go to 'bench' not done: MOVED BY ANOTHER \
         CLIENT: the arm is at rest 10 mm from where it was sent; STOP sent",
    );
    assert!(no_motion(&report(&mut b, 0.0, OURS_COMPLETED, pick)));
}

#[test]
fn a_talos_go_to_is_done_at_its_position_whatever_move_type_and_not_done_elsewhere() {
    // Over Talos the operator runs the Go To: the arm's move type may be anything (the last
    // Modbus move's, shown before it too), only where it ends tells.
    let mut b = Bench::new(true);
    b.move_type = MoveType::Action;
    b.feed(0.0, ActionStatus::Completed);
    let first = leg(&b.play("O"));
    assert_eq!(
        first,
        ArmCommand::GoToPosition {
            name: "bench".into()
        }
    );
    let second = leg(&b.finish_leg(first));
    assert_eq!(b.tour_label().as_deref(), Some("TOUR 2/3 → pick"));
    b.leg_started(second);
    // It comes to rest where it was, at bench, not at pick.
    let effects = b.feed(0.0, ActionStatus::Completed);
    assert_tour_ended(
        &b,
        &effects,
        "tour 'rounds' leg 2/3 → pick ended the tour: go to 'pick' not done: MOVED BY ANOTHER \
         CLIENT: the arm is at rest 10 mm from where it was sent; STOP sent",
    );
}

/// A console over Talos with Modbus telemetry (the arm's action status read over Modbus), the
/// status registers left at `(status, move type, id)` by an earlier move: what the status named
/// when our Go To was sent.
fn talos_with_status(left: (ActionStatus, MoveType, u16)) -> Bench {
    let mut b = Bench::new(true);
    b.event(ArmEvent::TelemetrySource(TelemetrySource::Modbus));
    let tool = b.tool;
    report(&mut b, 0.0, left, tool);
    b
}

#[test]
fn another_clients_action_under_a_talos_leg_ends_the_tour_naming_the_action() {
    // The simulator's Talos Go To leaves the last move's type and id (the arm's Home, action 0)
    // and reports it started: not another client's.
    let mut b = talos_with_status((ActionStatus::Completed, MoveType::Action, 0));
    let first = leg(&b.play("O"));
    assert!(
        matches!(first, ArmCommand::GoToPosition { .. }),
        "{first:?}"
    );
    b.event(ArmEvent::Done { command: first });
    let home = b.tool;
    let ours = (ActionStatus::Started, MoveType::Action, 0);
    assert!(no_motion(&report(&mut b, 12.0, ours, home)));
    assert!(no_motion(&report(&mut b, 12.0, ours, home)));
    assert_eq!(b.tour_label().as_deref(), Some("TOUR 1/3 → bench"));
    // `armjog modbus action --id 5` from a shell: the arm runs the Zero action instead.
    let action_5 = (ActionStatus::Started, MoveType::Action, 5);
    let effects = report(&mut b, 12.0, action_5, home);
    assert_tour_ended(
        &b,
        &effects,
        "tour 'rounds' leg 1/3 → bench ended the tour: go to 'bench' not done: MOVED BY ANOTHER \
         CLIENT: the arm runs action 5; STOP sent",
    );
    let end = report(
        &mut b,
        0.0,
        (ActionStatus::Completed, MoveType::Action, 5),
        home,
    );
    assert!(no_motion(&end), "{end:?}");
}

#[test]
fn a_talos_go_to_shown_as_a_trajectory_or_the_last_stored_move_is_ours_done_at_its_place() {
    for shown in [MoveType::CartesianTrajectory, MoveType::Sequence] {
        let mut b = talos_with_status((ActionStatus::Completed, MoveType::Sequence, 3));
        b.press("o");
        b.at(QUESTION_QUIET);
        let command = leg(&b.press("y"));
        b.event(ArmEvent::Done {
            command: command.clone(),
        });
        let home = b.tool;
        let ours = (ActionStatus::Started, shown, 3);
        assert!(no_motion(&report(&mut b, 12.0, ours, home)));
        b.arrive(&command);
        let there = b.tool;
        let end = (ActionStatus::Completed, shown, 3);
        assert!(report(&mut b, 0.0, end, there).is_empty());
        assert_eq!(b.message(), "go to 'bench' done", "{shown:?}");
    }
}

#[test]
fn a_stored_action_under_talos_home_is_not_another_clients_move() {
    // An operator may well run the arm's stored Home action for Talos Home.
    let mut b = talos_with_status((ActionStatus::Completed, MoveType::CartesianTrajectory, 0));
    b.press("h");
    b.at(QUESTION_QUIET);
    let effects = b.press("y");
    assert!(
        effects.contains(&Effect::Arm(ArmCommand::Home)),
        "{effects:?}"
    );
    b.event(ArmEvent::Done {
        command: ArmCommand::Home,
    });
    let home = b.tool;
    let effects = report(
        &mut b,
        12.0,
        (ActionStatus::Started, MoveType::Action, 2),
        home,
    );
    assert!(effects.is_empty(), "{effects:?}");
    assert!(matches!(b.app.motion_shown(), MotionShown::Action { .. }));
    report(
        &mut b,
        0.0,
        (ActionStatus::Completed, MoveType::Action, 2),
        home,
    );
    assert_eq!(b.message(), "home done");
}
