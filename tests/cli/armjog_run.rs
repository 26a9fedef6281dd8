//! Runs the armjog binary once and keeps what it printed.

/// What one run of the binary printed, and how it ended.
pub struct Run {
    pub code: i32,
    pub stdout: String,
    pub stderr: String,
}

/// Runs `armjog args...` with its logs in the temporary directory.
pub async fn armjog(args: &[&str]) -> Run {
    let out = tokio::process::Command::new(env!("CARGO_BIN_EXE_armjog"))
        .args(args)
        .env(
            "ARMJOG_LOG_DIR",
            std::env::temp_dir().join("armjog-test-logs"),
        )
        .output()
        .await
        .expect("run armjog");
    Run {
        code: out.status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}
