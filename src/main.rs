#![forbid(unsafe_code)]

use armjog::cli::profiles::{ArgsError, EXIT_PROFILE, Parsed, parse_args};
use armjog::cli::{Cli, Command, output};
use armjog::link::fence::Fence;

/// mimalloc: less CPU at rest than glibc's allocator (figures in docs/development.md).
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() {
    // The shared options of send/status/modbus may also come before the command word.
    let args = armjog::cli::options_after_command(std::env::args_os().collect());
    // The profile `--arm` names is read and checked before anything starts.
    let Parsed { cli, arm, fence } = match parse_args(args) {
        Ok(parsed) => parsed,
        Err(ArgsError::Clap(e)) => exit_clap(e),
        Err(e) => {
            output::print_error(&e.to_string());
            std::process::exit(EXIT_PROFILE);
        }
    };
    let log_guards = armjog::logging::init(log_role(cli.command.as_ref()));
    // One thread carries the key path (tty read, app, driver, links): a key becomes a frame
    // without waking another thread. Drawing, audit and the simulator have threads of their own.
    let runtime = match tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
    {
        Ok(rt) => rt,
        Err(e) => {
            output::print_error(&format!("cannot start the async runtime: {e}"));
            std::process::exit(1);
        }
    };
    let code = runtime.block_on(async {
        // A task: a panic ends at its edge and the runtime still carries the panic hook's STOP.
        match tokio::spawn(run(cli, arm, fence)).await {
            Ok(code) => code,
            Err(e) if e.is_panic() => {
                tokio::time::sleep(PANIC_GRACE).await;
                101
            }
            Err(_) => 1,
        }
    });
    // `exit` runs no destructors: the logs are flushed first.
    drop(log_guards);
    std::process::exit(code);
}

/// Ends the process with clap's message. A refusal is printed escaped (`output`): it may echo a
/// value with control or bidi characters; help and the version as clap prints them.
fn exit_clap(e: clap::Error) -> ! {
    if e.use_stderr() {
        output::print_error_lines(&e.to_string());
        std::process::exit(e.exit_code());
    }
    e.exit()
}

/// How long the runtime goes on after a command panicked: the console's panic hook ends the
/// process sooner (see `console::run`), once the stop it asked for has gone out.
const PANIC_GRACE: std::time::Duration = std::time::Duration::from_secs(1);

async fn run(cli: Cli, arm: Option<String>, fence: Option<Fence>) -> i32 {
    match cli.command {
        Some(Command::Send(args)) => report(armjog::cli::send::run(&args).await),
        Some(Command::Status(args)) => report(armjog::cli::status::run(&args).await),
        Some(Command::Modbus(args)) => report(armjog::cli::modbus::run(&args).await),
        Some(Command::Arms(_)) => report(armjog::cli::arms::run(cli.profile.config.as_deref())),
        Some(Command::Sim(args)) => armjog::cli::sim::run(&args).await,
        Some(Command::Replay(args)) => report(armjog::cli::replay::run(&args).await),
        Some(Command::Guard(args)) => armjog::cli::guard::run(&args).await,
        Some(Command::Completions(args)) => report(armjog::cli::generate::run_completions(&args)),
        Some(Command::Man(args)) => report(armjog::cli::generate::run_man(&args)),
        None => {
            let config_file = armjog::cli::profiles::config_path(cli.profile.config.as_deref());
            armjog::cli::console::run_console(&cli.console, arm, fence, config_file).await
        }
    }
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
            | Command::Replay(_)
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
