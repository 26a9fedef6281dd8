//! Hand-worked figures: the table of the example, a 40 mm tool sphere, 60 mm slow zone.

use super::*;

fn cell() -> Fence {
    let mut joints = [None; 7];
    joints[1] = Some([-120.0, 120.0]);
    Fence {
        inside: Some(Aabb {
            min: [-600.0, -600.0, 0.0],
            max: [800.0, 600.0, 900.0],
        }),
        tool_radius: 40.0,
        slow_zone: 60.0,
        joints,
        singularity: Singularity::default(),
        keep_out: vec![KeepOut {
            name: "table".into(),
            zone: Aabb {
                min: [250.0, -400.0, -100.0],
                max: [700.0, 400.0, 80.0],
            },
            enabled: true,
        }],
    }
}

/// 125 mm/s (50 % of 250), J2 at 20 deg/s, telemetry at 30 Hz: the least lookahead, 80 ms.
const PACE: Pace = Pace {
    speed_mm_s: 125.0,
    joint_rate: 20.0,
    lookahead_s: 0.05,
};

fn at(tool_mm: [f64; 3]) -> Sample {
    Sample {
        tool_mm,
        joints_deg: [0.0; 7],
        joint_rates: [0.0; 7],
        kappa: None,
    }
}

#[test]
fn the_sphere_s_clearance_to_a_zone_above_beside_and_inside_it() {
    let table = cell().keep_out[0].zone;
    // 150 above the top (80), less the 40 mm radius.
    assert_eq!(
        table.clearance([400.0, 0.0, 230.0], 40.0),
        (110.0, [0.0, 0.0, 1.0])
    );
    // Off a top edge diagonally: 30 up, 40 out in x: 50 from the edge.
    let (c, away) = table.clearance([740.0, 0.0, 110.0], 40.0);
    assert!(
        (c - 10.0).abs() < 1e-9 && (away[0] - 0.8).abs() < 1e-9,
        "{c} {away:?}"
    );
    // 12 mm under the top, inside: out through the top.
    assert_eq!(
        table.clearance([400.0, 0.0, 68.0], 40.0),
        (-52.0, [0.0, 0.0, 1.0])
    );
}

#[test]
fn moving_down_toward_the_table_slows_linearly_to_a_tenth() {
    let fence = cell();
    // Tool point 150 mm over the table top: sphere 110 mm clear, beyond the slow zone.
    let v = fence.judge(&at([400.0, 0.0, 230.0]), Heading::Axes([0, 0, -1]), PACE);
    assert_eq!(
        (v.axes, v.factor, v.state),
        ([0, 0, -1], 1.0, FenceState::Clear)
    );
    // 30 mm clear: 0.1 + 0.9 * 30/60 = 0.55.
    let v = fence.judge(&at([400.0, 0.0, 150.0]), Heading::Axes([0, 0, -1]), PACE);
    assert!((v.factor - 0.55).abs() < 1e-9, "{}", v.factor);
    let slowed = FenceState::Slowed {
        what: "table".into(),
        mm: 30.0,
    };
    assert_eq!(v.state, slowed);
    assert_eq!(v.state.text().as_deref(), Some("SLOWED: table 30 mm"));
    // 6 mm clear: 0.19, kept to the 0.05 step below.
    let v = fence.judge(&at([400.0, 0.0, 126.0]), Heading::Axes([0, 0, -1]), PACE);
    assert!((v.factor - 0.15).abs() < 1e-9, "{}", v.factor);
    // Going up, away from it: full speed.
    let v = fence.judge(&at([400.0, 0.0, 126.0]), Heading::Axes([0, 0, 1]), PACE);
    assert_eq!(v.factor, 1.0);
}

#[test]
fn at_contact_the_axis_toward_the_table_is_taken_out_and_the_rest_slides() {
    let fence = cell();
    // 125 mm/s at a tenth for 80 ms: 1 mm margin. 0.8 mm clear is contact.
    let down = fence.judge(&at([400.0, 0.0, 120.8]), Heading::Axes([0, 0, -1]), PACE);
    assert!(down.blocked());
    assert_eq!(down.state.text().as_deref(), Some("AT FENCE: table"));
    // Diagonally, the approach is 0.71 of the speed: a 0.71 mm margin.
    let slide = fence.judge(&at([400.0, 0.0, 120.6]), Heading::Axes([1, 0, -1]), PACE);
    assert_eq!(slide.axes, [1, 0, 0]);
    assert_eq!(slide.factor, 1.0);
    assert_eq!(slide.state.text().as_deref(), Some("AT FENCE: table"));
    // 1.5 mm clear is not yet contact.
    let near = fence.judge(&at([400.0, 0.0, 121.5]), Heading::Axes([0, 0, -1]), PACE);
    assert!(!near.blocked());
    // Any other motion stops whole at contact.
    let along = Heading::Along {
        tool: [0.6, 0.0, -0.8],
        joint: None,
    };
    assert!(fence.judge(&at([400.0, 0.0, 120.8]), along, PACE).blocked());
}

#[test]
fn the_box_s_floor_and_sides_are_faces_too() {
    let fence = cell();
    let v = fence.judge(&at([0.0, 0.0, 40.5]), Heading::Axes([0, 0, -1]), PACE);
    assert_eq!(v.state.text().as_deref(), Some("AT FENCE: floor"));
    let v = fence.judge(&at([0.0, 540.0, 400.0]), Heading::Axes([0, 1, 0]), PACE);
    let side = FenceState::Slowed {
        what: "+Y side".into(),
        mm: 20.0,
    };
    assert_eq!(v.state, side);
}

#[test]
fn inside_a_zone_deeper_is_refused_and_out_goes_at_a_tenth() {
    let fence = cell();
    // Tool point 12 mm under the table top: the sphere is 52 mm in.
    let deeper = fence.judge(&at([400.0, 0.0, 68.0]), Heading::Axes([0, 0, -1]), PACE);
    assert!(deeper.blocked());
    assert_eq!(
        deeper.state.text().as_deref(),
        Some("OUTSIDE FENCE: table, 52 mm in")
    );
    let out = fence.judge(&at([400.0, 0.0, 68.0]), Heading::Axes([0, 0, 1]), PACE);
    assert_eq!(out.factor, SLOWEST);
    // Sideways, parallel to the way out, is not deeper.
    let side = fence.judge(&at([400.0, 0.0, 68.0]), Heading::Axes([0, 1, 0]), PACE);
    assert_eq!(side.factor, SLOWEST);
}

#[test]
fn a_target_in_a_zone_or_out_of_the_box_is_refused_and_so_is_a_path_through_a_zone() {
    let fence = cell();
    assert_eq!(
        fence.refuse_target([400.0, 0.0, 100.0]).as_deref(),
        Some("table (20 mm in)")
    );
    assert_eq!(
        fence.refuse_target([0.0, 0.0, 20.0]).as_deref(),
        Some("floor (20 mm in)")
    );
    assert_eq!(fence.refuse_target([400.0, 0.0, 200.0]), None);
    // Over the table from one side to the other, low: through it.
    assert_eq!(
        fence.refuse_path([150.0, 0.0, 100.0], [750.0, 0.0, 100.0]),
        Some("table")
    );
    // The same, high enough for the sphere: clear. Sliding along its top at contact: clear.
    assert_eq!(
        fence.refuse_path([150.0, 0.0, 200.0], [750.0, 0.0, 200.0]),
        None
    );
    assert_eq!(
        fence.refuse_path([300.0, 0.0, 120.0], [600.0, 0.0, 120.0]),
        None
    );
    let mut off = cell();
    off.keep_out[0].enabled = false;
    assert_eq!(
        off.refuse_path([150.0, 0.0, 100.0], [750.0, 0.0, 100.0]),
        None
    );
}

#[test]
fn a_joint_jog_slows_over_the_last_ten_degrees_and_stops_at_the_soft_limit() {
    let fence = cell();
    let jog = Heading::Along {
        tool: [0.0; 3],
        joint: Some((1, 1.0)),
    };
    let mut s = at([0.0, 0.0, 400.0]);
    s.joints_deg[1] = 100.0;
    assert_eq!(fence.judge(&s, jog, PACE).factor, 1.0);
    // 5 degrees left: 0.55.
    s.joints_deg[1] = 115.0;
    let v = fence.judge(&s, jog, PACE);
    assert!((v.factor - 0.55).abs() < 1e-9);
    assert_eq!(
        v.state.text().as_deref(),
        Some("SLOWED: J2 soft limit 5.0°")
    );
    // 20 deg/s at a tenth for 80 ms: 0.3 degrees (the least margin).
    s.joints_deg[1] = 119.8;
    let v = fence.judge(&s, jog, PACE);
    assert!(v.blocked());
    assert_eq!(v.state.text().as_deref(), Some("AT FENCE: J2 soft limit"));
    // Away from it, at full speed.
    let back = Heading::Along {
        tool: [0.0; 3],
        joint: Some((1, -1.0)),
    };
    assert_eq!(fence.judge(&s, back, PACE).factor, 1.0);
    // Another motion turning J2 toward its limit at 10 deg/s stops 0.8 degrees short.
    s.joints_deg[1] = 119.3;
    s.joint_rates[1] = 10.0;
    assert!(fence.judge(&s, Heading::Axes([1, 0, 0]), PACE).blocked());
}

#[test]
fn near_a_singularity_speed_falls_unless_the_motion_lowers_kappa() {
    let fence = cell();
    let mut s = at([0.0, 0.0, 400.0]);
    // κ 20 of slow 17, stop 30: (30 - 20) / 13 = 0.77, kept to 0.75.
    s.kappa = Some((20.0, 20.5));
    let v = fence.judge(&s, Heading::Axes([1, 0, 0]), PACE);
    assert!((v.factor - 0.75).abs() < 1e-9);
    assert_eq!(
        v.state.text().as_deref(),
        Some("SLOWED: near singularity κ 20")
    );
    s.kappa = Some((20.0, 19.5));
    assert_eq!(fence.judge(&s, Heading::Axes([1, 0, 0]), PACE).factor, 1.0);
    s.kappa = Some((31.0, 32.0));
    assert!(fence.judge(&s, Heading::Axes([1, 0, 0]), PACE).blocked());
}

#[test]
fn kappa_ahead_says_whether_straightening_the_elbow_raises_kappa() {
    // J4 at -20 degrees (signed): near straight. Turning J4 toward 0 straightens it.
    let q = [0.0, 15.0, 180.0, -20.0, 0.0, 55.0, 90.0];
    let toward = Heading::Along {
        tool: [0.0; 3],
        joint: Some((3, 1.0)),
    };
    let (now, ahead) = kappa_ahead(&q, &toward).expect("finite");
    assert!(ahead > now, "{now} {ahead}");
    let away = Heading::Along {
        tool: [0.0; 3],
        joint: Some((3, -1.0)),
    };
    let (_, ahead) = kappa_ahead(&q, &away).expect("finite");
    assert!(ahead < now);
}

#[test]
fn check_names_the_key_that_cannot_be_a_fence() {
    assert_eq!(cell().check(), Ok(()));
    let mut f = cell();
    f.inside = Some(Aabb {
        min: [0.0, 0.0, 900.0],
        max: [1.0, 1.0, 900.0],
    });
    assert_eq!(
        f.check().map_err(|e| e.to_string()),
        Err("inside: min 900 is not below max 900 on z".into())
    );
    let mut f = cell();
    f.tool_radius = -1.0;
    assert_eq!(
        f.check().map_err(|e| e.key().to_string()),
        Err("tool_radius".into())
    );
    let mut f = cell();
    f.slow_zone = f64::NAN;
    assert_eq!(
        f.check().map_err(|e| e.key().to_string()),
        Err("slow_zone".into())
    );
    let mut f = cell();
    f.joints[3] = Some([-150.0, 140.0]);
    assert_eq!(
        f.check().map_err(|e| e.to_string()),
        Err("joints.j4: [-150, 140] is outside the arm's own limits of ±147.8°".into())
    );
    let mut f = cell();
    f.keep_out[0].zone.max[0] = f64::INFINITY;
    assert_eq!(
        f.check().map_err(|e| e.key().to_string()),
        Err("keep_out[1].max".into())
    );
    let mut f = cell();
    f.singularity = Singularity {
        slow: 30.0,
        stop: 17.0,
    };
    assert_eq!(
        f.check().map_err(|e| e.key().to_string()),
        Err("singularity".into())
    );
    assert_eq!(Fence::joint_index("j2"), Some(1));
    assert_eq!(Fence::joint_index("j8"), None);
}
