//! `armjog completions SHELL` and `armjog man`, from the clap definitions, so they never drift.

use clap::{Args, CommandFactory, ValueEnum};

use super::{Cli, Outcome, man_sections};

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
        "replay",
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
        .source(format!("armjog {}", super::version::VERSION))
        .render(&mut out)?;
    Ok(with_sections(out, &man_sections::roff()))
}

/// `page` with `sections` before VERSION (man convention), or at its end.
fn with_sections(page: Vec<u8>, sections: &str) -> Vec<u8> {
    let text = String::from_utf8_lossy(&page);
    match text.find("\n.SH VERSION") {
        Some(at) => format!("{}\n{sections}{}", &text[..at], &text[at + 1..]).into_bytes(),
        None if text.ends_with('\n') => format!("{text}{sections}").into_bytes(),
        None => format!("{text}\n{sections}").into_bytes(),
    }
}

pub fn run_completions(args: &CompletionsArgs) -> Outcome {
    Outcome::printed(text_lines(&completions(args.shell)))
}

pub fn run_man(args: &ManArgs) -> Outcome {
    match man_page(args.subcommand.as_deref()) {
        Ok(page) => Outcome::printed(text_lines(&page)),
        Err(e) => Outcome::error(format!("cannot render the man page: {e}"), 1),
    }
}

/// A generated text's lines, to be printed (each through `cli::output`).
fn text_lines(bytes: &[u8]) -> Vec<String> {
    String::from_utf8_lossy(bytes)
        .lines()
        .map(str::to_owned)
        .collect()
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

    #[test]
    fn the_pages_have_exit_status_environment_and_files_before_the_version() {
        for name in [None, Some("send")] {
            let page = String::from_utf8(man_page(name).expect("renders")).expect("utf-8");
            let at = |title: &str| {
                page.find(title)
                    .unwrap_or_else(|| panic!("{name:?} has no {title}"))
            };
            let exit = at(".SH \"EXIT STATUS\"\n");
            let env = at(".SH \"ENVIRONMENT\"\n");
            let files = at(".SH \"FILES\"\n");
            assert!(
                at(".SH OPTIONS") < exit && exit < env && env < files,
                "{page}"
            );
            if let Some(version) = page.find(".SH VERSION") {
                assert!(files < version, "{page}");
            }
            assert!(page.contains("\\fBARMJOG_LOG_DIR\\fR"), "{page}");
            assert!(page.contains("audit\\-YYYY\\-MM\\-DD.jsonl"), "{page}");
        }
    }
}
