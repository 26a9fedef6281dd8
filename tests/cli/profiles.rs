//! Arm profiles (`config.toml`, `--arm`, `armjog arms`): the file's checks with their lines,
//! which of a flag, a profile and a default wins, and `--arm` end to end against the simulator.
//! Every test names its own file (`--config` or `ARMJOG_CONFIG`): none reads the real home.

use crate::armjog_run::{self, Run, run};

use std::ffi::OsString;
use std::path::{Path, PathBuf};

use armjog::cli::Command;
use armjog::cli::modbus::ModbusCommand;
use armjog::cli::profiles::{self, ArgsError, Parsed, ProfileError};
use armjog::link::Dialect;
use armjog::sim::{SimConfig, Simulator};
use armjog::talos::Checksum;

/// The issue's example profile, and a second one.
const GOOD: &str = r#"# the arms of the day
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

// ---- precedence: the command line, the profile, the defaults ----

/// A config file in a temporary folder (kept while the guard lives).
pub(crate) fn config_file(text: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("config.toml");
    std::fs::write(&path, text).expect("write config");
    (dir, path)
}

fn parsed(config: &Path, args: &[&str]) -> Result<Parsed, ArgsError> {
    let mut all: Vec<OsString> = vec!["armjog".into(), "--config".into(), config.into()];
    all.extend(args.iter().map(OsString::from));
    // As main reads them: the shared options may come before the command word.
    profiles::parse_args(armjog::cli::options_after_command(all))
}

#[test]
fn the_profile_beats_the_defaults_and_a_flag_beats_the_profile() {
    let (_dir, config) = config_file(GOOD);
    let Parsed { cli, arm } = parsed(&config, &["--arm", "cell3"]).expect("parses");
    assert_eq!(arm.as_deref(), Some("cell3"));
    let c = &cli.console;
    assert_eq!(c.talos.as_deref(), Some("192.168.1.20"));
    assert_eq!(c.modbus.as_deref(), Some("192.168.1.10"));
    assert_eq!(c.dialect, Dialect::Ack);
    assert_eq!(c.checksum, Checksum::Xor8);
    assert_eq!(c.max_jog_speed, 100.0);
    assert_eq!(c.home_action_id, 7);
    assert_eq!(c.keymap, "numpad");
    // Not in the profile: the default.
    assert_eq!(c.refresh_hz, 10.0);

    // Typed values win, also one equal to the default (a default must not hide the profile,
    // and a typed default must not lose to it).
    let Parsed { cli, .. } = parsed(
        &config,
        &[
            "--arm",
            "cell3",
            "--max-jog-speed",
            "250",
            "--talos",
            "op:61616",
            "--dialect=icd",
        ],
    )
    .expect("parses");
    let c = &cli.console;
    assert_eq!(c.max_jog_speed, 250.0);
    assert_eq!(c.talos.as_deref(), Some("op:61616"));
    assert_eq!(c.dialect, Dialect::Icd);
    assert_eq!(
        c.checksum,
        Checksum::Xor8,
        "the rest still from the profile"
    );
}

#[test]
fn the_one_shot_commands_take_the_options_they_have() {
    let (_dir, config) = config_file(GOOD);
    let Parsed { cli, arm } = parsed(&config, &["status", "--arm", "cell3"]).expect("parses");
    assert_eq!(arm.as_deref(), Some("cell3"));
    let Some(Command::Status(status)) = cli.command else {
        panic!("status");
    };
    assert_eq!(status.arm.modbus, "192.168.1.10");
    assert_eq!(status.arm.unit, 1);

    // Before the command word, and a flag over the profile.
    let Parsed { cli, .. } = parsed(
        &config,
        &["--arm", "cell3", "modbus", "--unit", "3", "home"],
    )
    .expect("parses");
    let Some(Command::Modbus(modbus)) = cli.command else {
        panic!("modbus");
    };
    assert_eq!(modbus.arm.modbus, "192.168.1.10");
    assert_eq!(modbus.arm.unit, 3);
    let ModbusCommand::Home { action_id, .. } = modbus.command else {
        panic!("home");
    };
    assert_eq!(action_id, 7, "home takes the profile's home_action_id");

    let Parsed { cli, .. } =
        parsed(&config, &["send", "get-speed", "--arm", "cell3"]).expect("parses");
    let Some(Command::Send(send)) = cli.command else {
        panic!("send");
    };
    assert_eq!(send.talos, "192.168.1.20");
    assert_eq!(send.checksum, Checksum::Xor8);
    assert_eq!(send.dialect, Dialect::Ack);
}

#[test]
fn a_profile_without_what_the_command_needs_says_so() {
    let (_dir, config) = config_file(GOOD);
    let err = parsed(&config, &["send", "get-speed", "--arm", "bench"]).expect_err("no talos");
    let text = err.to_string();
    assert!(text.contains("talos"), "{text}");
    assert!(text.contains("the profile 'bench'"), "{text}");
}

#[test]
fn without_arm_the_file_is_not_read_and_arm_is_refused_where_it_means_nothing() {
    let missing = Path::new("/nonexistent/armjog/config.toml");
    let Parsed { cli, arm } = parsed(missing, &["--talos", "op"]).expect("no profile named");
    assert_eq!(arm, None);
    assert_eq!(cli.console.talos.as_deref(), Some("op"));
    let err = parsed(missing, &["--arm", "cell3"]).expect_err("missing file");
    assert!(
        matches!(err, ArgsError::Profile(ProfileError::NoFile { .. })),
        "{err}"
    );
    let sim = ["armjog", "sim", "--arm", "cell3"]
        .map(OsString::from)
        .to_vec();
    let err = profiles::parse_args(sim).expect_err("sim takes no profile");
    assert!(matches!(err, ArgsError::NotForThisCommand(_)), "{err}");
}

// ---- the binary ----

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

/// `armjog args...` with the default config file in `config_home` (`$XDG_CONFIG_HOME`).
async fn default_config_armjog(config_home: &Path, args: &[&str]) -> Run {
    let mut command = armjog_run::command(args);
    command
        .env_remove("ARMJOG_CONFIG")
        .env_remove("ARMJOG_ARM")
        .env("XDG_CONFIG_HOME", config_home);
    run(command).await
}

/// A profile `sim1` on the simulator, with a Home action id it does not have.
fn sim_profile(sim: &Simulator) -> String {
    let modbus = sim.modbus_addr.expect("modbus");
    format!(
        "[arms.sim1]\ntalos = \"{}\"\nmodbus = \"{modbus}\"\nhome_action_id = 9\n",
        sim.talos_addr
    )
}

#[tokio::test(flavor = "multi_thread")]
async fn status_and_modbus_reach_the_simulator_by_its_profile() {
    let sim = Simulator::start(SimConfig::ephemeral()).await.expect("sim");
    let (_dir, config) = config_file(&sim_profile(&sim));

    let status = armjog(&config, &[], &["status", "--arm", "sim1", "--json"]).await;
    assert_eq!(status.code, 0, "{}", status.stderr);
    let json: serde_json::Value = serde_json::from_str(status.stdout.trim()).expect("JSON");
    assert!(json["robot_state"].is_string(), "{json}");

    // ARMJOG_ARM names it as --arm does.
    let status = armjog(&config, &[("ARMJOG_ARM", "sim1")], &["status"]).await;
    assert_eq!(status.code, 0, "{}", status.stderr);
    assert!(status.stdout.contains("robot state"), "{}", status.stdout);

    // The profile's Home action id reaches the arm: the simulator has no action 9.
    let home = armjog(&config, &[], &["modbus", "--arm", "sim1", "home"]).await;
    assert_eq!(home.code, 1, "{} / {}", home.stdout, home.stderr);
    assert!(home.stderr.contains("action 9"), "{}", home.stderr);
    // And a flag wins over it: the simulator's Home is 2.
    let home = armjog(
        &config,
        &[],
        &["--arm", "sim1", "modbus", "home", "--action-id", "2"],
    )
    .await;
    assert_eq!(home.code, 0, "{} / {}", home.stdout, home.stderr);
    assert!(home.stdout.contains("home: completed"), "{}", home.stdout);

    let send = armjog(
        &config,
        &[],
        &["send", "get-speed", "--arm", "sim1", "--json"],
    )
    .await;
    assert_eq!(send.code, 0, "{}", send.stderr);
    assert!(send.stdout.contains("get_speed"), "{}", send.stdout);
}

#[tokio::test(flavor = "multi_thread")]
async fn a_bad_profile_is_refused_before_anything_connects() {
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0")
        .await
        .expect("bind");
    let addr = listener.local_addr().expect("addr");
    let (_dir, config) = config_file(&format!("[arms.cell3]\nmodbus = \"{addr}\"\nunti = 1\n"));
    let run = armjog(&config, &[], &["status", "--arm", "cell3"]).await;
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert_eq!(
        run.stderr.trim(),
        format!(
            "armjog: {}:3: unknown key 'unti'; did you mean 'unit'?",
            config.display()
        )
    );
    let unknown = armjog(&config, &[], &["--arm", "cell4"]).await;
    assert_eq!(unknown.code, 2, "{}", unknown.stderr);
    // No connection was made.
    let accepted =
        tokio::time::timeout(std::time::Duration::from_millis(200), listener.accept()).await;
    assert!(accepted.is_err(), "something connected");

    let missing = config.with_file_name("missing.toml");
    let run = armjog(&missing, &[], &["--arm", "cell3"]).await;
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(
        run.stderr.contains("missing.toml: no such file"),
        "{}",
        run.stderr
    );
}

#[tokio::test(flavor = "multi_thread")]
async fn arms_lists_the_profiles_with_their_targets() {
    let (_dir, config) = config_file(GOOD);
    let run = armjog(&config, &[], &["arms"]).await;
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(
        run.stdout,
        "cell3  talos 192.168.1.20  modbus 192.168.1.10 unit 1\n\
         bench  modbus 10.0.0.5:1502\n"
    );
    // --config before the command word, and a file with no arm in it.
    let (_dir, empty) = config_file("[arms.sim]\n");
    let run = armjog(
        &config,
        &[],
        &["--config", &empty.display().to_string(), "arms"],
    )
    .await;
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(run.stdout, "sim  the built-in simulated arm\n");

    // A file named (ARMJOG_CONFIG, --config) that is not there is refused, naming it.
    let missing = config.with_file_name("missing.toml");
    let run = armjog(&missing, &[], &["arms"]).await;
    assert_eq!(run.code, 2, "{}{}", run.stdout, run.stderr);
    assert_eq!(
        run.stderr,
        format!(
            "armjog: {}: no such file (arm profiles go there)\n",
            missing.display()
        )
    );
    let run = armjog(
        &config,
        &[],
        &["arms", "--config", "/nonexistent/armjog/config.toml"],
    )
    .await;
    assert_eq!(run.code, 2, "{}{}", run.stdout, run.stderr);
    assert!(
        run.stderr
            .contains("/nonexistent/armjog/config.toml: no such file"),
        "{}",
        run.stderr
    );
    // The default file not there: no profiles yet, which is fine.
    let home = tempfile::tempdir().expect("temp dir");
    let default = home.path().join("armjog").join("config.toml");
    let run = default_config_armjog(home.path(), &["arms"]).await;
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(
        run.stdout.starts_with(&format!(
            "no arm profiles: {} does not exist",
            default.display()
        )),
        "{}",
        run.stdout
    );

    let (_dir, bad) = config_file("[arms.cell3]\ntalso = \"x\"\n");
    let run = armjog(&bad, &[], &["arms"]).await;
    assert_eq!(run.code, 2);
    assert!(
        run.stderr.contains("config.toml:2: unknown key 'talso'"),
        "{}",
        run.stderr
    );
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
