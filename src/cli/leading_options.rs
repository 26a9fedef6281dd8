//! Shared options also before the command word, as `cargo --verbose build` takes them.

use std::ffi::OsString;

/// Commands whose shared options may come before their name.
const COMMANDS: [&str; 4] = ["send", "status", "modbus", "arms"];
/// Shared options that take a value.
const WITH_VALUE: [&str; 8] = [
    "--arm",
    "--config",
    "--talos",
    "--modbus",
    "--unit",
    "--timeout",
    "--checksum",
    "--dialect",
];
/// Shared options without one.
const FLAGS: [&str; 2] = ["--json", "--hex"];

/// Moves shared options before `send`, `status` or `modbus` to after it; else clap judges.
pub fn options_after_command(args: Vec<OsString>) -> Vec<OsString> {
    let mut shared = Vec::new();
    let mut i = 1;
    while let Some(arg) = args.get(i).and_then(|a| a.to_str()) {
        let name = arg.split_once('=').map_or(arg, |(name, _)| name);
        if FLAGS.contains(&arg) || (WITH_VALUE.contains(&name) && arg.contains('=')) {
            i += 1;
        } else if WITH_VALUE.contains(&arg) && i + 1 < args.len() {
            i += 2;
        } else {
            break;
        }
        shared.push(i);
    }
    let command_at = shared.last().copied().unwrap_or(1);
    let is_command = args
        .get(command_at)
        .and_then(|a| a.to_str())
        .is_some_and(|a| COMMANDS.contains(&a));
    if shared.is_empty() || !is_command {
        return args;
    }
    let mut out = Vec::with_capacity(args.len());
    out.push(args[0].clone());
    out.push(args[command_at].clone());
    out.extend_from_slice(&args[1..command_at]);
    out.extend_from_slice(&args[command_at + 1..]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn moved(args: &str) -> String {
        let args = args.split(' ').map(OsString::from).collect();
        options_after_command(args)
            .iter()
            .map(|a| a.to_string_lossy().into_owned())
            .collect::<Vec<_>>()
            .join(" ")
    }

    #[test]
    fn shared_options_before_the_command_move_after_it() {
        assert_eq!(
            moved("armjog --talos a:1 --json send get-speed"),
            "armjog send --talos a:1 --json get-speed"
        );
        assert_eq!(
            moved("armjog --modbus=a --unit 3 modbus quick-stop"),
            "armjog modbus --modbus=a --unit 3 quick-stop"
        );
        assert_eq!(
            moved("armjog --json status --modbus a"),
            "armjog status --json --modbus a"
        );
        assert_eq!(
            moved("armjog --arm cell3 modbus home"),
            "armjog modbus --arm cell3 home"
        );
        assert_eq!(
            moved("armjog --config c.toml arms"),
            "armjog arms --config c.toml"
        );
    }

    #[test]
    fn anything_else_is_left_alone() {
        for args in [
            "armjog send --talos a get-speed",
            "armjog --talos a:1",
            "armjog --talos a:1 --keymap numpad",
            "armjog --keymap numpad send get-speed",
            "armjog --talos send",
            "armjog --checksum xor8 sim",
        ] {
            assert_eq!(moved(args), args);
        }
    }
}
