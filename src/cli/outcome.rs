//! What a one-shot command (`send`, `status`, `modbus`) prints and how it exits.

/// A one-shot command's output lines, its error line and its exit status.
pub struct Outcome {
    pub stdout: Vec<String>,
    pub stderr: Option<String>,
    pub exit_code: i32,
}

impl Outcome {
    /// `stdout` printed, exit 0.
    pub fn printed(stdout: Vec<String>) -> Outcome {
        Outcome {
            stdout,
            stderr: None,
            exit_code: 0,
        }
    }

    /// Nothing printed, `message` on stderr, exit `exit_code`.
    pub fn error(message: String, exit_code: i32) -> Outcome {
        Outcome {
            stdout: Vec::new(),
            stderr: Some(message),
            exit_code,
        }
    }
}
