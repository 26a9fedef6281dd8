//! `armjog completions SHELL` and `armjog man`: generated from the same clap definitions that
//! parse the command line, so they never drift from it.

use clap::{Args, CommandFactory, ValueEnum};

use super::{Cli, Outcome};

/// Shells completions are generated for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Shell {
    Bash,
    Zsh,
    Fish,
}

#[derive(Debug, Args)]
pub struct CompletionsArgs {
    /// The shell to complete in.
    #[arg(value_enum)]
    pub shell: Shell,
}

/// The completion script for `shell`.
pub fn completions(shell: Shell) -> Vec<u8> {
    let mut command = Cli::command();
    let mut out = Vec::new();
    let generator = match shell {
        Shell::Bash => clap_complete::Shell::Bash,
        Shell::Zsh => clap_complete::Shell::Zsh,
        Shell::Fish => clap_complete::Shell::Fish,
    };
    clap_complete::generate(generator, &mut command, "armjog", &mut out);
    out
}

#[derive(Debug, Args)]
pub struct ManArgs {
    /// A subcommand's own page (armjog-SUBCOMMAND(1)) instead of armjog(1).
    #[arg(value_parser = documented_subcommands())]
    pub subcommand: Option<String>,
}

/// The subcommands with a page of their own: every visible one.
fn documented_subcommands() -> Vec<&'static str> {
    vec![
        "send",
        "status",
        "modbus",
        "arms",
        "sim",
        "completions",
        "man",
    ]
}

/// A man page in roff: armjog(1), or armjog-SUBCOMMAND(1).
pub fn man_page(subcommand: Option<&str>) -> std::io::Result<Vec<u8>> {
    let mut command = Cli::command();
    // Built, so options shared with nested subcommands show on their pages too.
    command.build();
    let page = match subcommand {
        None => command,
        Some(name) => {
            let Some(sub) = command.find_subcommand(name) else {
                return Err(std::io::Error::other(format!("no subcommand {name}")));
            };
            let title = format!("armjog-{name}");
            sub.clone()
                .display_name(title)
                .bin_name(format!("armjog {name}"))
        }
    };
    let mut out = Vec::new();
    clap_mangen::Man::new(page)
        .source(format!("armjog {}", env!("CARGO_PKG_VERSION")))
        .render(&mut out)?;
    Ok(out)
}

/// Runs `armjog completions`.
pub fn run_completions(args: &CompletionsArgs) -> Outcome {
    let script = completions(args.shell);
    Outcome {
        stdout: String::from_utf8_lossy(&script)
            .lines()
            .map(str::to_owned)
            .collect(),
        stderr: None,
        exit_code: 0,
    }
}

/// Runs `armjog man`.
pub fn run_man(args: &ManArgs) -> Outcome {
    match man_page(args.subcommand.as_deref()) {
        Ok(page) => Outcome {
            stdout: String::from_utf8_lossy(&page)
                .lines()
                .map(str::to_owned)
                .collect(),
            stderr: None,
            exit_code: 0,
        },
        Err(e) => Outcome {
            stdout: Vec::new(),
            stderr: Some(format!("cannot render the man page: {e}")),
            exit_code: 1,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_visible_subcommand_has_a_page() {
        let command = Cli::command();
        let visible: Vec<&str> = command
            .get_subcommands()
            .filter(|s| !s.is_hide_set())
            .map(|s| s.get_name())
            .collect();
        assert_eq!(visible, documented_subcommands());
        for name in visible {
            let page = man_page(Some(name)).expect("renders");
            let page = String::from_utf8_lossy(&page);
            assert!(
                page.contains(&format!(".TH armjog\\-{name}"))
                    || page.contains(&format!(".TH armjog-{name}")),
                "{name}: {page}"
            );
        }
    }
}
