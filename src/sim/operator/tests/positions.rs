//! Named positions: save, go to, get, set, anchors, unknown names and parents.

use super::*;

#[test]
fn save_go_to_and_get_a_named_position() {
    let (mut op, mut arm) = (Operator::default(), Arm::default());
    assert_eq!(save(&mut op, &mut arm, "start", false, ""), ReturnCode::OK);
    let (x, y, z) = cart(&mut op, &mut arm, "start");
    assert!(
        (x - 4566).abs() <= 10 && (y - 10).abs() <= 10 && (z - 4338).abs() <= 10,
        "{x} {y} {z}"
    );
    op.handle(
        &mut arm,
        Request::CartesianMove {
            delta_x: 0,
            delta_y: 800,
            delta_z: 0,
            delay_ms: 0,
            time_ms: 0,
        },
    );
    arm.advance(2.0);
    assert!(
        rc(&op.handle(
            &mut arm,
            Request::GoToPosition {
                name: "start".into()
            }
        ))
        .is_ok()
    );
    arm.advance(4.0);
    let p = arm.pose().position;
    assert!((p.y - 0.001).abs() < 1e-3, "back at start: {p:?}");
}

#[test]
fn unknown_names_and_parents_get_their_codes() {
    let (mut op, mut arm) = (Operator::default(), Arm::default());
    for request in [
        Request::GoToPosition {
            name: "nope".into(),
        },
        Request::DeletePosition {
            name: "nope".into(),
        },
        Request::GetPolarPosition {
            name: "nope".into(),
        },
        Request::GetCartesianPosition {
            name: "nope".into(),
        },
    ] {
        assert_eq!(
            rc(&op.handle(&mut arm, request)),
            ReturnCode::UNKNOWN_POSITION
        );
    }
    assert_eq!(
        save(&mut op, &mut arm, "child", true, "missing"),
        ReturnCode::INVALID_PARENT
    );
}

#[test]
fn set_cartesian_and_set_polar_round_trip_through_get() {
    let (mut op, mut arm) = (Operator::default(), Arm::default());
    let set = Request::SetCartesianPosition {
        name: "p".into(),
        x: 4000,
        y: -1000,
        z: 3000,
    };
    assert!(rc(&op.handle(&mut arm, set)).is_ok());
    assert_eq!(cart(&mut op, &mut arm, "p"), (4000, -1000, 3000));
    // 30.0 deg elevation, 45.0 deg azimuth, 500.0 mm radius.
    let set = Request::SetPolarPosition {
        name: "q".into(),
        delta: 300,
        azimuth: 450,
        radius: 5000,
    };
    assert!(rc(&op.handle(&mut arm, set)).is_ok());
    let reply = op.handle(&mut arm, Request::GetPolarPosition { name: "q".into() });
    assert_eq!(
        reply,
        Reply::GetPolarPosition {
            return_code: ReturnCode::OK,
            delta: 300,
            azimuth: 450,
            radius: 5000
        }
    );
    // r cos(30) cos(45) = 306.2 mm; z = r sin(30) = 250 mm.
    assert_eq!(cart(&mut op, &mut arm, "q"), (3062, 3062, 2500));
}

#[test]
fn an_anchored_position_moves_with_its_parent_and_is_frozen_when_the_parent_goes() {
    let (mut op, mut arm) = (Operator::default(), Arm::default());
    op.handle(
        &mut arm,
        Request::SetCartesianPosition {
            name: "table".into(),
            x: 4000,
            y: 0,
            z: 2000,
        },
    );
    // The arm is at home, (4566, 10, 4338): 566 / 10 / 2338 tenths from the table.
    assert_eq!(
        save(&mut op, &mut arm, "cup", true, "table"),
        ReturnCode::OK
    );
    assert_eq!(
        save(&mut op, &mut arm, "note", false, "table"),
        ReturnCode::OK
    );
    let before_note = cart(&mut op, &mut arm, "note");
    op.handle(
        &mut arm,
        Request::SetCartesianPosition {
            name: "table".into(),
            x: 4000,
            y: 1000,
            z: 2000,
        },
    );
    let (x, y, z) = cart(&mut op, &mut arm, "cup");
    assert!(
        (x - 4566).abs() <= 2 && (y - 1010).abs() <= 2 && (z - 4338).abs() <= 2,
        "{x} {y} {z}"
    );
    assert_eq!(
        cart(&mut op, &mut arm, "note"),
        before_note,
        "not anchored: stays"
    );
    // A parent may not become its own descendant.
    assert_eq!(
        save(&mut op, &mut arm, "table", true, "cup"),
        ReturnCode::INVALID_PARENT
    );
    assert!(
        rc(&op.handle(
            &mut arm,
            Request::DeletePosition {
                name: "table".into()
            }
        ))
        .is_ok()
    );
    let (x, y, _) = cart(&mut op, &mut arm, "cup");
    assert!(
        (x - 4566).abs() <= 2 && (y - 1010).abs() <= 2,
        "frozen where it was"
    );
}
