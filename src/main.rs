#![forbid(unsafe_code)]

use armjog::cli::profiles::{ArgsError, EXIT_PROFILE, Parsed, parse_args};
use armjog::cli::{Cli, Command, output};

/// mimalloc rather than glibc's allocator: the console at rest wakes some 250 times a second
/// (Modbus replies, reports, frames), each time with caches gone cold; with mimalloc it spends
/// 7-23 % less CPU there than with glibc's (`benches/idle_ab.py`, both side by side). Its
/// transparent huge pages are left off: with them it saved 15-41 %, but the console's resident
/// memory went from 18 to 30-32 MB.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() {
    // The shared options of send/status/modbus may also come before the command word.
    let args = armjog::cli::options_after_command(std::env::args_os().collect());
    // The profile `--arm` names is read and checked before anything starts.
    let Parsed { cli, arm } = match parse_args(args) {
        Ok(parsed) => parsed,
        Err(ArgsError::Clap(e)) => exit_clap(e),
        Err(e) => {
            output::print_error(&e.to_string());
            std::process::exit(EXIT_PROFILE);
        }
    };
    let log_guards = armjog::logging::init(log_role(cli.command.as_ref()));
    // One thread carries the key path: the tty is read, the app decides, the driver and the
    // links write, all as tasks of this runtime, so a key becomes a frame on the socket without
    // waking another thread (a reader thread and a multi-threaded runtime handed it across up
    // to three). Drawing, the audit log and the built-in simulator have threads of their own.
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
        // Run as a task, not in place: a panic in it ends at the task's edge and the runtime
        // goes on, so the driver still carries the STOP the console's panic hook asked for
        // while the hook's own thread ends the process.
        match tokio::spawn(run(cli, arm)).await {
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

/// Ends the process with clap's message (`--help`, `--version`, a refused argument). A refusal
/// may echo a value with a control or bidi character in it (a path, an address): it is printed
/// escaped, as every other message is (`output`), without clap's colours; help and the version
/// as clap prints them.
fn exit_clap(e: clap::Error) -> ! {
    // Every refusal is printed as plain text, escaped: on a terminal clap would print the
    // value as typed, escape sequences and all (its plain rendering drops them).
    if e.use_stderr() {
        output::print_error_lines(&e.to_string());
        std::process::exit(e.exit_code());
    }
    e.exit()
}

/// How long the runtime goes on after a command panicked: the console's panic hook ends the
/// process sooner (see `console::run`), once the stop it asked for has gone out.
const PANIC_GRACE: std::time::Duration = std::time::Duration::from_secs(1);

async fn run(cli: Cli, arm: Option<String>) -> i32 {
    match cli.command {
        Some(Command::Send(args)) => report(armjog::cli::send::run(&args).await),
        Some(Command::Status(args)) => report(armjog::cli::status::run(&args).await),
        Some(Command::Modbus(args)) => report(armjog::cli::modbus::run(&args).await),
        Some(Command::Arms(_)) => report(armjog::cli::arms::run(cli.profile.config.as_deref())),
        Some(Command::Sim(args)) => armjog::cli::sim::run(&args).await,
        Some(Command::Guard(args)) => armjog::cli::guard::run(&args).await,
        Some(Command::Completions(args)) => report(armjog::cli::generate::run_completions(&args)),
        Some(Command::Man(args)) => report(armjog::cli::generate::run_man(&args)),
        None => armjog::cli::console::run_console(&cli.console, arm).await,
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
