//! `armjog arms`: the arm profiles of config.toml, one line each with its targets and fence.

use clap::Args;

use super::Outcome;
use super::profiles::{self, EXIT_PROFILE, ProfileError, Profiles};
use crate::link::fence::Fence;
use crate::text;

#[derive(Debug, Args)]
pub struct ArmsArgs {}

/// Runs `armjog arms`; a missing default file means no profiles yet.
pub fn run(given: Option<&std::path::Path>) -> Outcome {
    let Some(path) = profiles::config_path(given) else {
        return refused(&ProfileError::NoPlace);
    };
    match profiles::load(&path) {
        Ok(profiles) => Outcome::printed(lines(&profiles)),
        Err(ProfileError::NoFile { path }) if given.is_none() => Outcome::printed(vec![format!(
            "no arm profiles: {} does not exist (each is an [arms.NAME] table; see the README)",
            path.display()
        )]),
        Err(e) => refused(&e),
    }
}

/// `fence: 2 keep-out zones, 1 off`.
fn fence_clause(fence: &Fence) -> String {
    let zones = fence.keep_out.len();
    let off = zones - fence.zones().count();
    let mut clause = match zones {
        0 => "fence: no keep-out zones".to_string(),
        1 => "fence: 1 keep-out zone".to_string(),
        n => format!("fence: {n} keep-out zones"),
    };
    if off > 0 {
        clause.push_str(&format!(", {off} off"));
    }
    clause
}

fn refused(e: &ProfileError) -> Outcome {
    Outcome::error(e.to_string(), EXIT_PROFILE)
}

/// One line a profile: its name, its Talos and Modbus targets as written, and its fence if any.
pub fn lines(profiles: &Profiles) -> Vec<String> {
    if profiles.arms.is_empty() {
        return vec![format!(
            "no arm profiles in {} (no [arms.NAME] tables)",
            profiles.file.display()
        )];
    }
    // Names as shown (escaped: see `text::shown`), so the columns line up as printed.
    let names: Vec<_> = profiles.arms.iter().map(|p| text::shown(&p.name)).collect();
    let width = names.iter().map(|n| n.chars().count()).max().unwrap_or(0);
    profiles
        .arms
        .iter()
        .zip(&names)
        .map(|(profile, name)| {
            let mut targets = Vec::new();
            if let Some(talos) = profile.value("talos") {
                targets.push(format!("talos {talos}"));
            }
            if let Some(modbus) = profile.value("modbus") {
                let unit = profile
                    .value("unit")
                    .map(|u| format!(" unit {u}"))
                    .unwrap_or_default();
                targets.push(format!("modbus {modbus}{unit}"));
            }
            if targets.is_empty() {
                targets.push("the built-in simulated arm".into());
            }
            if let Some(fence) = &profile.fence {
                targets.push(fence_clause(fence));
            }
            format!("{name:<width$}  {}", targets.join("  "))
        })
        .collect()
}
