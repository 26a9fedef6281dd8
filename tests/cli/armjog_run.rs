//! Runs the armjog binary once and keeps what it printed.

/// What one run of the binary printed, and how it ended.
pub struct Run {
    pub code: i32,
    pub stdout: String,
    pub stderr: String,
}

/// `armjog args...` with its logs in the temporary directory, not started yet.
pub fn command(args: &[&str]) -> tokio::process::Command {
    let mut command = tokio::process::Command::new(env!("CARGO_BIN_EXE_armjog"));
    command.args(args).env(
        "ARMJOG_LOG_DIR",
        std::env::temp_dir().join("armjog-test-logs"),
    );
    command
}

/// Runs `command` to its end.
pub async fn run(mut command: tokio::process::Command) -> Run {
    let out = command.output().await.expect("run armjog");
    Run {
        code: out.status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

/// Runs `armjog args...` with its logs in the temporary directory.
pub async fn armjog(args: &[&str]) -> Run {
    run(command(args)).await
}
