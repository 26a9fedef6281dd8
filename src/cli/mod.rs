//! Command-line front ends: argument definitions and the one-shot commands.

pub mod arms;
pub mod console;
pub mod generate;
pub mod guard;
mod hw_text;
mod leading_options;
mod man_sections;
pub mod modbus;
mod outcome;
pub mod output;
pub mod profiles;
pub mod replay;
pub mod send;
pub mod sim;
mod sim_thread;
pub mod status;
pub mod units;
pub mod values;
pub mod version;

use clap::{Parser, Subcommand};

pub use leading_options::options_after_command;
pub use outcome::Outcome;

/// armjog: jog a robot arm from the keyboard, and talk to it from a shell.
///
/// With no subcommand it opens the jog console: on the built-in simulated arm, or on the arm
/// given with --talos and/or --modbus, or by the profile --arm names.
#[derive(Debug, Parser)]
#[command(name = "armjog", version = version::VERSION, about, long_about = None, args_conflicts_with_subcommands = true, after_long_help = man_sections::files_text())]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
    #[command(flatten)]
    pub console: console::ConsoleArgs,
    #[command(flatten)]
    pub profile: profiles::ProfileArgs,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Send one Talos command to an operator and print its reply.
    Send(send::SendArgs),
    /// Print a complete snapshot of a Kinova arm over Modbus TCP.
    Status(status::StatusArgs),
    /// Write one Kinova Modbus command: quick stop, abort, fault reset, stop, home, a stored
    /// action or sequence by id, speed limit.
    Modbus(modbus::ModbusArgs),
    /// List the arm profiles of config.toml (`--arm NAME` takes one), with their targets.
    Arms(arms::ArmsArgs),
    /// Run the simulated Kinova Gen3 arm: a Talos operator and a Kinova Modbus server.
    Sim(sim::SimArgs),
    /// Play a recorded session in the console's panels (no link opened, no key moves an arm),
    /// or print its events with `--events`: keys, commands, stops, refusals, faults.
    Replay(replay::ReplayArgs),
    /// Print a shell completion script (bash, zsh or fish) to stdout.
    Completions(generate::CompletionsArgs),
    /// Print the man page (roff) to stdout: armjog(1), or a subcommand's.
    Man(generate::ManArgs),
    /// The stop guard the console starts for a real arm (internal).
    #[command(hide = true)]
    Guard(guard::GuardArgs),
}

/// Appends the default port to a bare host name.
pub fn with_default_port(addr: &str, port: u16) -> String {
    let has_port = match addr.rsplit_once(':') {
        // "[::1]:61616" or "host:61616"; a bare IPv6 address has several colons and no brackets.
        Some((host, p)) => p.parse::<u16>().is_ok() && (!host.contains(':') || host.ends_with(']')),
        None => false,
    };
    if has_port {
        addr.to_string()
    } else if addr.contains(':') && !addr.starts_with('[') {
        format!("[{addr}]:{port}")
    } else {
        format!("{addr}:{port}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_port_is_added_only_when_missing() {
        assert_eq!(with_default_port("10.0.0.2", 61616), "10.0.0.2:61616");
        assert_eq!(with_default_port("arm:8080", 61616), "arm:8080");
        assert_eq!(with_default_port("[::1]:9", 61616), "[::1]:9");
        assert_eq!(with_default_port("::1", 61616), "[::1]:61616");
    }
}
