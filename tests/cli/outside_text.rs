//! Text from outside (a profile's name, a path, an address, a key of config.toml, a keymap's
//! name, a book's path) never reaches the terminal as it is: every line the command line prints,
//! on stdout or stderr, goes through the one sanitiser (`text::shown`), so a control character
//! shows as its escape (`\u{1b}`) and a bidi override as `\u{202e}`.

use std::path::{Path, PathBuf};

use crate::armjog_run::{Run, armjog};

/// The profile name: an OSC title, a BEL, a colour and a right-to-left override.
const EVIL_NAME: &str = "evil\u{1b}]0;PWNED\u{7}\u{1b}[31m\u{202e}";
/// And its escapes.
const EVIL_NAME_SHOWN: &str = "evil\\u{1b}]0;PWNED\\u{7}\\u{1b}[31m\\u{202e}";
/// The address: clears the screen.
const CLEAR: &str = "\u{1b}[2J";
const CLEAR_SHOWN: &str = "\\u{1b}[2J";

/// Nothing a terminal acts on: no C0 control but the newline, no DEL, no C1, no bidi control.
fn assert_inert(run: &Run, what: &str) {
    for (stream, text) in [("stdout", &run.stdout), ("stderr", &run.stderr)] {
        let bad: Vec<char> = text
            .chars()
            .filter(|c| *c != '\n' && armjog::text::is_unsafe(*c))
            .collect();
        assert!(bad.is_empty(), "{what}: {stream} holds {bad:?}: {text:?}");
    }
}

/// `text` as a TOML basic string, every control written as `\uXXXX`.
fn toml_string(text: &str) -> String {
    let mut out = String::from("\"");
    for c in text.chars() {
        if armjog::text::is_unsafe(c) || c == '"' || c == '\\' {
            out.push_str(&format!("\\u{:04X}", u32::from(c)));
        } else {
            out.push(c);
        }
    }
    out.push('"');
    out
}

fn config_file(dir: &Path, text: &str) -> String {
    let path = dir.join("config.toml");
    std::fs::write(&path, text).expect("write config");
    path.display().to_string()
}

#[tokio::test(flavor = "multi_thread")]
async fn arms_shows_a_profiles_name_and_address_escaped() {
    let dir = tempfile::tempdir().expect("temp dir");
    let config = config_file(
        dir.path(),
        &format!(
            "[arms.{}]\nmodbus = {}\ntalos = {}\n",
            toml_string(EVIL_NAME),
            toml_string(&format!("arm{CLEAR}")),
            toml_string("op\u{202e}"),
        ),
    );
    let run = armjog(&["arms", "--config", &config]).await;
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_inert(&run, "arms");
    assert_eq!(
        run.stdout,
        format!("{EVIL_NAME_SHOWN}  talos op\\u{{202e}}  modbus arm{CLEAR_SHOWN}\n")
    );
}

#[tokio::test(flavor = "multi_thread")]
async fn a_bad_key_and_an_unknown_arm_are_named_escaped() {
    let dir = tempfile::tempdir().expect("temp dir");
    let config = config_file(
        dir.path(),
        &format!("[arms.cell]\n{} = 1\n", toml_string("bad\u{1b}[31mkey")),
    );
    for args in [
        &["arms", "--config", config.as_str()][..],
        &["status", "--config", &config, "--arm", "cell"],
        &["--config", &config, "--arm", "cell"],
    ] {
        let run = armjog(args).await;
        assert_eq!(run.code, 2, "{args:?}: {}", run.stderr);
        assert_inert(&run, "bad key");
        assert!(
            run.stderr
                .contains("config.toml:2: unknown key 'bad\\u{1b}[31mkey'"),
            "{args:?}: {}",
            run.stderr
        );
    }
    let config = config_file(dir.path(), "[arms.cell]\nunit = 1\n");
    let run = armjog(&["status", "--config", &config, "--arm", EVIL_NAME]).await;
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert_inert(&run, "unknown arm");
    assert!(
        run.stderr.contains(&format!("no arm '{EVIL_NAME_SHOWN}'")),
        "{}",
        run.stderr
    );
}

/// `status --arm`'s resolve error, and `modbus`'s and `send`'s: the address as the profile
/// wrote it, escaped.
#[tokio::test(flavor = "multi_thread")]
async fn a_profiles_address_that_does_not_resolve_is_named_escaped() {
    let dir = tempfile::tempdir().expect("temp dir");
    let address = toml_string(&format!("no-such-host{CLEAR}.invalid"));
    let config = config_file(
        dir.path(),
        &format!("[arms.cell]\nmodbus = {address}\ntalos = {address}\n"),
    );
    for args in [
        &["status", "--arm", "cell"][..],
        &["modbus", "--arm", "cell", "stop"],
        &["send", "--arm", "cell", "get-speed"],
    ] {
        let args = [&["--config", config.as_str()][..], args].concat();
        let run = armjog(&args).await;
        assert_eq!(run.code, 3, "{args:?}: {}", run.stderr);
        assert_inert(&run, "resolve");
        assert!(
            run.stderr
                .contains(&format!("no-such-host{CLEAR_SHOWN}.invalid")),
            "{args:?}: {}",
            run.stderr
        );
    }
}

/// Paths named in errors: the config file, a keymap, a positions book.
#[tokio::test(flavor = "multi_thread")]
async fn paths_and_names_in_errors_are_escaped() {
    let dir = tempfile::tempdir().expect("temp dir");
    let evil = |name: &str| -> PathBuf { dir.path().join(format!("{name}{EVIL_NAME}")) };
    let shown = |name: &str| format!("{name}{EVIL_NAME_SHOWN}");
    let missing_config = evil("config").display().to_string();
    let missing_keymap = evil("keymap.json").display().to_string();
    let book_dir = evil("book");
    std::fs::create_dir(&book_dir).expect("mkdir");
    let book_dir = book_dir.display().to_string();
    for (args, code, says) in [
        (
            vec!["arms", "--config", &missing_config],
            2,
            shown("config"),
        ),
        (
            vec!["--config", &missing_config, "--arm", "cell"],
            2,
            shown("config"),
        ),
        (vec!["--keymap", &missing_keymap], 2, shown("keymap.json")),
        (vec!["--keymap", EVIL_NAME], 2, EVIL_NAME_SHOWN.to_string()),
        (vec!["--positions", &book_dir], 1, shown("book")),
        // clap's own refusal, echoing the value (clap drops the escape sequences itself, not
        // the override).
        (vec!["--unit", EVIL_NAME], 2, "'evil\\u{202e}'".to_string()),
        (
            vec!["status", "--modbus", "op", "--timeout", EVIL_NAME],
            2,
            "'evil\\u{202e}'".to_string(),
        ),
    ] {
        let run = armjog(&args).await;
        assert_eq!(run.code, code, "{args:?}: {}", run.stderr);
        assert_inert(&run, &format!("{args:?}"));
        assert!(run.stderr.contains(&says), "{args:?}: {}", run.stderr);
    }
}

/// On a terminal clap prints a refused value as typed, colours on: every refusal is printed
/// escaped instead. `script` gives the program a terminal (util-linux, on every Debian).
#[tokio::test]
async fn a_refused_value_on_a_terminal_is_escaped() {
    if std::process::Command::new("script")
        .arg("--version")
        .output()
        .is_err()
    {
        panic!("this test needs `script` (util-linux) to give armjog a terminal");
    }
    for option in ["--max-jog-speed", "--unit"] {
        let output = tokio::process::Command::new("script")
            .args([
                "-qec",
                "\"$ARMJOG_BIN\" \"$OPTION\" \"$VALUE\"",
                "/dev/null",
            ])
            .env("ARMJOG_BIN", env!("CARGO_BIN_EXE_armjog"))
            .env("OPTION", option)
            // Escape sequences alone: clap's plain rendering drops them, so only the terminal
            // would see them.
            .env("VALUE", format!("1{CLEAR}\u{1b}]0;PWNED\u{7}"))
            // A terminal that takes colours, as a technician's does.
            .env("TERM", "xterm-256color")
            .env_remove("NO_COLOR")
            .env_remove("CLICOLOR")
            .stdin(std::process::Stdio::null())
            .output()
            .await
            .expect("script");
        let seen = String::from_utf8_lossy(&output.stdout);
        assert!(seen.contains("invalid value"), "{option}: {seen:?}");
        for raw in [CLEAR, "\u{1b}]0;PWNED"] {
            assert!(
                !seen.contains(raw),
                "{option}: {raw:?} reached the terminal: {seen:?}"
            );
        }
    }
}
