use super::*;

/// A cap checked as the front ends check it.
fn cap(max_jog_speed: f64) -> SpeedCap {
    SpeedCap::new(max_jog_speed).expect("a cap in range")
}

#[test]
fn a_percentage_scales_the_cap_and_the_turn_rate_and_only_1_to_100_is_settable() {
    assert!((tool_speed_at(0.25, 20) - 0.05).abs() < 1e-12);
    assert!((tool_speed_at(250.0, 100) - 250.0).abs() < 1e-12);
    assert!((cap(0.25).turn_rate(20) - 6.0).abs() < 1e-5);
    assert!((cap(0.25).turn_rate(100) - 30.0).abs() < 1e-5);
    assert!(!is_settable(0) && is_settable(1) && is_settable(100) && !is_settable(101));
}

#[test]
fn a_move_is_capped_at_the_tool_speed_and_the_turn_rate_of_its_percentage() {
    // 50 % of 250 mm/s: 125 mm/s, and half of the 30 deg/s turn rate.
    let limits = cap(0.25).move_cap(50);
    assert!((limits.linear - 0.125).abs() < 1e-7, "{limits:?}");
    assert!((limits.angular - 15.0).abs() < 1e-5, "{limits:?}");
    // The same rate an orientation jog turns at, at every percentage.
    for percent in 1..=100 {
        assert_eq!(
            cap(0.05).move_cap(percent).angular,
            cap(0.05).turn_rate(percent)
        );
    }
    let limits = cap(0.05).move_cap(10);
    assert!((limits.linear - 0.005).abs() < 1e-7 && (limits.angular - 3.0).abs() < 1e-5);
}

#[test]
fn a_cap_is_above_0_and_at_most_the_twists_limit() {
    for refused in [
        0.0,
        -0.1,
        0.500_001,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ] {
        assert_eq!(
            SpeedCap::new(refused),
            Err(SpeedCapError::OutOfRange),
            "{refused}"
        );
    }
    assert!((cap(0.5).max_jog_speed - 0.5).abs() < 1e-12);
    assert!((cap(0.000_1).max_mm_s() - 0.1).abs() < 1e-12);
    assert_eq!(
        SpeedCapError::OutOfRange.to_string(),
        "must be above 0 and at most 500 mm/s (the arm's twist limit)"
    );
}

#[test]
#[should_panic(expected = "max_jog_speed 0 m/s: must be above 0")]
fn a_configuration_that_skipped_the_check_does_not_start() {
    SpeedCap::configured(0.0);
}

#[test]
fn every_motion_takes_its_speed_from_the_one_cap() {
    // 80 mm/s at 40 %: 32 mm/s, a 0.032 m/s twist, a 12 deg/s turn.
    let c = cap(0.08);
    assert!((c.max_mm_s() - 80.0).abs() < 1e-9);
    assert!((c.tool_speed(40) - 0.032).abs() < 1e-12);
    assert!((c.tool_speed_mm_s(40) - 32.0).abs() < 1e-9);
    assert!((c.twist_speed(40) - 0.032).abs() < 1e-7);
    assert!((c.turn_rate(40) - 12.0).abs() < 1e-5);
    // At 100 %: the cap itself, and 30 deg/s.
    let limits = c.move_cap(100);
    assert!((limits.linear - 0.08).abs() < 1e-7 && (limits.angular - 30.0).abs() < 1e-5);
    // A polar pan configured at 250 mm/s keeps to the 80 mm/s cap: 40 % of it, 32 mm/s; one
    // configured at 10 mm/s keeps its own bound: 40 % of it, 4 mm/s.
    assert!((c.polar_linear_bound(0.25, 40) - 0.032).abs() < 1e-7);
    assert!((c.polar_linear_bound(0.01, 40) - 0.004).abs() < 1e-7);
}

#[test]
fn a_joint_jog_keeps_the_tool_point_under_the_cap_at_its_percentage() {
    let home = crate::kortex::gen3::HOME_DEG.map(|d| d as f32);
    // 50 mm/s at 50 %: 25 mm/s. J1 at home has a 0.4566 m lever arm, 12.5 mm longer half a
    // second ahead: 0.025 / 0.4691 rad/s = 3.05 deg/s, under the 20 deg/s jog speed's 10.
    let rate = cap(0.05).joint_rate(20.0, &home, 1, 50, 0.5);
    assert!((rate - 3.053).abs() < 0.02, "{rate}");
    // A slower jog speed bounds it itself: 2 deg/s at 50 %, 1 deg/s.
    let rate = cap(0.05).joint_rate(2.0, &home, 1, 50, 0.5);
    assert!((rate - 1.0).abs() < 1e-6, "{rate}");
}

#[test]
fn an_operator_is_checked_with_the_cap() {
    // 50 mm/s on a 250 mm/s operator: its 20 % is the console's 100 %.
    let scale = cap(0.05).with_operator(0.25).expect("an operator in range");
    assert_eq!(scale.cap(), cap(0.05));
    assert_eq!(scale.to_operator(100), 20);
    assert_eq!(scale.from_operator(20), Some(100));
    assert!((scale.operator_mm_s(20) - 50.0).abs() < 1e-9);
    // 5 mm/s is 1 % of 500 mm/s: allowed; 4 mm/s is not.
    assert!(cap(0.005).with_operator(0.5).is_ok());
    assert_eq!(
        cap(0.004).with_operator(0.5),
        Err(SpeedCapError::OperatorTooFast)
    );
    for refused in [0.0, 0.6, f64::NAN] {
        assert_eq!(
            cap(0.05).with_operator(refused),
            Err(SpeedCapError::OutOfRange),
            "{refused}"
        );
    }
}

#[test]
fn the_same_full_speed_is_one_to_one() {
    let scale = OperatorScale::new(0.25, 0.25);
    for percent in 1..=100 {
        assert_eq!(scale.to_operator(percent), percent);
        assert_eq!(scale.from_operator(percent), Some(percent));
    }
}

#[test]
fn a_faster_operator_gets_a_smaller_percentage_rounded_down() {
    // The case: a 50 mm/s cap on a 250 mm/s operator.
    let scale = OperatorScale::new(0.05, 0.25);
    assert_eq!(scale.to_operator(100), 20);
    assert_eq!(scale.to_operator(50), 10);
    assert_eq!(scale.to_operator(24), 4, "4.8 % rounds down");
    assert_eq!(scale.to_operator(1), 1, "0.2 % is asked as the least, 1 %");
    assert_eq!(
        scale.to_operator(0),
        0,
        "out of range: the operator refuses it"
    );
    assert_eq!(scale.to_operator(101), 101);
    // A cap that does not divide evenly: 50 of 300 mm/s.
    let scale = OperatorScale::new(50.0, 300.0);
    assert_eq!(scale.to_operator(100), 16, "16.7 % rounds down");
    assert_eq!(scale.to_operator(75), 12);
}

#[test]
fn no_console_percentage_asks_for_more_than_its_share_of_the_cap() {
    for (cap, full) in [(50.0, 250.0), (50.0, 300.0), (50.0, 500.0), (7.0, 500.0)] {
        let scale = OperatorScale::new(cap, full);
        for percent in 1..=100u8 {
            let operator_mm_s = f64::from(scale.to_operator(percent)) * full / 100.0;
            let wanted = cap * f64::from(percent) / 100.0;
            // Over the console's share only at the operator's floor of 1 %; never over the cap.
            assert!(
                operator_mm_s <= wanted + 1e-9 || scale.to_operator(percent) == 1,
                "{cap}/{full} at {percent} %: {operator_mm_s} mm/s"
            );
            assert!(operator_mm_s <= cap + 1e-9);
        }
    }
}

#[test]
fn an_operator_speed_reads_back_rounded_up_and_over_the_cap_as_none() {
    let scale = OperatorScale::new(0.05, 0.25);
    assert_eq!(scale.from_operator(20), Some(100));
    assert_eq!(scale.from_operator(10), Some(50));
    assert_eq!(scale.from_operator(21), None, "105 % of the cap");
    assert_eq!(scale.from_operator(100), None);
    let scale = OperatorScale::new(50.0, 300.0);
    assert_eq!(scale.from_operator(12), Some(72));
    assert_eq!(scale.from_operator(13), Some(78), "78.000 exactly, not 79");
    assert_eq!(scale.from_operator(17), None, "102 % of the cap");
    // A console cap above the operator's full speed: its 100 % is well under the cap.
    let scale = OperatorScale::new(0.25, 0.1);
    assert_eq!(scale.to_operator(100), 100);
    assert_eq!(scale.from_operator(100), Some(40));
}

#[test]
fn one_percent_of_the_operator_must_fit_under_the_cap() {
    assert!(OperatorScale::new(5.0, 500.0).allows_one_percent());
    assert!(!OperatorScale::new(4.9, 500.0).allows_one_percent());
    assert!(OperatorScale::new(0.0025, 0.25).allows_one_percent());
}
