//! Which of a flag, a profile and a default wins, as `armjog`'s arguments are parsed; what each
//! one-shot command takes from a profile, and `--arm` refused where it means nothing.

use std::ffi::OsString;
use std::path::Path;

use armjog::cli::Command;
use armjog::cli::modbus::ModbusCommand;
use armjog::cli::profiles::{self, ArgsError, Parsed, ProfileError};
use armjog::link::Dialect;
use armjog::talos::Checksum;

use crate::profiles::{GOOD, config_file};

fn parsed(config: &Path, args: &[&str]) -> Result<Parsed, ArgsError> {
    let mut all: Vec<OsString> = vec!["armjog".into(), "--config".into(), config.into()];
    all.extend(args.iter().map(OsString::from));
    // As main reads them: the shared options may come before the command word.
    profiles::parse_args(armjog::cli::options_after_command(all))
}

#[test]
fn the_profile_beats_the_defaults_and_a_flag_beats_the_profile() {
    let (_dir, config) = config_file(GOOD);
    let Parsed { cli, arm, .. } = parsed(&config, &["--arm", "cell3"]).expect("parses");
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
    let Parsed { cli, arm, .. } = parsed(&config, &["status", "--arm", "cell3"]).expect("parses");
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
    let Parsed { cli, arm, .. } = parsed(missing, &["--talos", "op"]).expect("no profile named");
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
