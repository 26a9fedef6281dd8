//! The man page's EXIT STATUS, ENVIRONMENT and FILES sections, which clap does not know; each entry
//! states what the code does (exit codes of the commands, `logging::log_dir`,
//! `console::audit::audit_dir`, `positions::default_path`).

/// A section: its title and its (term, text) entries.
type Section = (&'static str, &'static [(&'static str, &'static str)]);

const EXIT_STATUS: Section = (
    "EXIT STATUS",
    &[
        (
            "0",
            "Success: the console quit (after stopping the arm), or a one-shot command did what it was asked.",
        ),
        (
            "1",
            "send: the operator answered with a non-zero return code (the reply is still printed). \
             status, modbus: the arm answered with a Modbus exception, or an action (home) aborted, \
             faulted, was never taken or timed out. The console or sim could not start or failed while \
             running; output could not be written.",
        ),
        (
            "2",
            "Bad arguments or configuration, refused before anything connects or is sent: a value \
             outside its range, an invalid name, a bad keymap or profile.",
        ),
        (
            "3",
            "send, status, modbus: the operator or arm could not be reached, or the link failed \
             (refused, timeout, disconnect, a corrupt or mismatched reply).",
        ),
    ],
);

const ENVIRONMENT: Section = (
    "ENVIRONMENT",
    &[
        (
            "ARMJOG_ARM",
            "The arm profile to use when --arm is not given (see FILES).",
        ),
        (
            "ARMJOG_LOG",
            "What the log files record, as a tracing filter: info (the default), debug, or per module \
             (armjog::link=debug).",
        ),
        (
            "ARMJOG_LOG_DIR",
            "The log directory, instead of $XDG_STATE_HOME/armjog (~/.local/state/armjog). Also the \
             audit directory when ARMJOG_STATE_DIR is not set.",
        ),
        (
            "ARMJOG_STATE_DIR",
            "The console's audit directory, instead of ARMJOG_LOG_DIR or ~/.local/state/armjog.",
        ),
        (
            "ARMJOG_DATA_DIR",
            "Where the positions books live (its positions/ folder), instead of \
             $XDG_DATA_HOME/armjog (~/.local/share/armjog).",
        ),
        (
            "XDG_CONFIG_HOME, XDG_STATE_HOME, XDG_DATA_HOME",
            "The base directories of the config file, the logs and audit, and the positions books.",
        ),
        (
            "NO_COLOR",
            "When set and not empty, the console draws without colour.",
        ),
    ],
);

const FILES: Section = (
    "FILES",
    &[
        (
            "$XDG_CONFIG_HOME/armjog/config.toml",
            "The arm profiles: one [arms.NAME] table each, with console options by their long names \
             and an optional [arms.NAME.fence] table (box, keep-out zones, soft joint limits) \
             (~/.config/armjog/config.toml).",
        ),
        (
            "~/.local/state/armjog/armjog-ROLE.YYYY-MM-DD.log",
            "The logs, one file per program (console, sim, cli, guard) and per UTC day; the 14 newest \
             of each are kept. Nothing is logged to the terminal.",
        ),
        (
            "~/.local/state/armjog/audit-YYYY-MM-DD.jsonl",
            "The console's audit: every technician action and what the arm and link did, one JSON \
             object per line, by UTC day. Kept: audit files are records and are never removed.",
        ),
        (
            "~/.local/state/armjog/armjog-YYYY-MM-DDTHH-MM-SSZ-ARM.mcap",
            "The flight recording of each console session (MCAP, JSON messages with JSON Schemas, \
             read by Foxglove): telemetry, keys, commands, stops and refusals, by start time and \
             arm; 14 days are kept. --no-record turns it off.",
        ),
        (
            "~/.local/share/armjog/positions/ARM.json",
            "The named positions the console remembers for each arm (simulator.json for the \
             simulated arm), written atomically.",
        ),
        (
            "FILE.json (--keymap)",
            "A keymap of one's own; the built-in default and numpad keymaps need no file.",
        ),
    ],
);

/// The FILES section as plain text, for `armjog --help`.
pub fn files_text() -> String {
    let (title, entries) = FILES;
    let mut out = format!("{title}:\n");
    for (path, text) in entries {
        out.push_str(&format!("  {path}\n      {text}\n"));
    }
    out
}

/// `text` as roff: backslashes and hyphens escaped, no line read as a request.
fn roff_text(text: &str) -> String {
    let escaped = text.replace('\\', "\\e").replace('-', "\\-");
    if escaped.starts_with(['.', '\'']) {
        format!("\\&{escaped}")
    } else {
        escaped
    }
}

/// The three sections in roff, to follow the options and subcommands.
pub fn roff() -> String {
    let mut out = String::new();
    for (title, entries) in [EXIT_STATUS, ENVIRONMENT, FILES] {
        out.push_str(&format!(".SH \"{title}\"\n"));
        for (term, text) in entries {
            out.push_str(&format!(
                ".TP\n\\fB{}\\fR\n{}\n",
                roff_text(term),
                roff_text(text)
            ));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hyphens_and_leading_dots_are_escaped() {
        assert_eq!(roff_text("--arm"), "\\-\\-arm");
        assert_eq!(roff_text(".local"), "\\&.local");
        assert_eq!(roff_text("a\\b"), "a\\eb");
    }

    #[test]
    fn every_exit_code_the_commands_use_is_listed() {
        let codes: Vec<&str> = EXIT_STATUS.1.iter().map(|(code, _)| *code).collect();
        for code in [
            0,
            super::super::send::EXIT_RETURN_CODE,
            super::super::modbus::EXIT_REFUSED,
            super::super::modbus::EXIT_LINK,
            super::super::send::EXIT_LINK,
        ] {
            assert!(codes.contains(&code.to_string().as_str()), "exit {code}");
        }
    }
}
