//! `armjog sim --near-singularity`: parsed through the clap definition, the pose it starts the
//! simulator at (inside the console's singularity warning, inside every joint limit), and its
//! conflict with `--near-limit`.

use crate::sim_args_near_limit::{sim_args, sim_long_help};
use armjog::kortex::gen3::{SINGULARITY_WARNING, condition_number};
use armjog::sim::kinematics::{HOME_DEG, within_limit};

#[test]
fn near_singularity_bends_the_elbow_to_3_degrees_short_of_straight_and_the_rest_at_home() {
    let config = sim_args(&["--near-singularity"])
        .expect("parses")
        .config()
        .expect("a pose");
    let q = config.arm.joints();
    let q_deg = q.map(f64::to_degrees);
    for (i, (angle, home)) in q_deg.iter().zip(HOME_DEG).enumerate() {
        let expected = if i == 3 { -3.0 } else { home };
        // Angles as the model keeps them may wrap: compare on the circle.
        let off = (angle - expected).rem_euclid(360.0);
        assert!(
            off.min(360.0 - off) < 1e-9,
            "J{}: {angle} vs {expected}",
            i + 1
        );
        assert!(within_limit(i, q[i]), "J{} out of its limits", i + 1);
    }
    let kappa = condition_number(&q);
    assert!(kappa > SINGULARITY_WARNING, "{kappa}");
    // Without the flag: home, far below the warning.
    let home = sim_args(&[]).expect("parses").config().expect("home");
    assert!(condition_number(&home.arm.joints()) < SINGULARITY_WARNING);
}

#[test]
fn near_singularity_and_near_limit_cannot_both_be_given() {
    let err = sim_args(&["--near-singularity", "--near-limit", "4"]).expect_err("conflict");
    let text = err.to_string();
    assert!(
        text.contains("--near-singularity") && text.contains("--near-limit"),
        "{text}"
    );
}

#[test]
fn sim_help_documents_near_singularity() {
    let help = sim_long_help();
    assert!(help.contains("--near-singularity"), "{help}");
    assert!(help.contains("3 degrees short of straight"), "{help}");
}
