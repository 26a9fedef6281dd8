//! A profile's options are added as if typed unless given (a flag beats it, it beats defaults).

use std::ffi::OsString;

use clap::parser::ValueSource;
use clap::{ArgMatches, Command, CommandFactory, FromArgMatches, Parser};

use super::{Profile, ProfileError, config_path, first_line, load};
use crate::cli::Cli;
use crate::link::fence::Fence;

/// The commands a profile applies to (`None`: the console).
const TAKE_PROFILES: [Option<&str>; 4] = [None, Some("send"), Some("status"), Some("modbus")];

/// Profile keys a command calls by another name: (command, key, its long option there).
const RENAMED: [(&str, &str, &str); 1] = [("home", "home_action_id", "action-id")];

/// The command line read, with the profile it named applied.
#[derive(Debug)]
pub struct Parsed {
    pub cli: Cli,
    /// The profile applied, if any.
    pub arm: Option<String>,
    /// That profile's fence, checked, if it has one.
    pub fence: Option<Fence>,
}

/// Why the command line cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum ArgsError {
    /// clap's own (also `--help` and `--version`): `exit()` prints it.
    #[error(transparent)]
    Clap(#[from] clap::Error),
    #[error(transparent)]
    Profile(#[from] ProfileError),
    /// `--arm` typed for a command that takes no profile.
    #[error("--arm: `{0}` takes no arm profile (the console, send, status and modbus do)")]
    NotForThisCommand(String),
    /// Neither the command line nor the profile gives an option the command needs.
    #[error("{0}")]
    Incomplete(String),
}

/// Reads `args` and applies the profile `--arm` or `ARMJOG_ARM` names, checked whole first.
pub fn parse_args(args: Vec<OsString>) -> Result<Parsed, ArgsError> {
    let mut command = Cli::command();
    command.build();
    let matches = command.clone().try_get_matches_from(&args)?;
    let (path, leaf_matches, leaf_command) = leaf(&matches, &command);
    let from_line = leaf_matches.value_source("arm") == Some(ValueSource::CommandLine);
    let arm = leaf_matches.get_one::<String>("arm").cloned();
    let takes_profiles = TAKE_PROFILES.contains(&path.first().copied());
    let Some(arm) = arm.filter(|_| takes_profiles) else {
        if from_line && !takes_profiles {
            return Err(ArgsError::NotForThisCommand(path.join(" ")));
        }
        return Ok(Parsed {
            cli: Cli::from_arg_matches(&matches)?,
            arm: None,
            fence: None,
        });
    };
    let given = leaf_matches.get_one::<std::path::PathBuf>("config");
    let file = config_path(given.map(|p| p.as_path())).ok_or(ProfileError::NoPlace)?;
    let profiles = load(&file)?;
    let profile = profiles.get(&arm)?;
    let mut full = args;
    let added = profile_args(profile, path.last().copied(), leaf_matches, leaf_command);
    // Before a `--`, which would make them positional.
    let at = full.iter().position(|a| a == "--").unwrap_or(full.len());
    full.splice(at..at, added);
    match Cli::try_parse_from(full) {
        Ok(cli) => Ok(Parsed {
            cli,
            arm: Some(arm),
            fence: profile.fence.clone(),
        }),
        Err(e) if e.kind() == clap::error::ErrorKind::MissingRequiredArgument => {
            Err(ArgsError::Incomplete(format!(
                "{}: neither the command line nor the profile '{arm}' in {} gives it",
                first_line(&e),
                file.display()
            )))
        }
        Err(e) => Err(e.into()),
    }
}

/// The innermost command named: its path of names, its matches and its definition.
fn leaf<'a>(
    matches: &'a ArgMatches,
    command: &'a Command,
) -> (Vec<&'a str>, &'a ArgMatches, &'a Command) {
    let mut path = Vec::new();
    let (mut m, mut c) = (matches, command);
    while let Some((name, sub_matches)) = m.subcommand() {
        let Some(sub_command) = c.find_subcommand(name) else {
            break;
        };
        path.push(name);
        (m, c) = (sub_matches, sub_command);
    }
    (path, m, c)
}

/// The profile's options the command takes and its command line does not give, as arguments.
pub fn profile_args(
    profile: &Profile,
    command_name: Option<&str>,
    matches: &ArgMatches,
    command: &Command,
) -> Vec<OsString> {
    let mut args = Vec::new();
    for setting in &profile.settings {
        let long = RENAMED
            .iter()
            .find(|(c, key, _)| Some(*c) == command_name && *key == setting.key)
            .map_or_else(
                || setting.key.replace('_', "-"),
                |(_, _, long)| long.to_string(),
            );
        let Some(arg) = command
            .get_arguments()
            .find(|a| a.get_long() == Some(long.as_str()))
        else {
            // An option of the console this command does not have (`keymap` for `status`).
            continue;
        };
        if matches.value_source(arg.get_id().as_str()) == Some(ValueSource::CommandLine) {
            continue;
        }
        if arg.get_action().takes_values() {
            args.push(OsString::from(format!("--{long}={}", setting.value)));
        } else if setting.value == "true" {
            args.push(OsString::from(format!("--{long}")));
        }
    }
    args
}
