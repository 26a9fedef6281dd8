//! Options anywhere, their possible values, completions and the man page: parsed through the
//! clap definition, and a few real runs of the binary against the simulator on loopback.

use crate::armjog_run::{Run, armjog};
use armjog::cli::modbus::ModbusCommand;
use armjog::cli::send::SendCommand;
use armjog::cli::{Cli, Command};
use armjog::link::Dialect;
use armjog::sim::{SimConfig, Simulator};
use armjog::talos::Checksum;
use clap::{CommandFactory, Parser};
use serde_json::Value;

fn parse(args: &[&str]) -> Cli {
    let mut full = vec!["armjog"];
    full.extend_from_slice(args);
    Cli::try_parse_from(&full).unwrap_or_else(|e| panic!("{args:?}: {e}"))
}

/// `send` with every shared option, once before and once after the nested command.
#[test]
fn send_options_are_taken_before_or_after_the_command() {
    let options = [
        "--talos",
        "arm:4000",
        "--json",
        "--hex",
        "--timeout",
        "1234",
        "--checksum",
        "xor8",
        "--dialect",
        "ack",
    ];
    let before: Vec<&str> = ["send"]
        .into_iter()
        .chain(options)
        .chain(["polar-stop"])
        .collect();
    let after: Vec<&str> = ["send", "polar-stop"].into_iter().chain(options).collect();
    for args in [before, after] {
        let Some(Command::Send(send)) = parse(&args).command else {
            panic!("{args:?}: not send");
        };
        assert_eq!(send.talos, "arm:4000", "{args:?}");
        assert!(send.json && send.hex, "{args:?}");
        assert_eq!(send.timeout, 1234, "{args:?}");
        assert_eq!(send.checksum, Checksum::Xor8, "{args:?}");
        assert_eq!(send.dialect, Dialect::Ack, "{args:?}");
        assert!(matches!(send.command, SendCommand::PolarStop), "{args:?}");
    }
}

#[test]
fn shared_options_before_the_command_word_are_taken_too() {
    let args = [
        "armjog",
        "--talos",
        "arm:4000",
        "--json",
        "--checksum=xor8",
        "send",
        "get-speed",
        "--hex",
    ];
    let args = armjog::cli::options_after_command(args.map(Into::into).to_vec());
    let Some(Command::Send(send)) = Cli::try_parse_from(args).expect("parses").command else {
        panic!("not send");
    };
    assert_eq!(send.talos, "arm:4000");
    assert!(send.json && send.hex);
    assert_eq!(send.checksum, Checksum::Xor8);
    assert!(matches!(send.command, SendCommand::GetSpeed));
}

#[test]
fn send_options_keep_their_defaults_when_not_given() {
    let Some(Command::Send(send)) = parse(&["send", "get-speed", "--talos", "a"]).command else {
        panic!("not send");
    };
    assert_eq!(
        (
            send.checksum,
            send.dialect,
            send.timeout,
            send.json,
            send.hex
        ),
        (Checksum::Crc16, Dialect::Icd, 500, false, false)
    );
}

#[test]
fn modbus_and_status_options_are_taken_before_or_after_the_command() {
    let options = [
        "--modbus",
        "arm:1502",
        "--unit",
        "7",
        "--timeout",
        "900",
        "--json",
    ];
    let before: Vec<&str> = ["modbus"]
        .into_iter()
        .chain(options)
        .chain(["quick-stop"])
        .collect();
    let after: Vec<&str> = ["modbus", "quick-stop"]
        .into_iter()
        .chain(options)
        .collect();
    for args in [before, after] {
        let Some(Command::Modbus(modbus)) = parse(&args).command else {
            panic!("{args:?}: not modbus");
        };
        assert_eq!(modbus.arm.modbus, "arm:1502", "{args:?}");
        assert_eq!((modbus.arm.unit, modbus.arm.timeout), (7, 900), "{args:?}");
        assert!(modbus.json, "{args:?}");
        assert!(
            matches!(modbus.command, ModbusCommand::QuickStop),
            "{args:?}"
        );
    }
    let Some(Command::Status(status)) =
        parse(&["status", "--json", "--modbus", "a", "--unit", "3"]).command
    else {
        panic!("not status");
    };
    assert_eq!((status.arm.modbus.as_str(), status.arm.unit), ("a", 3));
    assert!(status.json);
}

#[test]
fn a_missing_address_is_refused_naming_the_option() {
    for args in [
        vec!["armjog", "send", "get-speed"],
        vec!["armjog", "modbus", "quick-stop"],
        vec!["armjog", "status"],
    ] {
        let err = Cli::try_parse_from(&args).expect_err("no address");
        let text = err.to_string();
        assert!(
            text.contains("talos") || text.contains("modbus"),
            "{args:?}: {text}"
        );
    }
}

#[test]
fn help_lists_the_possible_values() {
    let mut command = Cli::command();
    command.build();
    for sub in ["send", "sim"] {
        let help = command
            .find_subcommand_mut(sub)
            .expect("subcommand")
            .render_long_help()
            .to_string();
        for value in ["crc16", "xor8", "none", "icd", "ack"] {
            assert!(help.contains(value), "{sub} --help lacks {value}:\n{help}");
        }
    }
    let help = command.render_long_help().to_string();
    assert!(help.contains("xor8") && help.contains("ack"), "{help}");
    let err = Cli::try_parse_from([
        "armjog",
        "send",
        "get-speed",
        "--talos",
        "a",
        "--checksum",
        "crc32",
    ])
    .expect_err("unknown checksum");
    assert!(err.to_string().contains("xor8"), "{err}");
}

#[test]
fn completions_name_the_commands_for_every_shell() {
    use armjog::cli::generate::{Shell, completions};
    for shell in [Shell::Bash, Shell::Zsh, Shell::Fish] {
        let script = String::from_utf8(completions(shell)).expect("utf-8");
        assert!(script.contains("quick-stop"), "{shell:?}");
        assert!(script.contains("get-speed"), "{shell:?}");
        assert!(
            script.contains("xor8"),
            "{shell:?}: possible values complete"
        );
    }
}

#[test]
fn the_man_page_names_the_subcommands_and_options() {
    let page =
        String::from_utf8(armjog::cli::generate::man_page(None).expect("man")).expect("utf-8");
    assert!(
        page.starts_with(".ie") || page.contains(".TH armjog"),
        "{page}"
    );
    for sub in ["send", "status", "modbus", "sim", "completions"] {
        assert!(page.contains(sub), "armjog(1) lacks {sub}");
    }
    let send = String::from_utf8(armjog::cli::generate::man_page(Some("send")).expect("man"))
        .expect("utf-8");
    assert!(
        send.contains("armjog\\-send") || send.contains("armjog-send"),
        "{send}"
    );
    for text in ["get\\-speed", "\\-\\-talos", "xor8"] {
        assert!(send.contains(text), "armjog-send(1) lacks {text}");
    }
}

// ---- the binary itself ----

fn json(run: &Run) -> Value {
    assert_eq!(run.code, 0, "stderr: {}", run.stderr);
    serde_json::from_str(run.stdout.trim()).expect("one JSON object")
}

#[tokio::test(flavor = "multi_thread")]
async fn options_after_the_command_reach_the_simulator() {
    let sim = Simulator::start(SimConfig::ephemeral()).await.expect("sim");
    let talos = sim.talos_addr.to_string();
    let modbus = sim.modbus_addr.expect("modbus").to_string();

    let reply = json(&armjog(&["send", "get-speed", "--talos", &talos, "--json", "--hex"]).await);
    assert_eq!(reply["command"], "get_speed");
    assert!(
        reply["request_hex"].is_string(),
        "--hex after the command: {reply}"
    );

    let stop = json(&armjog(&["modbus", "quick-stop", "--modbus", &modbus, "--json"]).await);
    assert_eq!(stop["command"], "quick_stop");

    // Before the command word, as `cargo --verbose build`.
    let reset = json(&armjog(&["--json", "--modbus", &modbus, "modbus", "fault-reset"]).await);
    assert_eq!(reset["command"], "fault_reset");

    let status =
        json(&armjog(&["status", "--json", "--modbus", &modbus, "--timeout", "2000"]).await);
    assert!(status["robot_state"].is_string(), "{status}");
}

#[tokio::test(flavor = "multi_thread")]
async fn completions_and_man_print_to_stdout() {
    let bash = armjog(&["completions", "bash"]).await;
    assert_eq!(bash.code, 0, "{}", bash.stderr);
    assert!(bash.stdout.contains("quick-stop"));
    let man = armjog(&["man"]).await;
    assert_eq!(man.code, 0, "{}", man.stderr);
    assert!(man.stdout.contains(".TH"), "{}", man.stdout);
}
