//! Arm profiles (`config.toml`, `--arm`, `armjog arms`): the file's checks with their lines, and
//! a profile's book. Which of a flag, a profile and a default wins is in `profile_precedence.rs`,
//! the binary with `--arm` against the simulator in `profile_commands.rs`, a profile's values in
//! `profile_values.rs`. Every test names its own file (`--config` or `ARMJOG_CONFIG`): none
//! reads the real home.

use crate::armjog_run::{self, Run, run};

use std::path::{Path, PathBuf};

use armjog::cli::profiles::{self, ProfileError};

/// The issue's example profile, and a second one.
pub(crate) const GOOD: &str = r#"# the arms of the day
[arms.cell3]
talos = "192.168.1.20"        # every console option may appear, with its long name
dialect = "ack"
checksum = "xor8"
modbus = "192.168.1.10"
unit = 1
max_jog_speed = 100
operator_full_speed = 250
home_action_id = 7
keymap = "numpad"

[arms.bench]
modbus = "10.0.0.5:1502"
refresh_hz = 20.5
"#;

pub(crate) fn parse(text: &str) -> Result<profiles::Profiles, ProfileError> {
    profiles::parse(Path::new("config.toml"), text)
}

pub(crate) fn error(text: &str) -> String {
    parse(text).expect_err("refused").to_string()
}

#[test]
fn a_good_file_gives_each_arm_its_options_in_the_files_order() {
    let profiles = parse(GOOD).expect("good file");
    let names: Vec<&str> = profiles.arms.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["cell3", "bench"]);
    let cell3 = profiles.get("cell3").expect("cell3");
    assert_eq!(cell3.line, 2);
    let settings: Vec<(&str, &str, usize)> = cell3
        .settings
        .iter()
        .map(|s| (s.key.as_str(), s.value.as_str(), s.line))
        .collect();
    // The parser sorts keys; the values are as the command line would write them.
    for expected in [
        ("talos", "192.168.1.20", 3),
        ("dialect", "ack", 4),
        ("checksum", "xor8", 5),
        ("modbus", "192.168.1.10", 6),
        ("unit", "1", 7),
        ("max_jog_speed", "100", 8),
        ("operator_full_speed", "250", 9),
        ("home_action_id", "7", 10),
        ("keymap", "numpad", 11),
    ] {
        assert!(settings.contains(&expected), "{expected:?} in {settings:?}");
    }
    assert_eq!(settings.len(), 9);
    let bench = profiles.get("bench").expect("bench");
    assert_eq!(bench.value("refresh_hz"), Some("20.5"));
    assert_eq!(bench.value("talos"), None);
}

#[test]
fn every_console_option_is_a_key_under_its_long_name() {
    let keys = profiles::known_keys();
    for key in [
        "talos",
        "modbus",
        "dialect",
        "checksum",
        "unit",
        "keymap",
        "max_jog_speed",
        "operator_full_speed",
        "refresh_hz",
        "telemetry_hz",
        "key_release",
        "positions",
        "home_action_id",
    ] {
        assert!(keys.iter().any(|k| k == key), "{key} in {keys:?}");
    }
    // The profile's own options are not options of a profile.
    assert!(
        !keys.iter().any(|k| k == "arm" || k == "config"),
        "{keys:?}"
    );
}

#[test]
fn an_unknown_key_is_named_with_its_line_and_the_nearest_key() {
    assert_eq!(
        error("[arms.cell3]\ntalso = \"192.168.1.20\"\n"),
        "config.toml:2: unknown key 'talso'; did you mean 'talos'?"
    );
    // Dashes are the command line's spelling, not the file's.
    assert_eq!(
        error("[arms.cell3]\nunit = 1\n\nmax-jog-speed = 100\n"),
        "config.toml:4: unknown key 'max-jog-speed'; did you mean 'max_jog_speed'?"
    );
    // Nothing near: the keys are listed.
    let far = error("[arms.cell3]\ncolour = \"red\"\n");
    assert!(
        far.starts_with("config.toml:2: unknown key 'colour' (known: talos, modbus,"),
        "{far}"
    );
    // Outside [arms.NAME] too.
    assert_eq!(
        error("[arm.cell3]\nunit = 1\n"),
        "config.toml:1: unknown key 'arm'; did you mean 'arms'?"
    );
}

#[test]
fn a_wrong_type_is_named_with_its_line_and_what_was_expected() {
    assert_eq!(
        error("[arms.cell3]\ntalos = \"a\"\nunit = \"one\"\n"),
        "config.toml:3: unit: expected an integer, found a string"
    );
    assert_eq!(
        error("[arms.cell3]\ntalos = 192\n"),
        "config.toml:2: talos: expected a string, found an integer"
    );
    assert_eq!(
        error("[arms.cell3]\nmax_jog_speed = \"fast\"\n"),
        "config.toml:2: max_jog_speed: expected a number, found a string"
    );
    assert_eq!(
        error("[arms.cell3]\nunit = 1.5\n"),
        "config.toml:2: unit: expected an integer, found a float"
    );
    assert_eq!(
        error("arms = 3\n"),
        "config.toml:1: arms: expected a table of [arms.NAME], found an integer"
    );
    assert_eq!(
        error("[arms]\ncell3 = \"192.168.1.20\"\n"),
        "config.toml:2: arms.cell3: expected a table of options, found a string"
    );
}

#[test]
fn a_value_the_option_refuses_is_named_with_its_line() {
    assert_eq!(
        error("[arms.cell3]\ndialect = \"akc\"\n"),
        "config.toml:2: dialect: 'akc' is not one of icd, ack; did you mean 'ack'?"
    );
    assert_eq!(
        error("[arms.cell3]\nunit = 300\n"),
        "config.toml:2: unit = 300: 300 is not in 0..=255"
    );
    assert_eq!(
        error("[arms.cell3]\nhome_action_id = -1\n"),
        "config.toml:2: home_action_id = -1: -1 is outside 1 to 65535"
    );
}

#[test]
fn bad_toml_is_named_with_its_line() {
    let text = error("[arms.cell3]\ntalos = \"a\"\nunit = \n");
    assert!(
        text.starts_with("config.toml:3: not valid TOML: "),
        "{text}"
    );
    let text = error("[arms.cell3]\nunit = 1\nunit = 2\n");
    assert!(
        text.starts_with("config.toml:3: not valid TOML: "),
        "{text}"
    );
    assert!(!text.contains('\n'), "one line: {text}");
}

#[test]
fn an_unknown_arm_is_named_with_the_nearest_one() {
    let profiles = parse(GOOD).expect("good file");
    assert_eq!(
        profiles.get("cell4").expect_err("no cell4").to_string(),
        "config.toml: no arm 'cell4'; did you mean 'cell3'?"
    );
    assert_eq!(
        profiles.get("lathe").expect_err("no lathe").to_string(),
        "config.toml: no arm 'lathe' (arms: cell3, bench)"
    );
    let empty = parse("# nothing yet\n").expect("an empty file is a file");
    assert_eq!(
        empty.get("cell3").expect_err("no arms").to_string(),
        "config.toml: no arm 'cell3' (the file has no [arms.NAME] tables)"
    );
}

#[test]
fn a_missing_file_is_named() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("config.toml");
    let err = profiles::load(&path).expect_err("no file");
    assert_eq!(err, ProfileError::NoFile { path: path.clone() });
    assert!(
        err.to_string()
            .starts_with(&format!("{}: no such file", path.display())),
        "{err}"
    );
}

/// A config file in a temporary folder (kept while the guard lives).
pub(crate) fn config_file(text: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("config.toml");
    std::fs::write(&path, text).expect("write config");
    (dir, path)
}

/// `armjog args...` with the config file `config`, no `ARMJOG_ARM`, and `env`.
pub(crate) async fn armjog(config: &Path, env: &[(&str, &str)], args: &[&str]) -> Run {
    let mut command = armjog_run::command(args);
    command
        .env("ARMJOG_CONFIG", config)
        .env_remove("ARMJOG_ARM");
    for (name, value) in env {
        command.env(name, value);
    }
    run(command).await
}

#[test]
fn a_profiles_book_goes_by_its_name_whatever_address_reaches_the_arm() {
    use armjog::console::positions::{book_key, default_path};
    let by_address = book_key(Some("cell3"), "talos-192.168.1.20:61616");
    let by_host = book_key(Some("cell3"), "talos-cell3.plant:61616");
    assert_eq!(by_address, "arm-cell3");
    assert_eq!(by_host, by_address);
    assert_eq!(
        book_key(None, "talos-192.168.1.20:61616"),
        "talos-192.168.1.20:61616"
    );
    let path = default_path(&by_address).expect("a data folder");
    assert!(
        path.ends_with("positions/arm-cell3.json"),
        "{}",
        path.display()
    );
}
