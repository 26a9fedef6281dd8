//! `armjog sim --near-limit N`: parsed through the clap definition, the pose it starts the
//! simulator at, and the joints it refuses.

use armjog::cli::{Cli, Command};
use armjog::sim::kinematics::{HOME_DEG, JOINT_LIMITS_DEG};
use clap::{CommandFactory, Parser};

pub(crate) fn sim_args(args: &[&str]) -> Result<armjog::cli::sim::SimArgs, clap::Error> {
    let mut full = vec!["armjog", "sim"];
    full.extend_from_slice(args);
    match Cli::try_parse_from(&full)?.command {
        Some(Command::Sim(sim)) => Ok(sim),
        other => panic!("{args:?}: not sim but {other:?}"),
    }
}

#[test]
fn near_limit_places_the_joint_two_degrees_inside_its_limit_and_the_rest_at_home() {
    for joint in [2usize, 4, 6] {
        let text = joint.to_string();
        let config = sim_args(&["--near-limit", &text])
            .expect("parses")
            .config()
            .expect("a limited joint");
        let q = config.arm.joints().map(f64::to_degrees);
        let limit = JOINT_LIMITS_DEG[joint - 1].expect("limited");
        for (i, (angle, home)) in q.iter().zip(HOME_DEG).enumerate() {
            // Angles as the model keeps them may wrap: compare on the circle.
            let expected = if i == joint - 1 { limit - 2.0 } else { home };
            let off = (angle - expected).rem_euclid(360.0);
            assert!(
                off.min(360.0 - off) < 1e-9,
                "J{}: {angle} vs {expected}",
                i + 1
            );
        }
    }
}

#[test]
fn near_limit_refuses_continuous_joints_and_numbers_out_of_range() {
    for joint in ["1", "3", "5", "7"] {
        let args = sim_args(&["--near-limit", joint]).expect("parses");
        let err = args.config().expect_err("a continuous joint").to_string();
        assert!(
            err.contains(&format!("--near-limit {joint}")) && err.contains("continuously"),
            "{err}"
        );
    }
    for joint in ["0", "8", "four"] {
        let err = sim_args(&["--near-limit", joint]).expect_err("out of range");
        assert!(err.to_string().contains("--near-limit"), "{joint}: {err}");
    }
}

/// `armjog sim --help`, long form.
pub(crate) fn sim_long_help() -> String {
    let mut command = Cli::command();
    command.build();
    command
        .find_subcommand_mut("sim")
        .expect("sim")
        .render_long_help()
        .to_string()
}

#[test]
fn sim_help_documents_near_limit() {
    let help = sim_long_help();
    assert!(help.contains("--near-limit"), "{help}");
    assert!(help.contains("2, 4 or 6"), "{help}");
}
