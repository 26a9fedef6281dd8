#![forbid(unsafe_code)]

use armjog::cli::profiles::{ArgsError, EXIT_PROFILE, Parsed, parse_args};
use armjog::cli::{Command, output};

fn main() {
    // The shared options of send/status/modbus may also come before the command word.
    let args = armjog::cli::options_after_command(std::env::args_os().collect());
    // The profile `--arm` names is read and checked before anything starts.
    let Parsed { cli, arm } = match parse_args(args) {
        Ok(parsed) => parsed,
        Err(ArgsError::Clap(e)) => e.exit(),
        Err(e) => {
            output::print_error(&e.to_string());
            std::process::exit(EXIT_PROFILE);
        }
    };
    let log_guards = armjog::logging::init(log_role(cli.command.as_ref()));
    let runtime = match tokio::runtime::Runtime::new() {
        Ok(rt) => rt,
        Err(e) => {
            output::print_error(&format!("cannot start the async runtime: {e}"));
            std::process::exit(1);
        }
    };
    let code = runtime.block_on(async {
        match cli.command {
            Some(Command::Send(args)) => report(armjog::cli::send::run(&args).await),
            Some(Command::Status(args)) => report(armjog::cli::status::run(&args).await),
            Some(Command::Modbus(args)) => report(armjog::cli::modbus::run(&args).await),
            Some(Command::Arms(_)) => report(armjog::cli::arms::run(cli.profile.config.as_deref())),
            Some(Command::Sim(args)) => armjog::cli::sim::run(&args).await,
            Some(Command::Guard(args)) => armjog::cli::guard::run(&args).await,
            Some(Command::Completions(args)) => {
                report(armjog::cli::generate::run_completions(&args))
            }
            Some(Command::Man(args)) => report(armjog::cli::generate::run_man(&args)),
            None => armjog::cli::console::run_console(&cli.console, arm).await,
        }
    });
    // `exit` runs no destructors: the logs are flushed first.
    drop(log_guards);
    std::process::exit(code);
}

/// Which log file(s) this run writes.
fn log_role(command: Option<&Command>) -> armjog::logging::LogRole {
    use armjog::logging::LogRole;
    match command {
        None => LogRole::Console,
        Some(Command::Sim(_)) => LogRole::Sim,
        Some(Command::Guard(_)) => LogRole::Guard,
        Some(
            Command::Send(_)
            | Command::Status(_)
            | Command::Modbus(_)
            | Command::Arms(_)
            | Command::Completions(_)
            | Command::Man(_),
        ) => LogRole::Cli,
    }
}

/// Prints a one-shot command's output and returns its exit status.
fn report(outcome: armjog::cli::Outcome) -> i32 {
    output::report(
        &outcome.stdout,
        outcome.stderr.as_deref(),
        outcome.exit_code,
    )
}
