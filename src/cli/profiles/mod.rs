//! Named arm profiles: `[arms.NAME]` tables in `config.toml` giving the console's options for one
//! arm, chosen with `--arm NAME` (or `ARMJOG_ARM`). The command line wins over the profile, the
//! profile over the defaults.

mod apply;
mod fence;
mod file;

use std::path::{Path, PathBuf};

use clap::Args;

use crate::link::fence::Fence;

pub use apply::{ArgsError, Parsed, parse_args, profile_args};
pub use file::{known_keys, load, nearest, parse};

/// Exit status of a profile that cannot be used (as for any other refused argument).
pub const EXIT_PROFILE: i32 = 2;

/// The options that choose a profile. `global`: accepted before or after any command word.
#[derive(Debug, Clone, Args)]
pub struct ProfileArgs {
    /// Take the options of this arm's profile in config.toml (options given here win).
    #[arg(long, value_name = "NAME", env = "ARMJOG_ARM", global = true)]
    pub arm: Option<String>,
    /// The profiles file (default: $XDG_CONFIG_HOME/armjog/config.toml, else
    /// ~/.config/armjog/config.toml).
    #[arg(long, value_name = "FILE", env = "ARMJOG_CONFIG", global = true)]
    pub config: Option<PathBuf>,
}

/// Where the profiles are: `--config`, `$ARMJOG_CONFIG`, else the user's configuration folder.
pub fn config_path(given: Option<&Path>) -> Option<PathBuf> {
    given
        .map(Path::to_path_buf)
        .or_else(|| dirs::config_dir().map(|d| d.join("armjog").join("config.toml")))
}

/// The first line of clap's message, without its `error: `.
fn first_line(e: &clap::Error) -> String {
    let rendered = e.to_string();
    let first = rendered.lines().next().unwrap_or_default();
    first.strip_prefix("error: ").unwrap_or(first).to_string()
}

/// A config file's profiles, in the file's order.
#[derive(Debug, Clone, PartialEq)]
pub struct Profiles {
    pub file: PathBuf,
    pub arms: Vec<Profile>,
}

/// One `[arms.NAME]` table, checked.
#[derive(Debug, Clone, PartialEq)]
pub struct Profile {
    pub name: String,
    /// The line of its `[arms.NAME]` header.
    pub line: usize,
    pub settings: Vec<Setting>,
    /// Its `[arms.NAME.fence]` table, checked; `None` when it has none.
    pub fence: Option<Fence>,
}

/// One option of a profile, as the command line would write its value.
#[derive(Debug, Clone, PartialEq)]
pub struct Setting {
    /// The option's long name with `_` for `-` (`max_jog_speed`).
    pub key: String,
    pub value: String,
    pub line: usize,
}

impl Profiles {
    /// The profile called `name`; an unknown name is refused with the nearest known one.
    pub fn get(&self, name: &str) -> Result<&Profile, ProfileError> {
        self.arms
            .iter()
            .find(|p| p.name == name)
            .ok_or_else(|| ProfileError::UnknownArm {
                path: self.file.clone(),
                name: name.to_string(),
                known: self.arms.iter().map(|p| p.name.clone()).collect(),
            })
    }
}

impl Profile {
    /// The value of the option `key` (`talos`, `max_jog_speed`), if the profile gives it.
    pub fn value(&self, key: &str) -> Option<&str> {
        self.settings
            .iter()
            .find(|s| s.key == key)
            .map(|s| s.value.as_str())
    }
}

/// Why a profile could not be used. Each names the file; those about its contents, the line.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ProfileError {
    /// No configuration folder is known (no home directory) and no `--config` was given.
    #[error("no configuration folder is known (no home directory): give --config FILE")]
    NoPlace,
    #[error("{}: no such file (arm profiles go there)", path.display())]
    NoFile { path: PathBuf },
    #[error("{}: cannot read it: {reason}", path.display())]
    Unreadable { path: PathBuf, reason: String },
    /// Bad TOML, an unknown key, a wrong type or a bad value.
    #[error("{}:{line}: {message}", path.display())]
    Invalid {
        path: PathBuf,
        line: usize,
        message: String,
    },
    #[error("{}: no arm '{name}'{}", path.display(), known_arms(name, known))]
    UnknownArm {
        path: PathBuf,
        name: String,
        known: Vec<String>,
    },
}

/// What follows an unknown arm's name: the nearest known one, else the known ones.
fn known_arms(name: &str, known: &[String]) -> String {
    match nearest(name, known) {
        Some(near) => format!("; did you mean '{near}'?"),
        None if known.is_empty() => " (the file has no [arms.NAME] tables)".into(),
        None => format!(" (arms: {})", known.join(", ")),
    }
}
